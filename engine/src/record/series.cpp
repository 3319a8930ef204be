#include "gaitlab/series.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "gaitlab/controller.h"
#include "gaitlab/error.h"
#include "gaitlab/simulation.h"
#include "gaitlab/suggest.h"

namespace gaitlab {

const char* to_string(SeriesKind kind) {
    switch (kind) {
        case SeriesKind::robot:
            return "robot";
        case SeriesKind::controller:
            return "controller";
        case SeriesKind::sensor:
            return "sensor";
        case SeriesKind::object:
            return "object";
    }
    return "?";
}

bool parse_series_kind(std::string_view name, SeriesKind& kind) {
    for (SeriesKind k :
         {SeriesKind::robot, SeriesKind::controller, SeriesKind::sensor, SeriesKind::object}) {
        if (name == to_string(k)) {
            kind = k;
            return true;
        }
    }
    return false;
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// one robot: centre of mass, body poses, joints, mechanical power and energy
class RobotSource final : public SeriesSource {
  public:
    RobotSource(const Simulation& sim, int robot) : robot_(robot) {
        const RobotSpec& spec = sim.world().robots[static_cast<size_t>(robot)].robot;
        const std::string& label = sim.robot_label(robot);
        bodies_ = static_cast<int>(spec.bodies.size());
        joints_ = static_cast<int>(spec.joints.size());
        auto add = [&](std::string value, int joint, std::string body, const char* unit) {
            SeriesInfo s;
            s.kind = SeriesKind::robot;
            s.source = label;
            if (!body.empty()) {
                s.name = label + "." + body + "." + value;
            } else if (joint > 0) {
                s.name = fmt::format("{}.{}[{}]", label, value, joint);
            } else {
                s.name = label + "." + value;
            }
            s.value = std::move(value);
            s.joint = joint;
            s.body = std::move(body);
            s.unit = unit;
            series_.push_back(std::move(s));
        };
        for (const char* c : {"x", "y", "z"})
            add(std::string("com.") + c, 0, "", "m");
        for (const char* c : {"vx", "vy", "vz"})
            add(std::string("com.") + c, 0, "", "m/s");
        for (const BodySpec& b : spec.bodies) {
            if (b.name == "com") {
                throw SpecError(fmt::format(
                    "robot '{}' has a body named 'com', whose series would clash with the centre "
                    "of mass series '{}.com.x' (rename the body)",
                    spec.name, label));
            }
            for (const char* c : {"x", "y", "z"})
                add(c, 0, b.name, "m");
            for (const char* c : {"qw", "qx", "qy", "qz"})
                add(c, 0, b.name, "");
        }
        const std::pair<const char*, const char*> per_joint[] = {
            {"angle", "deg"},  {"target", "deg"}, {"velocity", "deg/s"},
            {"torque", "N·m"}, {"power", "W"},    {"energy", "J"}};
        for (const auto& [value, unit] : per_joint) {
            for (int m = 1; m <= joints_; ++m)
                add(value, m, "", unit);
        }
        add("power", 0, "", "W");
        add("energy", 0, "", "J");
        power_.assign(static_cast<size_t>(joints_), 0.0);
        energy_.assign(static_cast<size_t>(joints_), 0.0);
    }

    const std::vector<SeriesInfo>& series() const override { return series_; }

    void sample(const Simulation& sim, double* out) override {
        const Vec3 c = sim.robot_position(robot_), v = sim.robot_velocity(robot_);
        for (double x : {c.x, c.y, c.z, v.x, v.y, v.z})
            *out++ = x;
        for (int b = 0; b < bodies_; ++b) {
            const Pose p = sim.body(robot_, b).pose;
            for (double x : {p.position.x, p.position.y, p.position.z, p.orientation.w,
                             p.orientation.x, p.orientation.y, p.orientation.z})
                *out++ = x;
        }
        double* angle = out;
        double* target = angle + joints_;
        double* velocity = target + joints_;
        double* torque = velocity + joints_;
        double* power = torque + joints_;
        double* energy = power + joints_;
        // the simulation integrates the energy from time 0, recorded or not
        // (Simulation::joint_energies): every recording of it reads the same
        sim.joint_powers(robot_, power_.data());
        sim.joint_energies(robot_, energy_.data());
        double total_power = 0, total_energy = 0;
        for (int j = 0; j < joints_; ++j) {
            const JointState s = sim.joint(robot_, j);
            angle[j] = rad_to_deg(s.angle);
            target[j] = rad_to_deg(s.target);
            velocity[j] = rad_to_deg(s.velocity);
            torque[j] = s.torque;
            power[j] = power_[static_cast<size_t>(j)];
            energy[j] = energy_[static_cast<size_t>(j)];
            total_power += power[j];
            total_energy += energy[j];
        }
        out = energy + joints_;
        out[0] = total_power;
        out[1] = total_energy;
    }

  private:
    int robot_;
    int bodies_ = 0;
    int joints_ = 0;
    std::vector<SeriesInfo> series_;
    std::vector<double> power_;   // W, per joint, now (scratch)
    std::vector<double> energy_;  // J, per joint, since time 0 (scratch)
};

// one drive's controller: its parameters, then its per-joint values
class ControllerSource final : public SeriesSource {
  public:
    ControllerSource(const Simulation& sim, int drive) : drive_(drive) {
        const Controller& c = sim.controller(drive);
        const std::string& label = sim.drive_label(drive);
        joints_ = c.joints();
        for (const ParamDef& p : c.def().params) {
            SeriesInfo s;
            s.name = label + "." + p.name;
            s.kind = SeriesKind::controller;
            s.source = label;
            s.value = p.name;
            s.unit = p.unit;
            series_.push_back(std::move(s));
            params_.push_back(p.name);
        }
        for (const std::string& v : c.def().values) {
            for (int m = 1; m <= joints_; ++m) {
                SeriesInfo s;
                s.name = fmt::format("{}.{}[{}]", label, v, m);
                s.kind = SeriesKind::controller;
                s.source = label;
                s.value = v;
                s.joint = m;
                series_.push_back(std::move(s));
            }
            values_.push_back(v);
        }
        resolve(c);
    }

    const std::vector<SeriesInfo>& series() const override { return series_; }

    void sample(const Simulation& sim, double* out) override {
        const Controller& c = sim.controller(drive_);
        // a reloaded controller may have renamed, added or removed parameters and values: the
        // columns stay, by name; the missing ones read NaN
        if (c.def_version() != def_version_) resolve(c);
        for (int i : param_index_)
            *out++ = i < 0 ? kNaN : c.param(i);
        const auto& values = c.all_values();
        for (int k : value_index_) {
            for (int m = 0; m < joints_; ++m) {
                *out++ = k < 0 ? kNaN : values[static_cast<size_t>(k)][static_cast<size_t>(m)];
            }
        }
    }

  private:
    void resolve(const Controller& c) {
        def_version_ = c.def_version();
        param_index_.clear();
        for (const std::string& p : params_)
            param_index_.push_back(c.find_param(p));
        value_index_.clear();
        for (const std::string& v : values_)
            value_index_.push_back(c.find_value(v));
    }

    int drive_;
    int joints_ = 0;
    std::vector<SeriesInfo> series_;
    std::vector<std::string> params_, values_;
    std::vector<int> param_index_, value_index_;
    std::uint64_t def_version_ = 0;
};

// the sensors of one robot that exist when the recording starts: one series per channel,
// "<robot>.<sensor>.<channel>" in user units (degrees for angles); NaN while switched off
class SensorSource final : public SeriesSource {
  public:
    SensorSource(const Simulation& sim, int robot) {
        const std::string& label = sim.robot_label(robot);
        for (int i = 0; i < sim.sensor_count(); ++i) {
            if (sim.sensor_robot(i) != robot) continue;
            const SensorSpec& spec = sim.sensor(i);
            const std::string name = sensor_name(spec);
            sensors_.push_back(i);
            for (const SensorChannel& ch : sim.sensor_channels(i)) {
                SeriesInfo s;
                s.name = label + "." + name + "." + ch.name;
                s.kind = SeriesKind::sensor;
                s.source = label;
                s.value = name + "." + ch.name;
                s.joint = spec.kind == SensorKind::joint ? spec.joint + 1 : 0;
                s.unit = user_unit(ch);
                series_.push_back(std::move(s));
            }
        }
    }
    bool empty() const { return sensors_.empty(); }

    const std::vector<SeriesInfo>& series() const override { return series_; }

    void sample(const Simulation& sim, double* out) override {
        for (int i : sensors_) {
            const std::vector<SensorChannel>& channels = sim.sensor_channels(i);
            const bool on = sim.sensor_enabled(i);
            const std::vector<double>& values = sim.sensor_values(i);
            for (size_t c = 0; c < channels.size(); ++c)
                *out++ = on ? to_user_units(channels[c], values[c]) : kNaN;
        }
    }

  private:
    std::vector<int> sensors_;
    std::vector<SeriesInfo> series_;
};

}  // namespace

namespace {

// the world's moving objects (boxes and cylinders with a mass): the pose of each, as
// Simulation::object numbers them; named after the object ("box 2" -> box_2.x ... box_2.qz)
class ObjectSource final : public SeriesSource {
  public:
    explicit ObjectSource(const Simulation& sim) : count_(sim.object_count()) {
        std::vector<std::string> names;
        const WorldSpec& w = sim.world();
        for (size_t i = 0; i < w.boxes.size(); ++i)
            if (w.boxes[i].mass > 0) names.push_back(fmt::format("box {}", i + 1));
        for (size_t i = 0; i < w.cylinders.size(); ++i)
            if (w.cylinders[i].mass > 0) names.push_back(fmt::format("cylinder {}", i + 1));
        if (static_cast<int>(names.size()) != count_) {
            throw SpecError(fmt::format("the world has {} moving objects, the simulation {}",
                                        names.size(), count_));
        }
        for (const std::string& object : names) {
            std::string prefix = object;
            std::replace(prefix.begin(), prefix.end(), ' ', '_');
            const std::pair<const char*, const char*> parts[] = {
                {"x", "m"}, {"y", "m"}, {"z", "m"}, {"qw", ""}, {"qx", ""}, {"qy", ""}, {"qz", ""}};
            for (const auto& [value, unit] : parts) {
                SeriesInfo s;
                s.kind = SeriesKind::object;
                s.source = object;
                s.name = prefix + "." + value;
                s.value = value;
                s.unit = unit;
                series_.push_back(std::move(s));
            }
        }
    }

