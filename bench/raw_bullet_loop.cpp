#include "raw_bullet_loop.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "bullet/box_plane.h"
#include "bullet/box_shape.h"
#include "bullet/coulomb_solver.h"

namespace gaitlab_bench {

namespace {

constexpr double kPi = 3.14159265358979323846;

// the y1 module: 72 mm joint to joint, 52 x 52 mm, 50 g in two halves, joint range +-90 deg,
// servo kp 8.3 1/s, max 4.5 rad/s, max 0.4 N m; friction 1.0; box collision margin 1 mm
constexpr double kLength = 0.072;
constexpr double kWidth = 0.052;
constexpr double kHeight = 0.052;
constexpr double kMass = 0.05;
constexpr double kMaxAngle = 1.5707963267948966;
constexpr double kKp = 8.3;
constexpr double kMaxSpeed = 4.5;
constexpr double kMaxTorque = 0.4;
constexpr double kModuleFriction = 1.0;
constexpr btScalar kMargin = btScalar(0.001);
// the robot's own collision group bit: its bodies touch the floor, never each other
constexpr int kRobotBit = 1 << 8;

}  // namespace

struct RawSnake::Impl {
    explicit Impl(std::unique_ptr<btCollisionConfiguration> c)
        : config(std::move(c)),
          dispatcher(config.get()),
          world(&dispatcher, &broadphase, &solver, config.get()) {}
    // the engine's contact generation (gaitlab::BoxPlaneConfiguration) unless RawOptions say
    std::unique_ptr<btCollisionConfiguration> config;
    btCollisionDispatcher dispatcher;
    btDbvtBroadphase broadphase;
    gaitlab::CoulombSolver solver;  // the engine's contact model
    btDiscreteDynamicsWorld world;
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btRigidBody>> bodies;  // floor first, then tail to head
    std::vector<std::unique_ptr<btHingeConstraint>> hinges;
    std::vector<btJointFeedback> feedback;
    std::vector<double> masses;
    Vec start;

    // gait and servo state, one entry per joint
    std::vector<double> amplitude;  // deg
    std::vector<double> lag;        // rad: index within the joint's group times the phase
    std::vector<double> angle;      // rad, read every tick
    std::vector<double> target;     // rad, set every control step
    double clock = 0;               // s, advanced by control_dt before each gait step
    double frequency = 0;
    double dt = 0;
    double control_dt = 0;
    int control_every = 1;
    long tick = 0;

    ~Impl() {
        for (auto& h : hinges)
            world.removeConstraint(h.get());
        for (auto& b : bodies)
            world.removeRigidBody(b.get());
    }

