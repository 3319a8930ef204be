#include "gaitlab/controller.h"

#include <cmath>
#include <set>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "spec/check.h"

namespace gaitlab {

void validate(const ControllerDef& def) {
    if (def.name.empty()) throw SpecError("controller name must not be empty");
    // names become series names, labels in files and JSON strings
    detail::check_name("controller name", def.name);
    std::set<std::string> seen;
    for (const ParamDef& p : def.params) {
        const std::string where =
            fmt::format("parameter '{}' of controller '{}'", p.name, def.name);
        if (p.name.empty()) throw SpecError("parameter names must not be empty");
        detail::check_name(where + " name", p.name);
        detail::check_name(where + " unit", p.unit);
        if (!seen.insert(p.name).second) throw SpecError(where + " is declared twice");
        if (!(std::isfinite(p.min) && std::isfinite(p.max) && p.min <= p.max)) {
            throw SpecError(where + " needs a finite range with min <= max");
        }
        if (!(p.default_value >= p.min && p.default_value <= p.max)) {
            throw SpecError(fmt::format("{}: default {} is outside its range [{}, {}]", where,
                                        p.default_value, p.min, p.max));
        }
    }
    for (const std::string& v : def.values) {
        if (v.empty()) throw SpecError("value names must not be empty");
        detail::check_name(fmt::format("value '{}' of controller '{}' name", v, def.name), v);
        if (!seen.insert(v).second) {
            throw SpecError(
                fmt::format("value '{}' of controller '{}' repeats a parameter or value "
                            "name",
                            v, def.name));
        }
    }
}

Controller::Controller(ControllerDef def) : def_(std::move(def)) {
    validate(def_);
    params_.reserve(def_.params.size());
    for (const ParamDef& p : def_.params)
        params_.push_back(p.default_value);
    values_.resize(def_.values.size());
}

Controller::Controller(const Controller& other)
    : values_(other.values_),
      def_(other.def_),
      params_(other.params_),
      param_version_(other.param_version_),
      def_version_(other.def_version_),
      joints_(other.joints_),
      failed_(other.failed_),
      failure_(other.failure_) {}

std::unique_ptr<Controller> Controller::clone() const {
    throw SpecError(
        fmt::format("controller '{}' cannot be copied: its C++ class does not implement "
                    "Controller::clone()",
                    def_.name));
}

std::unique_ptr<Controller> Controller::fresh_copy() const {
    std::unique_ptr<Controller> c = clone();
    c->joints_ = 0;
    c->set_failed(false);
    for (auto& v : c->values_)
        v.clear();
    return c;
}

void ControlIO::bad_target(int m, double rad) const {
    throw SpecError(fmt::format("joint {} of the group: target must be a finite number (got {})",
                                m + 1, std::isnan(rad) ? "nan" : fmt::format("{} rad", rad)));
}

int ControlIO::find_sensor(std::string_view name) const {
    for (int k = 0; k < sensor_count(); ++k) {
        if (sensors_->spec(k).name == name) return k;
    }
    return -1;
}

int Controller::find_param(std::string_view name) const {
    for (size_t i = 0; i < def_.params.size(); ++i) {
        if (def_.params[i].name == name) return static_cast<int>(i);
    }
    return -1;
}

double Controller::param(std::string_view name) const {
    const int i = find_param(name);
    if (i < 0) {
        throw SpecError(fmt::format("controller '{}' has no parameter '{}'", def_.name, name));
    }
    return params_[i];
}

void Controller::set_param(int i, double value, Origin origin) {
    const ParamDef& p = def_.params[i];
    if (!(value >= p.min && value <= p.max)) {
        throw SpecError(fmt::format("{}.{} must be in [{}, {}]{}{} (got {})", def_.name, p.name,
                                    p.min, p.max, p.unit.empty() ? "" : " ", p.unit,
                                    std::isnan(value) ? "nan" : fmt::format("{}", value)));
    }
    if (params_[i] != value) {
        params_[i] = value;
        ++param_version_;
        if (param_listener_) param_listener_(i, value, origin);
    }
}

void Controller::set_param(std::string_view name, double value, Origin origin) {
    const int i = find_param(name);
    if (i < 0) {
        throw SpecError(fmt::format("controller '{}' has no parameter '{}'", def_.name, name));
    }
    set_param(i, value, origin);
}

void Controller::bind(int joints) {
    if (joints < 1) throw SpecError("a controller must drive at least one joint");
    if (bound()) {
        throw SpecError(
            fmt::format("controller '{}' already drives a group (create one "
                        "controller per group)",
                        def_.name));
    }
    joints_ = joints;
    reset();
}

void Controller::unbind() {
    joints_ = 0;
    for (auto& v : values_)
        v.clear();
    param_listener_ = nullptr;
}

void Controller::reset() {
    for (auto& v : values_)
        v.assign(static_cast<size_t>(joints_), 0.0);
    on_bind();
}

ControllerRef Controller::ref() const {
    ControllerRef r;
    r.kind = ControllerRef::Kind::builtin;
    r.name = name();
    for (size_t i = 0; i < def_.params.size(); ++i)
        r.params.emplace_back(def_.params[i].name, params_[i]);
    return r;
}

void Controller::set_failed(bool failed, std::string message) {
    failed_ = failed;
    failure_ = failed ? std::move(message) : std::string();
}

void Controller::redefine(ControllerDef def, std::vector<double> params) {
    validate(def);
    if (params.size() != def.params.size()) {
        throw SpecError(fmt::format("controller '{}': {} parameter values for {} parameters",
                                    def.name, params.size(), def.params.size()));
    }
    for (size_t i = 0; i < params.size(); ++i) {
        const ParamDef& p = def.params[i];
        if (!(params[i] >= p.min && params[i] <= p.max)) {
            throw SpecError(fmt::format("{}.{} must be in [{}, {}] (got {})", def.name, p.name,
                                        p.min, p.max, params[i]));
        }
    }
    def_ = std::move(def);
    params_ = std::move(params);
    ++param_version_;
    ++def_version_;
    values_.assign(def_.values.size(), std::vector<double>(static_cast<size_t>(joints_), 0.0));
}

const std::vector<double>& Controller::values(int k) const {
    sync_values();
    return values_[k];
}

const std::vector<std::vector<double>>& Controller::all_values() const {
    sync_values();
    return values_;
}

int Controller::find_value(std::string_view name) const {
    for (size_t i = 0; i < def_.values.size(); ++i) {
        if (def_.values[i] == name) return static_cast<int>(i);
    }
    return -1;
}

}  // namespace gaitlab
