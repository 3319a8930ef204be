// libFuzzer target: every configuration file reader over arbitrary bytes. A reader may reject
// its input (FormatError, SpecError), but must not crash, hang, leak or throw anything else.
// The first byte picks the reader; the rest is the file. tools/fuzz.sh builds and runs it.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "gaitlab/xml.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
    try {
        switch (data[0] % 4) {
            case 0:
                gaitlab::format_robot(gaitlab::parse_robot(text, "fuzz.xml"));
                break;
            case 1:
                gaitlab::format_actuation(gaitlab::parse_actuation(text, "fuzz.xml"));
                break;
            case 2:
                gaitlab::format_environment(gaitlab::parse_environment(text, "fuzz.xml"));
                break;
            default:
                gaitlab::parse_simulation(text, "fuzz.xml");
                break;
        }
    } catch (const gaitlab::FormatError&) {
        // rejected with a message: the expected outcome for most inputs
    } catch (const gaitlab::SpecError&) {
        // a spec the reader accepted but the writer's check refused: a reader bug
        std::abort();
    }
    return 0;
}