    const std::vector<SeriesInfo>& series() const override { return series_; }

    void sample(const Simulation& sim, double* out) override {
        for (int k = 0; k < count_; ++k) {
            const Pose p = sim.object(k).pose;
            for (double x : {p.position.x, p.position.y, p.position.z, p.orientation.w,
                             p.orientation.x, p.orientation.y, p.orientation.z})
                *out++ = x;
        }
    }

  private:
    int count_ = 0;
    std::vector<SeriesInfo> series_;
};

}  // namespace

std::vector<std::unique_ptr<SeriesSource>> make_sources(const Simulation& sim) {
    std::vector<std::unique_ptr<SeriesSource>> sources;
    for (int r = 0; r < sim.robot_count(); ++r)
        sources.push_back(std::make_unique<RobotSource>(sim, r));
    for (int d = 0; d < sim.drive_count(); ++d)
        sources.push_back(std::make_unique<ControllerSource>(sim, d));
    for (int r = 0; r < sim.robot_count(); ++r) {
        auto sensors = std::make_unique<SensorSource>(sim, r);
        if (!sensors->empty()) sources.push_back(std::move(sensors));
    }
    if (sim.object_count() > 0) {
        // the objects' poses are for playing a run back: a robot or controller whose series
        // would have one of their names keeps it, and the objects are not recorded
        auto objects = std::make_unique<ObjectSource>(sim);
        std::set<std::string> taken;
        for (const auto& src : sources)
            for (const SeriesInfo& i : src->series())
                taken.insert(i.name);
        bool clash = false;
        for (const SeriesInfo& i : objects->series())
            clash = clash || taken.count(i.name) > 0;
        if (!clash) sources.push_back(std::move(objects));
    }
    return sources;
}

bool glob_match(std::string_view pattern, std::string_view name) {
    // iterative matcher with backtracking to the last '*'
    size_t p = 0, n = 0, star = std::string_view::npos, mark = 0;
    while (n < name.size()) {
        if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == name[n])) {
            ++p;
            ++n;
        } else if (p < pattern.size() && pattern[p] == '*') {
            star = p++;
            mark = n;
        } else if (star != std::string_view::npos) {
            p = star + 1;
            n = ++mark;
        } else {
            return false;
        }
    }
    while (p < pattern.size() && pattern[p] == '*')
        ++p;
    return p == pattern.size();
}

