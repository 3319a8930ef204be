// libFuzzer target: every configuration file reader over arbitrary bytes. A reader may reject
// its input (FormatError, SpecError), but must not crash, hang, leak or throw anything else.
// The first byte picks the reader; the rest is the file. tools/fuzz.sh builds and runs it.
// A robot the URDF importer accepts must also survive its own export: the file format_urdf
// writes for it imports again, or the writer and the reader disagree. A rejection's message,
// as the terminal gets it, holds no control characters.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "gaitlab/terminal.h"
#include "gaitlab/urdf.h"
#include "gaitlab/xml.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
    try {
        switch (data[0] % 5) {
            case 0:
                gaitlab::format_robot(gaitlab::parse_robot(text, "fuzz.xml"));
                break;
            case 1:
                gaitlab::format_actuation(gaitlab::parse_actuation(text, "fuzz.xml"));
                break;
            case 2:
                gaitlab::format_environment(gaitlab::parse_environment(text, "fuzz.xml"));
                break;
            case 3:
                gaitlab::parse_simulation(text, "fuzz.xml");
                break;
            default: {
                // the byte's next choice: the links' inertias as given, or from their shapes
                gaitlab::UrdfImport how;
                how.inertia_from_shapes = data[0] / 5 % 2 == 1;
                const gaitlab::RobotSpec robot = gaitlab::parse_urdf(text, "fuzz.urdf", how);
                const std::string exported = gaitlab::format_urdf(robot);
                try {
                    gaitlab::parse_urdf(exported, "exported.urdf");
                } catch (...) {
                    std::abort();  // gaitlab wrote a URDF file it refuses to read
                }
                break;
            }
        }
    } catch (const gaitlab::FormatError& e) {
        // rejected with a message: the expected outcome for most inputs. Whatever bytes of
        // the file it quotes, what reaches the terminal holds none a terminal acts on:
        // terminal_text leaves its own output as it is
        const std::string shown = gaitlab::terminal_text(e.what());
        if (gaitlab::terminal_text(shown) != shown) std::abort();
    } catch (const gaitlab::SpecError&) {
        // a spec the reader accepted but the writer's check refused: a reader bug
        std::abort();
    }
    return 0;
}