    Vec centre_of_mass() const {
        Vec sum;
        double total = 0;
        for (size_t b = 0; b < masses.size(); ++b) {
            const btVector3& p = bodies[b + 1]->getWorldTransform().getOrigin();
            sum.x += double(p.x()) * masses[b];
            sum.y += double(p.y()) * masses[b];
            sum.z += double(p.z()) * masses[b];
            total += masses[b];
        }
        const double inv = 1.0 / total;
        return {sum.x * inv, sum.y * inv, sum.z * inv};
    }
};

namespace {

std::unique_ptr<btCollisionConfiguration> collision_configuration(RawOptions::Contacts c) {
    switch (c) {
        case RawOptions::Contacts::bullet_multipoint:
            return std::make_unique<gaitlab::ContactConfiguration>();
        case RawOptions::Contacts::box_plane_fewer:
            return std::make_unique<gaitlab::BoxPlaneConfiguration>(
                gaitlab::BoxPlanePoints::flat_or_two);
        case RawOptions::Contacts::engine:
            break;
    }
    return std::make_unique<gaitlab::BoxPlaneConfiguration>(gaitlab::BoxPlanePoints::touching);
}

}  // namespace

RawSnake::RawSnake(const Scenario& sc, const RawOptions& options)
    : impl_(std::make_unique<Impl>(collision_configuration(options.contacts))) {
    Impl& s = *impl_;
    btDiscreteDynamicsWorld& world = s.world;
    world.setGravity(btVector3(0, 0, btScalar(-9.81)));
    world.getSolverInfo().m_numIterations = sc.solver_iterations;
    if (sc.friction_per_step) s.solver.set_friction_model(gaitlab::FrictionModel::per_step);
    if (sc.solver_method == "symmetric") {
        s.solver.set_method(gaitlab::SolverMethod::symmetric);
    } else if (sc.solver_method == "nncg") {
        s.solver.set_method(gaitlab::SolverMethod::nncg);
    } else if (sc.solver_method == "block") {
        s.solver.set_method(gaitlab::SolverMethod::block);
    } else if (sc.solver_method == "block-nncg") {
        s.solver.set_method(gaitlab::SolverMethod::block_nncg);
    } else if (sc.solver_method != "pgs") {
        throw std::runtime_error("unknown solver method '" + sc.solver_method +
                                 "' (pgs, symmetric, nncg, block or block-nncg)");
    }

    auto plane = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), btScalar(0));
    btRigidBody::btRigidBodyConstructionInfo floor_info(0, nullptr, plane.get());
    floor_info.m_friction = btScalar(sc.floor_friction);
    s.bodies.push_back(std::make_unique<btRigidBody>(floor_info));
    s.bodies.back()->setUserIndex(-2);  // the engine's numbering, which its solver orders by
    world.addRigidBody(s.bodies.back().get(), btBroadphaseProxy::StaticFilter,
                       btBroadphaseProxy::AllFilter);
    s.shapes.push_back(std::move(plane));

    // N modules cut at their mid-planes: tail half, N - 1 whole segments, head half
    const int n = sc.modules;
    auto add_box = [&](double x0, double x1, double mass) {
        const btVector3 half(btScalar((x1 - x0) * 0.5), btScalar(kWidth * 0.5),
                             btScalar(kHeight * 0.5));
        auto box = std::make_unique<gaitlab::BoxShape>(half);
        box->setMargin(kMargin);
        btVector3 inertia(0, 0, 0);
        box->calculateLocalInertia(btScalar(mass), inertia);
        btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), nullptr, box.get(), inertia);
        info.m_startWorldTransform.setIdentity();
        info.m_startWorldTransform.setOrigin(
            btVector3(btScalar((x0 + x1) / 2), 0, btScalar(kHeight / 2)));
        info.m_friction = btScalar(kModuleFriction);
        info.m_restitution = 0;
        s.bodies.push_back(std::make_unique<btRigidBody>(info));
        btRigidBody* body = s.bodies.back().get();
        body->setUserIndex(static_cast<int>(s.bodies.size()) - 2);  // 0 for the first module
        body->setActivationState(DISABLE_DEACTIVATION);
        world.addRigidBody(body, kRobotBit, btBroadphaseProxy::AllFilter & ~kRobotBit);
        s.shapes.push_back(std::move(box));
        s.masses.push_back(mass);
    };
    add_box(0, kLength / 2, kMass / 2);
    for (int k = 1; k < n; ++k)
        add_box(kLength * (k - 0.5), kLength * (k + 0.5), kMass);
    add_box(kLength * (n - 0.5), kLength * n, kMass / 2);

    // joint j joins body j (tail side) and body j + 1 (head side) at their shared face; Bullet's
    // body A is the head side, so the hinge angle is the head side's rotation about the axis
    int pitch_index = 0, yaw_index = 0;
    const double dphi = sc.phase * (kPi / 180);
    for (int j = 0; j < n; ++j) {
        btRigidBody& child = *s.bodies[static_cast<size_t>(j) + 2];
        btRigidBody& parent = *s.bodies[static_cast<size_t>(j) + 1];
        const bool yaw = sc.pitch_yaw && j % 2 == 1;
        const btVector3 pivot(btScalar(kLength * (j + 0.5)), 0, btScalar(kHeight / 2));
        const btVector3 axis = yaw ? btVector3(0, 0, 1) : btVector3(0, -1, 0);
        const btTransform& tc = child.getWorldTransform();
        const btTransform& tp = parent.getWorldTransform();
        auto hinge = std::make_unique<btHingeConstraint>(
            child, parent, tc.inverse() * pivot, tp.inverse() * pivot,
            tc.getBasis().transpose() * axis, tp.getBasis().transpose() * axis);
        hinge->setLimit(btScalar(-kMaxAngle), btScalar(kMaxAngle));
        hinge->enableAngularMotor(true, 0, btScalar(kMaxTorque * sc.dt));
        hinge->setUserConstraintId(j);  // the solver visits joints in this order, as the engine's
        if (options.joint_iterations > 0)
            hinge->setOverrideNumSolverIterations(options.joint_iterations);
        world.addConstraint(hinge.get(), true);
        s.hinges.push_back(std::move(hinge));
        s.amplitude.push_back(yaw ? sc.yaw_amplitude : sc.pitch_amplitude);
        s.lag.push_back(static_cast<double>(yaw ? yaw_index++ : pitch_index++) * dphi +
                        (sc.phase0 + (yaw ? sc.yaw_phase0 : 0)) * (kPi / 180));
    }
    s.feedback.resize(s.hinges.size());
    for (size_t j = 0; j < s.hinges.size(); ++j) {
        s.hinges[j]->setJointFeedback(&s.feedback[j]);
        s.hinges[j]->enableFeedback(true);
    }

    s.angle.assign(s.hinges.size(), 0.0);
    s.target.assign(s.hinges.size(), 0.0);
    s.frequency = sc.frequency;
    s.dt = sc.dt;
    s.control_every = sc.control_every;
    s.control_dt = sc.dt * sc.control_every;
    s.start = s.centre_of_mass();
}

