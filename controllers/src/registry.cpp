#include "gaitlab/controllers/registry.h"

#include "gaitlab/controllers/distributed.h"
#include "gaitlab/controllers/hindmarsh_rose.h"
#include "gaitlab/controllers/hopf.h"
#include "gaitlab/controllers/matsuoka.h"
#include "gaitlab/controllers/offset.h"
#include "gaitlab/controllers/phase_chain.h"
#include "gaitlab/controllers/sine.h"

namespace gaitlab::controllers {

namespace {

struct Entry {
    const char* name;
    std::unique_ptr<Controller> (*make)();
};

// every built-in controller, sorted by name
const Entry kBuiltins[] = {
    {"distributed", [] { return std::unique_ptr<Controller>(new Distributed()); }},
    {"hindmarsh_rose", [] { return std::unique_ptr<Controller>(new HindmarshRose()); }},
    {"hopf", [] { return std::unique_ptr<Controller>(new Hopf()); }},
    {"matsuoka", [] { return std::unique_ptr<Controller>(new Matsuoka()); }},
    {"offset", [] { return std::unique_ptr<Controller>(new Offset()); }},
    {"phase_chain", [] { return std::unique_ptr<Controller>(new PhaseChain()); }},
    {"sine", [] { return std::unique_ptr<Controller>(new Sine()); }},
};

}  // namespace

std::vector<std::string> builtin_names() {
    std::vector<std::string> out;
    for (const Entry& e : kBuiltins)
        out.emplace_back(e.name);
    return out;
}

std::unique_ptr<Controller> make_builtin(std::string_view name) {
    for (const Entry& e : kBuiltins) {
        if (name == e.name) return e.make();
    }
    return nullptr;
}

}  // namespace gaitlab::controllers
