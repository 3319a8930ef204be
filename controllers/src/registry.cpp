#include "gaitlab/controllers/registry.h"

#include "gaitlab/controllers/offset.h"
#include "gaitlab/controllers/sine.h"

namespace gaitlab::controllers {

namespace {

struct Entry {
    const char* name;
    std::unique_ptr<Controller> (*make)();
};

// every built-in controller, sorted by name
const Entry kBuiltins[] = {
    {"offset", [] { return std::unique_ptr<Controller>(new Offset()); }},
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