RawSnake::~RawSnake() = default;

void RawSnake::step(long ticks) {
    Impl& s = *impl_;
    const size_t n = s.hinges.size();
    const btScalar dt = btScalar(s.dt);
    for (long i = 0; i < ticks; ++i, ++s.tick) {
        for (size_t j = 0; j < n; ++j)
            s.angle[j] = s.hinges[j]->getHingeAngle();
        if (s.tick % s.control_every == 0) {
            s.clock += s.control_dt;
            const double wt = 2 * kPi * s.frequency * s.clock;
            for (size_t j = 0; j < n; ++j) {
                const double deg = s.amplitude[j] * std::sin(wt + s.lag[j]);
                s.target[j] = std::clamp(deg * (kPi / 180), -kMaxAngle, kMaxAngle);
            }
        }
        for (size_t j = 0; j < n; ++j) {
            const double w = std::clamp(kKp * (s.target[j] - s.angle[j]), -kMaxSpeed, kMaxSpeed);
            s.hinges[j]->setMotorTargetVelocity(btScalar(w));
        }
        s.world.stepSimulation(dt, 0);
    }
}

long RawSnake::ticks() const {
    return impl_->tick;
}

Vec RawSnake::displacement() const {
    const Vec c = impl_->centre_of_mass();
    return {c.x - impl_->start.x, c.y - impl_->start.y, c.z - impl_->start.z};
}

double RawSnake::max_separation() const {
    double worst = 0;
    for (const auto& h : impl_->hinges) {
        const btVector3 a = h->getRigidBodyA().getWorldTransform() * h->getAFrame().getOrigin();
        const btVector3 b = h->getRigidBodyB().getWorldTransform() * h->getBFrame().getOrigin();
        worst = std::max(worst, double((a - b).length()));
    }
    return worst;
}

double RawSnake::max_axis_angle() const {
    double worst = 0;
    for (const auto& h : impl_->hinges) {
        // the hinge axis is the z column of each body's constraint frame
        const btVector3 a = h->getRigidBodyA().getWorldTransform().getBasis() *
                            h->getAFrame().getBasis().getColumn(2);
        const btVector3 b = h->getRigidBodyB().getWorldTransform().getBasis() *
                            h->getBFrame().getBasis().getColumn(2);
        worst = std::max(worst, double(std::atan2(a.cross(b).length(), a.dot(b))));
    }
    return worst;
}

int RawSnake::contact_count() const {
    int count = 0;
    btDispatcher& d = impl_->dispatcher;
    for (int i = 0; i < d.getNumManifolds(); ++i) {
        count += d.getManifoldByIndexInternal(i)->getNumContacts();
    }
    return count;
}

btContactSolverInfo& RawSnake::solver_info() {
    return impl_->world.getSolverInfo();
}

}  // namespace gaitlab_bench
