#include "sim/sensing.h"

#include <algorithm>
#include <cmath>

#include "bullet/physics_world.h"

namespace gaitlab {

namespace {

// `d` (finite, not zero) made a unit vector. Its norm underflows to 0 or overflows to infinity
// for components such as 1e-300 or 1e300 (a ray along 1/infinity times the direction has no
// length and meets nothing): such a vector is divided by its largest component first. Others
// are normalized as they always were, to the same bits
Vec3 unit(const Vec3& d) {
    const double n = d.norm();
    if (n >= 1e-150 && n <= 1e150) return d * (1.0 / n);
    const double big = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    const Vec3 e{d.x / big, d.y / big, d.z / big};
    return e * (1.0 / e.norm());
}

}  // namespace

// robot r's sensors as its controllers see them
class Sensing::Reader final : public SensorReader {
  public:
    Reader(const Sensing& s, int robot) : s_(s), robot_(robot) {}
    int count() const override { return s_.robot_sensor_count(robot_); }
    const SensorSpec& spec(int k) const override { return s_.spec(s_.index(robot_, k)); }
    const double* values(int k) const override { return s_.values(s_.index(robot_, k)).data(); }

  private:
    const Sensing& s_;
    int robot_;
};

Sensing::Sensing(const WorldSpec& world, double dt) : dt_(dt), gravity_(world.gravity) {
    int first_body = 0, first_joint = 0;
    for (size_t r = 0; r < world.robots.size(); ++r) {
        const RobotSpec& spec = world.robots[r].robot;
        RobotInfo info;
        info.first_body = first_body;
        info.bodies = static_cast<int>(spec.bodies.size());
        info.first_joint = first_joint;
        for (const BodySpec& b : spec.bodies) {
            info.masses.push_back(b.mass);
            info.total_mass += b.mass;
            body_joints_.emplace_back();
        }
        // each joint's pivot in the frames of the two bodies it joins: a contact point on a
        // body belongs to the module whose joint is nearest to it
        for (size_t j = 0; j < spec.joints.size(); ++j) {
            const JointSpec& js = spec.joints[j];
            const int g = first_joint + static_cast<int>(j);
            for (int b : {js.parent, js.child}) {
                const Pose& pose = spec.bodies[static_cast<size_t>(b)].pose;
                const Vec3 local = pose.orientation.conjugate().rotate(js.pivot - pose.position);
                body_joints_[static_cast<size_t>(first_body + b)].push_back({local, g});
            }
            info.parents.push_back(first_body + js.parent);
            info.children.push_back(first_body + js.child);
        }
        info.reader = std::make_unique<Reader>(*this, static_cast<int>(r));
        first_body += info.bodies;
        first_joint += static_cast<int>(spec.joints.size());
        robots_.push_back(std::move(info));
    }
    robot_bodies_ = first_body;
    contacts_by_joint_.resize(static_cast<size_t>(first_joint));
    contact_bodies_.assign(static_cast<size_t>(first_body), 0);
    for (size_t r = 0; r < world.robots.size(); ++r) {
        const auto& sensors = world.robots[r].robot.sensors;
        for (size_t k = 0; k < sensors.size(); ++k) {
            robots_[r].sensors.push_back(count());
            slots_.push_back(compile(static_cast<int>(r), static_cast<int>(k), sensors[k]));
        }
    }
    rebuild_active();
}

Sensing::~Sensing() = default;

Sensing::Sensing(const Sensing& o)
    : dt_(o.dt_),
      gravity_(o.gravity_),
      slots_(o.slots_),
      body_joints_(o.body_joints_),
      robot_bodies_(o.robot_bodies_),
      active_(o.active_),
      active_contacts_(o.active_contacts_),
      contacts_by_joint_(o.contacts_by_joint_),
      contact_bodies_(o.contact_bodies_) {
    for (size_t r = 0; r < o.robots_.size(); ++r) {
        const RobotInfo& from = o.robots_[r];
        RobotInfo info;
        info.first_body = from.first_body;
        info.bodies = from.bodies;
        info.first_joint = from.first_joint;
        info.masses = from.masses;
        info.total_mass = from.total_mass;
        info.parents = from.parents;
        info.children = from.children;
        info.sensors = from.sensors;
        info.reader = std::make_unique<Reader>(*this, static_cast<int>(r));
        robots_.push_back(std::move(info));
    }
}

std::unique_ptr<Sensing> Sensing::copy() const {
    return std::unique_ptr<Sensing>(new Sensing(*this));
}

void Sensing::adopt(PhysicsWorld& physics) {
    mark_robot_bodies(physics, robot_bodies_);
}

Sensing::Slot Sensing::compile(int robot, int local, const SensorSpec& spec) const {
    const RobotInfo& info = robots_[static_cast<size_t>(robot)];
    Slot s;
    s.spec = spec;
    s.spec.name = sensor_name(spec);
    s.robot = robot;
    s.local = local;
    const size_t m = static_cast<size_t>(spec.module);
    switch (spec.kind) {
        case SensorKind::joint:
            s.joint = info.first_joint + spec.joint;
            break;
        case SensorKind::contact:
            s.joint = info.first_joint + spec.module;
            break;
        case SensorKind::imu:
        case SensorKind::range:
            s.body = spec.half == ModuleHalf::tail ? info.parents[m] : info.children[m];
            s.direction = unit(spec.direction);
            break;
        case SensorKind::position:
            break;
    }
    s.values.assign(sensor_channels(spec.kind).size(), 0.0);
    return s;
}

int Sensing::find(int robot, std::string_view name) const {
    for (int i : robots_[static_cast<size_t>(robot)].sensors) {
        if (slots_[static_cast<size_t>(i)].spec.name == name) return i;
    }
    return -1;
}

int Sensing::add(int robot, const SensorSpec& spec, const PhysicsWorld& physics) {
    RobotInfo& info = robots_[static_cast<size_t>(robot)];
    const int i = count();
    slots_.push_back(compile(robot, static_cast<int>(info.sensors.size()), spec));
    info.sensors.push_back(i);
    if (spec.enabled) {
        rebuild_active();
        if (spec.kind == SensorKind::contact) {
            read_contacts(physics);
        } else {
            read(slots_.back(), physics);
        }
    }
    return i;
}

void Sensing::set_enabled(int i, bool on, const PhysicsWorld& physics) {
    Slot& s = slots_[static_cast<size_t>(i)];
    if (s.spec.enabled == on) return;
    s.spec.enabled = on;
    s.has_last = false;  // an IMU switched on again starts from rest
    rebuild_active();
    if (!on) return;
    if (s.spec.kind == SensorKind::contact) {
        read_contacts(physics);
    } else {
        read(s, physics);
    }
}

void Sensing::attach(PhysicsWorld& physics) {
    mark_robot_bodies(physics, robot_bodies_);
    for (Slot& s : slots_)
        s.has_last = false;
    update(physics);
}

void Sensing::rebuild_active() {
    active_.clear();
    active_contacts_.clear();
    for (auto& v : contacts_by_joint_)
        v.clear();
    std::fill(contact_bodies_.begin(), contact_bodies_.end(), 0);
    for (int i = 0; i < count(); ++i) {
        const Slot& s = slots_[static_cast<size_t>(i)];
        if (!s.spec.enabled) continue;
        if (s.spec.kind != SensorKind::contact) {
            active_.push_back(i);
            continue;
        }
        active_contacts_.push_back(i);
        contacts_by_joint_[static_cast<size_t>(s.joint)].push_back(i);
        const RobotInfo& info = robots_[static_cast<size_t>(s.robot)];
        const size_t m = static_cast<size_t>(s.joint - info.first_joint);
        contact_bodies_[static_cast<size_t>(info.parents[m])] = 1;
        contact_bodies_[static_cast<size_t>(info.children[m])] = 1;
    }
}

void Sensing::update(const PhysicsWorld& physics) {
    if (!active_contacts_.empty()) read_contacts(physics);
    for (int i : active_)
        read(slots_[static_cast<size_t>(i)], physics);
}

void Sensing::read(Slot& s, const PhysicsWorld& physics) {
    double* out = s.values.data();
    switch (s.spec.kind) {
        case SensorKind::joint:
            out[0] = physics.angle(s.joint);
            out[1] = physics.velocity(s.joint);
            out[2] = physics.torque(s.joint);
            break;
        case SensorKind::imu: {
            const BodyState b = physics.body(s.body);
            const Quat& q = b.pose.orientation;
            const Quat inv = q.conjugate();
            // yaw: heading of the body's x axis; pitch: its elevation (nose up > 0); roll:
            // about it (left side up > 0); so q = Rz(yaw) * Ry(-pitch) * Rx(roll)
            const Vec3 x = q.rotate({1, 0, 0}), y = q.rotate({0, 1, 0}), z = q.rotate({0, 0, 1});
            out[0] = std::atan2(y.z, z.z);
            out[1] = std::atan2(x.z, std::hypot(x.x, x.y));
            out[2] = std::atan2(x.y, x.x);
            out[3] = q.w;
            out[4] = q.x;
            out[5] = q.y;
            out[6] = q.z;
            const Vec3 w = inv.rotate(b.angular_velocity);
            out[7] = w.x;
            out[8] = w.y;
            out[9] = w.z;
            // an accelerometer measures specific force: the acceleration minus gravity, so a
            // module at rest reads +9.81 m/s² upward; the acceleration is the change of the
            // body's velocity since the previous reading (one tick), zero at the first
            const Vec3 a =
                s.has_last ? (b.linear_velocity - s.last_velocity) * (1.0 / dt_) : Vec3{};
            const Vec3 f = inv.rotate(a - gravity_);
            out[10] = f.x;
            out[11] = f.y;
            out[12] = f.z;
            s.last_velocity = b.linear_velocity;
            s.has_last = true;
            break;
        }
        case SensorKind::range: {
            const BodyState b = physics.body(s.body);
            const RayHit h = cast_ray(physics, s.body, b.pose.position,
                                      b.pose.orientation.rotate(s.direction), s.spec.max_range);
            out[0] = h.distance;
            out[1] = h.hit ? 1 : 0;
            break;
        }
        case SensorKind::position: {
            const RobotInfo& info = robots_[static_cast<size_t>(s.robot)];
            Vec3 x, v;
            // the robot's centre of mass: its bodies' centres of mass, which may lie off their
            // shapes' centres
            for (int k = 0; k < info.bodies; ++k) {
                const double m = info.masses[static_cast<size_t>(k)];
                x += physics.position(info.first_body + k) * m;
                v += physics.mass_velocity(info.first_body + k) * m;
            }
            x = x * (1.0 / info.total_mass);
            v = v * (1.0 / info.total_mass);
            out[0] = x.x;
            out[1] = x.y;
            out[2] = x.z;
            out[3] = v.x;
            out[4] = v.y;
            out[5] = v.z;
            break;
        }
        case SensorKind::contact:
            break;  // read_contacts reads every contact sensor at once
    }
}

void Sensing::read_contacts(const PhysicsWorld& physics) {
    for (int i : active_contacts_) {
        auto& v = slots_[static_cast<size_t>(i)].values;
        v[0] = 0;
        v[1] = 0;
    }
    contact_buffer_.clear();
    collect_contacts(physics, contact_bodies_, contact_buffer_);
    for (const BodyContact& c : contact_buffer_) {
        const auto& joints = body_joints_[static_cast<size_t>(c.body)];
        const BodyJoint* nearest = &joints[0];
        double best = (c.local - nearest->pivot).norm();
        for (const BodyJoint& j : joints) {
            const double d = (c.local - j.pivot).norm();
            if (d < best) {
                best = d;
                nearest = &j;
            }
        }
        for (int i : contacts_by_joint_[static_cast<size_t>(nearest->joint)]) {
            auto& v = slots_[static_cast<size_t>(i)].values;
            v[0] = 1;
            v[1] += c.impulse / dt_;
        }
    }
}

}  // namespace gaitlab
