// The built-in controllers, by name.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "gaitlab/controller.h"

namespace gaitlab::controllers {

/// Names of the built-in controllers, sorted.
std::vector<std::string> builtin_names();
/// A new instance of the built-in controller `name` with default parameters, or nullptr.
std::unique_ptr<Controller> make_builtin(std::string_view name);

}  // namespace gaitlab::controllers