SeriesSet::SeriesSet(const Simulation& sim, const std::vector<std::string>& selection)
    : SeriesSet(make_sources(sim), selection) {}

SeriesSet::SeriesSet(std::vector<std::unique_ptr<SeriesSource>> sources,
                     const std::vector<std::string>& selection)
    : sources_(std::move(sources)) {
    std::set<std::string> names;
    for (const auto& s : sources_) {
        for (const SeriesInfo& info : s->series()) {
            if (!names.insert(info.name).second) {
                throw SpecError(fmt::format("two series are named '{}'", info.name));
            }
        }
    }
    select(selection);
}

void SeriesSet::select(const std::vector<std::string>& selection) {
    std::vector<std::string> all;
    for (const auto& s : sources_) {
        for (const SeriesInfo& info : s->series())
            all.push_back(info.name);
    }
    // which entries of the selection pick each series (a kind or a pattern)
    auto picked = [&](const SeriesInfo& info, const std::string& entry) {
        SeriesKind kind;
        if (parse_series_kind(entry, kind)) return info.kind == kind;
        return glob_match(entry, info.name);
    };
    for (const std::string& entry : selection) {
        bool any = false;
        SeriesKind kind;
        const bool is_kind = parse_series_kind(entry, kind);
        for (const auto& s : sources_) {
            for (const SeriesInfo& info : s->series())
                any = any || picked(info, entry);
        }
        if (!any && !is_kind) {
            throw SpecError(fmt::format("no series matches '{}'{}", entry, suggest(entry, all)));
        }
    }
    picks_.assign(sources_.size(), Pick{});
    size_t widest = 0;
    for (size_t k = 0; k < sources_.size(); ++k) {
        const std::vector<SeriesInfo>& series = sources_[k]->series();
        widest = std::max(widest, series.size());
        Pick& pick = picks_[k];
        for (size_t i = 0; i < series.size(); ++i) {
            const bool chosen = selection.empty() || std::any_of(selection.begin(), selection.end(),
                                                                 [&](const std::string& e) {
                                                                     return picked(series[i], e);
                                                                 });
            if (chosen) {
                pick.columns.push_back(static_cast<int>(i));
                selected_.push_back(series[i]);
            }
        }
        pick.used = !pick.columns.empty();
        pick.all = pick.columns.size() == series.size();
    }
    scratch_.assign(widest, 0.0);
}

int SeriesSet::find(std::string_view name) const {
    for (size_t i = 0; i < selected_.size(); ++i) {
        if (selected_[i].name == name) return static_cast<int>(i);
    }
    return -1;
}

void SeriesSet::tick(const Simulation& sim) {
    for (size_t k = 0; k < sources_.size(); ++k) {
        if (picks_[k].used) sources_[k]->tick(sim);
    }
}

void SeriesSet::sample(const Simulation& sim, double* out) {
    for (size_t k = 0; k < sources_.size(); ++k) {
        const Pick& pick = picks_[k];
        if (!pick.used) continue;
        if (pick.all) {
            sources_[k]->sample(sim, out);
            out += pick.columns.size();
            continue;
        }
        sources_[k]->sample(sim, scratch_.data());
        for (int c : pick.columns)
            *out++ = scratch_[static_cast<size_t>(c)];
    }
}

void SeriesSet::restart() {
    for (auto& s : sources_)
        s->restart();
}

}  // namespace gaitlab
