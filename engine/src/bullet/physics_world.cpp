#include "bullet/physics_world.h"

#include "bullet/box_plane.h"
#include "bullet/box_shape.h"
#include "bullet/coulomb_solver.h"

#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "gaitlab/error.h"
#include "gaitlab/geometry.h"
#include "spec/random.h"

namespace gaitlab {

namespace {

btVector3 to_bt(const Vec3& v) {
    return {static_cast<btScalar>(v.x), static_cast<btScalar>(v.y), static_cast<btScalar>(v.z)};
}
btQuaternion to_bt(const Quat& q) {
    return {static_cast<btScalar>(q.x), static_cast<btScalar>(q.y), static_cast<btScalar>(q.z),
            static_cast<btScalar>(q.w)};
}
btTransform to_bt(const Pose& p) {
    return btTransform(to_bt(p.orientation), to_bt(p.position));
}
Vec3 from_bt(const btVector3& v) {
    return {v.x(), v.y(), v.z()};
}
Quat from_bt(const btQuaternion& q) {
    return {q.w(), q.x(), q.y(), q.z()};
}

// collision margin of every shape: Bullet's default 4 cm is larger than a module's half-width
constexpr btScalar kMargin = btScalar(0.001);

// the Bullet shape of a solid; a heightfield's samples are copied to `*heights`, which must
// outlive the shape
std::unique_ptr<btCollisionShape> make_shape(const Solid& s, std::vector<float>* heights) {
    std::unique_ptr<btCollisionShape> shape;
    switch (s.kind) {
        case Solid::Kind::box:
            shape = std::make_unique<BoxShape>(to_bt(s.size * 0.5));
            break;
        case Solid::Kind::cylinder:
            shape = std::make_unique<btCylinderShapeX>(to_bt(s.size * 0.5));
            break;
        case Solid::Kind::convex: {
            auto hull = std::make_unique<btConvexHullShape>();
            for (const Vec3& p : s.points)
                hull->addPoint(to_bt(p), false);
            hull->recalcLocalAabb();
            shape = std::move(hull);
            break;
        }
        case Solid::Kind::heightfield: {
            const HeightGrid& g = s.grid;
            heights->assign(g.heights.begin(), g.heights.end());
            const auto [lo, hi] = std::minmax_element(heights->begin(), heights->end());
            auto field = std::make_unique<HeightfieldShape>(g.samples_x, g.samples_y,
                                                            heights->data(), *lo, *hi);
            field->setLocalScaling(btVector3(btScalar(g.length / (g.samples_x - 1)),
                                             btScalar(g.width / (g.samples_y - 1)), 1));
            shape = std::move(field);
            break;
        }
    }
    shape->setMargin(kMargin);
    return shape;
}

// The shape of a body whose centre of mass is off its shape's centre: Bullet's body frame is
// its centre of mass, so the box or cylinder sits in a compound, shifted from it by the offset.
// Its one child answers for it where Bullet asks the shape of the body rather than the child: the
// contact breaking threshold of the pair's manifold (a BoxShape's, at most half its smallest
// side, which keeps a thin box's corners apart; the compound's own would be 2 % of its bounding
// sphere about the centre of mass, larger the farther the shape lies from it)
class OffsetShape : public btCompoundShape {
  public:
    OffsetShape(const btVector3& center_of_mass, btCollisionShape* shape)
        : btCompoundShape(/*enableDynamicAabbTree=*/false, 1) {
        addChildShape(btTransform(btQuaternion::getIdentity(), -center_of_mass), shape);
        setMargin(kMargin);
    }
    btScalar getContactBreakingThreshold(btScalar factor) const override {
        return getChildShape(0)->getContactBreakingThreshold(factor);
    }
};

// Bullet centres a heightfield between its lowest and highest sample: the body's transform puts
// height 0 of the grid at the solid's origin
btTransform body_transform(const Solid& s) {
    btTransform t = to_bt(s.pose);
    if (s.kind == Solid::Kind::heightfield) {
        const auto [lo, hi] = std::minmax_element(s.grid.heights.begin(), s.grid.heights.end());
        const btScalar mid = btScalar((static_cast<float>(*lo) + static_cast<float>(*hi)) / 2);
        t.setOrigin(t * btVector3(0, 0, mid));
    }
    return t;
}
// a body's contact stiffness and damping as neither of them in the combination with a compliant
// floor's (k = 1/(1/k0 + 1/k1): 1/infinity adds nothing; c = c0 + c1), instead of Bullet's
// defaults (a huge stiffness, which adds a rounding, and a damping of 0.1 N s/m, which would be
// added to the floor's). Without the flag that setContactStiffnessAndDamping sets, the values
// are read only when the other body has it (the compliant floor): rigid contacts are unchanged
void contact_values_neutral(btCollisionObject& body) {
    body.setContactStiffnessAndDamping(std::numeric_limits<btScalar>::infinity(), 0);
    body.setCollisionFlags(body.getCollisionFlags() &
                           ~btCollisionObject::CF_HAS_CONTACT_STIFFNESS_DAMPING);
}

// robots get collision group bits 8..31 so that robots collide with each other but a robot's
// bodies do not collide among themselves (unless self_collision asks for it)
constexpr int kFirstRobotBit = 8;
constexpr int kRobotBits = 24;

}  // namespace

const char* physics_version() {
    static const std::string v =
        std::to_string(btGetVersion() / 100) + "." + std::to_string(btGetVersion() % 100);
    return v.c_str();
}

struct PhysicsWorld::Impl {
    struct Joint {
        btHingeConstraint* hinge;
        btJointFeedback feedback;
        btRigidBody* child;   // Bullet's body A
        btRigidBody* parent;  // Bullet's body B
        btVector3 pivot_in_child, pivot_in_parent, axis_in_child, axis_in_parent;
    };

    // the engine's contact points (box_plane.h, box_heightfield.h)
    BoxPlaneConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    CoulombSolver solver;
    btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btRigidBody>> bodies;  // robots' bodies, then dynamic boxes
    // per body, its centre of mass in its shape's frame (zero for most): Bullet's transform is
    // the centre of mass's, the engine's poses are the shape's
    std::vector<btVector3> offsets;
    std::vector<std::unique_ptr<btRigidBody>> fixed;  // floor and static boxes
    // per fixed body, what it is ("the floor", "wall 1"), or for a compound what each of its
    // children belongs to
    std::vector<std::vector<std::string>> fixed_names;
    std::vector<std::unique_ptr<btHingeConstraint>> hinges;
    std::vector<Joint> joints;
    // the bodies of robots whose bodies do not collide with each other (self_collision off),
    // each body's robot, and the pairs of them exempt from deepest_self_pass (sorted): those a
    // joint joins and those that overlap as built. Where one of the other pairs enters the
    // other, the robot passes through itself
    std::vector<int> self_bodies;
    std::vector<int> robot_of;
    std::vector<std::pair<int, int>> self_exempt;
    bool self_pass_possible = false;

    ~Impl() {
        for (auto& h : hinges)
            world.removeConstraint(h.get());
        for (auto& b : bodies)
            world.removeRigidBody(b.get());
        for (auto& b : fixed)
            world.removeRigidBody(b.get());
    }

    std::vector<std::unique_ptr<std::vector<float>>> height_data;  // of heightfield shapes

    // one static body for `group`, static solids of one friction and no heightfield
    void add_compound(const std::vector<Solid>& solids, std::vector<size_t> group) {
        // the compound's tree of children grows by insertion without rebalancing: solids in
        // spatial order (a row of boxes, a grid) would make it a list and every insertion
        // linear. In a fixed shuffled order it stays shallow (as a random binary tree does)
        detail::SplitMix64 rng(group.size());
        for (size_t k = group.size(); k > 1; --k)
            std::swap(group[k - 1], group[static_cast<size_t>(rng.next() % k)]);
        auto compound = std::make_unique<btCompoundShape>(true, static_cast<int>(group.size()));
        std::vector<std::string> names;
        for (size_t k : group) {
            auto child = make_shape(solids[k], nullptr);
            compound->addChildShape(body_transform(solids[k]), child.get());
            shapes.push_back(std::move(child));
            names.push_back(solids[k].object);
        }
        compound->setMargin(kMargin);
        btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, compound.get());
        info.m_friction = btScalar(solids[group.front()].friction);
        info.m_restitution = 0;
        auto body = std::make_unique<btRigidBody>(info);
        contact_values_neutral(*body);
        body->setUserIndex(-2 - static_cast<int>(fixed.size()));
        world.addRigidBody(body.get(), btBroadphaseProxy::StaticFilter,
                           btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
        fixed.push_back(std::move(body));
        fixed_names.push_back(std::move(names));
        shapes.push_back(std::move(compound));
    }

    btRigidBody* add_body(const Solid& solid, int group, int mask) {
        // a heightfield shape points into its samples, which live as long as the world
        std::vector<float>* heights = nullptr;
        if (solid.kind == Solid::Kind::heightfield) {
            height_data.push_back(std::make_unique<std::vector<float>>());
            heights = height_data.back().get();
        }
        auto shape = make_shape(solid, heights);
        const double mass = solid.mass;
        btVector3 inertia(0, 0, 0);
        if (solid.inertia) {
            inertia = to_bt(*solid.inertia);
        } else if (mass > 0) {
            // the shape's own (about its centre), also for a body whose centre of mass is
            // elsewhere: taken as about that (robot.h)
            shape->calculateLocalInertia(btScalar(mass), inertia);
        }
        btTransform start = body_transform(solid);
        btVector3 offset(0, 0, 0);
        // a body without a centre of mass, or with it at its shape's centre, keeps its plain
        // shape, and with it every bit of its motion (and the box colliders, which the compound
        // would not take)
        if (solid.center_of_mass && !to_bt(*solid.center_of_mass).isZero()) {
            offset = to_bt(*solid.center_of_mass);
            auto compound = std::make_unique<OffsetShape>(offset, shape.get());
            shapes.push_back(std::move(shape));
            shape = std::move(compound);
            start.setOrigin(start * offset);
        }
        btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), nullptr, shape.get(),
                                                      inertia);
        info.m_startWorldTransform = start;
        info.m_friction = btScalar(solid.friction);
        info.m_restitution = 0;
        auto body = std::make_unique<btRigidBody>(info);
        contact_values_neutral(*body);
        btRigidBody* raw = body.get();
        // the first user index numbers the bodies: dynamic ones from 0 (as body() does),
        // fixed ones from -2 down (fixed[k] is -2 - k), for overlap reports
        if (mass > 0) {
            raw->setActivationState(DISABLE_DEACTIVATION);
            raw->setUserIndex(static_cast<int>(bodies.size()));
            bodies.push_back(std::move(body));
            offsets.push_back(offset);
        } else {
            raw->setUserIndex(-2 - static_cast<int>(fixed.size()));
            fixed.push_back(std::move(body));
            fixed_names.push_back({solid.object});
        }
        shapes.push_back(std::move(shape));
        world.addRigidBody(raw, group, mask);
        return raw;
    }
};

PhysicsWorld::PhysicsWorld(const WorldSpec& spec, double dt, int solver_iterations,
                           ConstraintSolver solver, int newton_steps)
    : impl_(std::make_unique<Impl>()) {
    Impl& s = *impl_;
    s.world.setGravity(to_bt(spec.gravity));
    s.world.getSolverInfo().m_numIterations = solver_iterations;
    s.solver.set_method(solver == ConstraintSolver::block_nncg ? SolverMethod::block_nncg
                                                               : SolverMethod::pgs);
    s.solver.set_newton_steps(solver == ConstraintSolver::block_nncg ? newton_steps : 0);
    // friction: CoulombSolver (one row where a contact slides, two where it does not)
    // only bodies that move get their bounding boxes updated each step. Bullet's default
    // updates every body's, static ones included, and each update of a static body moves its
    // broadphase proxy from the fixed tree back to the dynamic one and collides it with
    // everything there: with many static objects (a rubble field) every step cost time
    // quadratic in their number. Static bodies never move here, and dynamic ones never sleep
    // (DISABLE_DEACTIVATION), so the default bought nothing.
    s.world.setForceUpdateAllAabbs(false);

    if (spec.floor.enabled) {
        auto plane = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), btScalar(0));
        btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, plane.get());
        info.m_friction = btScalar(spec.floor.friction);
        auto floor = std::make_unique<btRigidBody>(info);
        // a compliant floor: Bullet makes each contact point with it an implicit spring-damper
        // (its row's cfm = 1/(dt k + c), erp = dt k/(dt k + c)) from the two bodies' values,
        // combined as k = 1/(1/k0 + 1/k1) and c = c0 + c1; every other body has k = infinity
        // and c = 0 (contact_values_neutral), so the floor's values are the contact's own
        // (the stiffness as 1/(1/k) in single precision: k, or one unit in the last place off)
        if (!spec.floor.rigid) {
            floor->setContactStiffnessAndDamping(
                btScalar(spec.floor.stiffness.value_or(kDefaultFloorStiffness)),
                btScalar(spec.floor.damping.value_or(kDefaultFloorDamping)));
        }
        floor->setUserIndex(-2);
        s.world.addRigidBody(floor.get(), btBroadphaseProxy::StaticFilter,
                             btBroadphaseProxy::AllFilter);
        s.fixed.push_back(std::move(floor));
        s.fixed_names.push_back({"the floor"});
        s.shapes.push_back(std::move(plane));
    }

    for (size_t r = 0; r < spec.robots.size(); ++r) {
        const PlacedRobot& placed = spec.robots[r];
        const RobotSpec& robot = placed.robot;
        const int bit = 1 << (kFirstRobotBit + static_cast<int>(r % kRobotBits));
        const int mask = robot.self_collision ? btBroadphaseProxy::AllFilter
                                              : (btBroadphaseProxy::AllFilter & ~bit);
        const size_t first = s.bodies.size();
        for (size_t b = 0; b < robot.bodies.size(); ++b) {
            const Pose& local = robot.bodies[b].pose;
            const Pose world_pose{placed.pose.apply(local.position),
                                  placed.pose.orientation * local.orientation};
            s.add_body(body_solid(robot, static_cast<int>(b), world_pose), bit, mask);
        }
        for (const JointSpec& j : robot.joints) {
            btRigidBody* child = s.bodies[first + static_cast<size_t>(j.child)].get();
            btRigidBody* parent = s.bodies[first + static_cast<size_t>(j.parent)].get();
            const btVector3 pivot = to_bt(placed.pose.apply(j.pivot));
            const btVector3 axis = to_bt(placed.pose.orientation.rotate(j.axis));
            Impl::Joint joint{};
            joint.child = child;
            joint.parent = parent;
            joint.pivot_in_child = child->getWorldTransform().inverse() * pivot;
            joint.pivot_in_parent = parent->getWorldTransform().inverse() * pivot;
            joint.axis_in_child = child->getWorldTransform().getBasis().transpose() * axis;
            joint.axis_in_parent = parent->getWorldTransform().getBasis().transpose() * axis;
            // body A is the child, so the hinge angle is the child's rotation about the axis
            // relative to the parent, which is the sign convention of the public API
            auto hinge = std::make_unique<btHingeConstraint>(
                *child, *parent, joint.pivot_in_child, joint.pivot_in_parent, joint.axis_in_child,
                joint.axis_in_parent);
            hinge->setLimit(btScalar(j.min_angle), btScalar(j.max_angle));
            hinge->enableAngularMotor(true, 0, btScalar(j.servo.max_torque * dt));
            joint.hinge = hinge.get();
            // the solver's order of joints (CoulombSolver::solveGroup)
            hinge->setUserConstraintId(static_cast<int>(s.joints.size()));
            s.world.addConstraint(hinge.get(), /*disableCollisionsBetweenLinkedBodies=*/true);
            s.hinges.push_back(std::move(hinge));
            s.joints.push_back(joint);
        }
    }
    // feedback pointers must stay put: set them once the joints vector is complete. Bullet
    // leaves the feedback uninitialized until the first step: zero, so torques read before it
    // (a recording's first row) are 0, not whatever the memory held
    for (Impl::Joint& j : s.joints) {
        const btVector3 zero(0, 0, 0);
        j.feedback.m_appliedForceBodyA = zero;
        j.feedback.m_appliedTorqueBodyA = zero;
        j.feedback.m_appliedForceBodyB = zero;
        j.feedback.m_appliedTorqueBodyB = zero;
        j.hinge->setJointFeedback(&j.feedback);
        j.hinge->enableFeedback(true);
    }

    first_object_body_ = static_cast<int>(s.bodies.size());
    find_self_pairs(spec);
    // the world's objects, expanded into solids only now (a heightfield reads its image here).
    // The static solids of one friction (all but heightfields) are one body of one compound
    // shape: they never enter the broadphase one by one, so building and stepping a world of
    // 100 000 static boxes or stones (which Bullet would pair with each other on insertion,
    // however many overlap) costs what one body costs there, and a robot's body meets only the
    // solids its bounding box overlaps (the compound's own tree finds them)
    const std::vector<Solid> solids = world_solids(spec);
    std::map<double, std::vector<size_t>> by_friction;
    for (size_t k = 0; k < solids.size(); ++k) {
        const Solid& solid = solids[k];
        if (solid.mass > 0) {
            s.add_body(solid, btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
        } else if (solid.kind == Solid::Kind::heightfield) {
            s.add_body(solid, btBroadphaseProxy::StaticFilter,
                       btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
        } else {
            by_friction[solid.friction].push_back(k);
        }
    }
    for (const auto& [friction, group] : by_friction)
        s.add_compound(solids, group);
}

PhysicsWorld::~PhysicsWorld() = default;

int PhysicsWorld::body_count() const {
    return static_cast<int>(impl_->bodies.size());
}
int PhysicsWorld::joint_count() const {
    return static_cast<int>(impl_->joints.size());
}

void PhysicsWorld::read_angles(double* out) const {
    for (const Impl::Joint& j : impl_->joints)
        *out++ = j.hinge->getHingeAngle();
}

double PhysicsWorld::angle(int joint) const {
    return impl_->joints[static_cast<size_t>(joint)].hinge->getHingeAngle();
}

double PhysicsWorld::velocity(int joint) const {
    const Impl::Joint& j = impl_->joints[static_cast<size_t>(joint)];
    const btVector3 axis = j.child->getWorldTransform().getBasis() * j.axis_in_child;
    return (j.child->getAngularVelocity() - j.parent->getAngularVelocity()).dot(axis);
}

double PhysicsWorld::torque(int joint) const {
    // the feedback holds the whole constraint wrench on the child; removing the moment of the
    // pivot force leaves the angular rows, whose component along the axis is the motor's
    const Impl::Joint& j = impl_->joints[static_cast<size_t>(joint)];
    const btTransform& t = j.child->getWorldTransform();
    const btVector3 arm = t.getBasis() * j.pivot_in_child;
    const btVector3 axis = t.getBasis() * j.axis_in_child;
    const btVector3 angular =
        j.feedback.m_appliedTorqueBodyA - arm.cross(j.feedback.m_appliedForceBodyA);
    return angular.dot(axis);
}

void PhysicsWorld::set_motor_velocities(const double* commands) {
    for (Impl::Joint& j : impl_->joints)
        j.hinge->setMotorTargetVelocity(btScalar(*commands++));
}

void PhysicsWorld::step(double dt) {
    impl_->world.stepSimulation(btScalar(dt), 0);
}

BodyState PhysicsWorld::body(int index) const {
    const btRigidBody& b = *impl_->bodies[static_cast<size_t>(index)];
    const btTransform& t = b.getWorldTransform();
    BodyState s;
    s.pose.orientation = from_bt(t.getRotation());
    s.angular_velocity = from_bt(b.getAngularVelocity());
    s.pose.position = shape_position(index);
    const btVector3& offset = impl_->offsets[static_cast<size_t>(index)];
    // the shape's centre moves as the point behind the centre of mass by the offset, turned
    // with the body
    s.linear_velocity =
        from_bt(offset.isZero() ? b.getLinearVelocity()
                                : b.getVelocityInLocalPoint(t.getBasis() * -offset));
    return s;
}

Vec3 PhysicsWorld::position(int index) const {
    return from_bt(impl_->bodies[static_cast<size_t>(index)]->getWorldTransform().getOrigin());
}

Vec3 PhysicsWorld::shape_position(int index) const {
    const btTransform& t = impl_->bodies[static_cast<size_t>(index)]->getWorldTransform();
    const btVector3& offset = impl_->offsets[static_cast<size_t>(index)];
    if (offset.isZero()) return from_bt(t.getOrigin());
    return from_bt(t * -offset);
}

Vec3 PhysicsWorld::mass_velocity(int index) const {
    return from_bt(impl_->bodies[static_cast<size_t>(index)]->getLinearVelocity());
}

Vec3 PhysicsWorld::center_of_mass(int index) const {
    return from_bt(impl_->offsets[static_cast<size_t>(index)]);
}

double PhysicsWorld::speed(int index) const {
    return impl_->bodies[static_cast<size_t>(index)]->getLinearVelocity().length();
}

int PhysicsWorld::first_diverged(double max_distance, double max_speed) const {
    const btScalar d2 = btScalar(max_distance * max_distance);
    const btScalar v2 = btScalar(max_speed * max_speed);
    const auto& bodies = impl_->bodies;
    for (size_t i = 0; i < bodies.size(); ++i) {
        const btRigidBody& b = *bodies[i];
        const btTransform& t = b.getWorldTransform();
        const btVector3& p = t.getOrigin();
        const btVector3& v = b.getLinearVelocity();
        const btVector3& w = b.getAngularVelocity();
        const btMatrix3x3& r = t.getBasis();
        // one sum is not finite if any term is NaN or infinite
        const btScalar all = w.x() + w.y() + w.z() + r[0].x() + r[0].y() + r[0].z() + r[1].x() +
                             r[1].y() + r[1].z() + r[2].x() + r[2].y() + r[2].z();
        // comparisons with NaN are false: a NaN position or velocity fails them too
        if (!(p.length2() < d2 && v.length2() < v2 && std::isfinite(all))) {
            return static_cast<int>(i);
        }
    }
    return -1;
}

std::optional<PhysicsWorld::Overlap> PhysicsWorld::deepest_robot_overlap(double tolerance) const {
    // only what the body collides with: a robot's own bodies (which do not collide unless
    // self_collision is on, and never across a joint) are not reported. Bullet's contact test
    // filters by the callback's group and mask, not the body's: the test asks the body's own
    struct Deepest : btCollisionWorld::ContactResultCallback {
        const btCollisionObject* body = nullptr;
        int self = -1;
        int other = 0;  // user index of the other body
        int child = 0;  // the child of the other body's compound shape, if it is one
        btScalar depth = 0;
        bool needsCollision(btBroadphaseProxy* proxy) const override {
            const btBroadphaseProxy& mine = *body->getBroadphaseHandle();
            return (mine.m_collisionFilterGroup & proxy->m_collisionFilterMask) != 0 &&
                   (proxy->m_collisionFilterGroup & mine.m_collisionFilterMask) != 0 &&
                   body->checkCollideWith(
                       static_cast<const btCollisionObject*>(proxy->m_clientObject));
        }
        btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper* a, int,
                                 int index_a, const btCollisionObjectWrapper* b, int,
                                 int index_b) override {
            const bool a_is_self = a->getCollisionObject()->getUserIndex() == self;
            const btCollisionObject* o =
                a_is_self ? b->getCollisionObject() : a->getCollisionObject();
            if (-cp.getDistance() > depth) {
                depth = -cp.getDistance();
                other = o->getUserIndex();
                child = a_is_self ? index_b : index_a;
            }
            return 0;
        }
    };
    std::optional<Overlap> out;
    const int robot_bodies = first_object_body_;
    for (int b = 0; b < robot_bodies; ++b) {
        Deepest cb;
        cb.body = impl_->bodies[static_cast<size_t>(b)].get();
        cb.self = b;
        cb.depth = btScalar(tolerance);
        impl_->world.contactTest(impl_->bodies[static_cast<size_t>(b)].get(), cb);
        if (cb.depth > btScalar(tolerance) && (!out || cb.depth > out->depth)) {
            Overlap o;
            o.body = b;
            o.depth = cb.depth;
            if (cb.other >= 0) {
                o.other_body = cb.other;
            } else {
                const auto& names = impl_->fixed_names[static_cast<size_t>(-2 - cb.other)];
                const size_t child = static_cast<size_t>(std::max(cb.child, 0));
                o.other = names.size() == 1 || child >= names.size() ? names.front() : names[child];
            }
            out = o;
        }
    }
    return out;
}

namespace {

// the deepest penetration of a contact test, > 0, or 0
struct PenetrationDepth : btCollisionWorld::ContactResultCallback {
    btScalar depth = 0;
    btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int,
                             const btCollisionObjectWrapper*, int, int) override {
        depth = std::max(depth, -cp.getDistance());
        return 0;
    }
};

bool aabbs_overlap(const btRigidBody& a, const btRigidBody& b) {
    const btBroadphaseProxy& p = *a.getBroadphaseHandle();
    const btBroadphaseProxy& q = *b.getBroadphaseHandle();
    return TestAabbAgainstAabb2(p.m_aabbMin, p.m_aabbMax, q.m_aabbMin, q.m_aabbMax);
}

// calls visit(a, b) for the pairs of `bodies` of one robot (robot_of) whose bounding boxes
// overlap, a < b: sorted along x and swept, so a chain of 1000 modules costs its n log n and
// the pairs that are near, not its half a million pairs
template <class Visit>
void near_pairs(const std::vector<std::unique_ptr<btRigidBody>>& all,
                const std::vector<int>& bodies, const std::vector<int>& robot_of, Visit&& visit) {
    // (lower x, body), a box that is not finite last: the order stays strict whatever the state
    std::vector<std::pair<btScalar, int>> by_x;
    by_x.reserve(bodies.size());
    for (int b : bodies) {
        const btScalar lo = all[static_cast<size_t>(b)]->getBroadphaseHandle()->m_aabbMin.x();
        by_x.emplace_back(std::isfinite(lo) ? lo : std::numeric_limits<btScalar>::infinity(), b);
    }
    std::sort(by_x.begin(), by_x.end());
    for (size_t i = 0; i < by_x.size(); ++i) {
        const btRigidBody& bi = *all[static_cast<size_t>(by_x[i].second)];
        const btScalar hi = bi.getBroadphaseHandle()->m_aabbMax.x();
        for (size_t j = i + 1; j < by_x.size() && by_x[j].first <= hi; ++j) {
            const int a = std::min(by_x[i].second, by_x[j].second);
            const int b = std::max(by_x[i].second, by_x[j].second);
            if (robot_of[static_cast<size_t>(a)] == robot_of[static_cast<size_t>(b)] &&
                aabbs_overlap(bi, *all[static_cast<size_t>(by_x[j].second)])) {
                visit(a, b);
            }
        }
    }
}

}  // namespace

void PhysicsWorld::find_self_pairs(const WorldSpec& spec) {
    Impl& s = *impl_;
    s.robot_of.assign(s.bodies.size(), -1);
    size_t first = 0;
    size_t pairs = 0;  // of bodies that do not collide with each other
    for (size_t r = 0; r < spec.robots.size(); ++r) {
        const RobotSpec& robot = spec.robots[r].robot;
        const size_t n = robot.bodies.size();
        if (!robot.self_collision) {
            for (size_t b = 0; b < n; ++b) {
                s.self_bodies.push_back(static_cast<int>(first + b));
                s.robot_of[first + b] = static_cast<int>(r);
            }
            for (const JointSpec& j : robot.joints) {
                const int a = static_cast<int>(first) + j.child;
                const int b = static_cast<int>(first) + j.parent;
                if (a != b) s.self_exempt.emplace_back(std::min(a, b), std::max(a, b));
            }
            pairs += n * (n - 1) / 2;
        }
        first += n;
    }
    near_pairs(s.bodies, s.self_bodies, s.robot_of, [&](int a, int b) {
        PenetrationDepth built;
        s.world.contactPairTest(s.bodies[static_cast<size_t>(a)].get(),
                                s.bodies[static_cast<size_t>(b)].get(), built);
        if (built.depth > 0) s.self_exempt.emplace_back(a, b);
    });
    std::sort(s.self_exempt.begin(), s.self_exempt.end());
    s.self_exempt.erase(std::unique(s.self_exempt.begin(), s.self_exempt.end()),
                        s.self_exempt.end());
    s.self_pass_possible = pairs > s.self_exempt.size();
}

bool PhysicsWorld::may_pass_through_itself() const {
    return impl_->self_pass_possible;
}

std::optional<PhysicsWorld::Overlap> PhysicsWorld::deepest_self_pass(double tolerance) const {
    const Impl& s = *impl_;
    std::optional<Overlap> out;
    near_pairs(s.bodies, s.self_bodies, s.robot_of, [&](int a, int b) {
        if (std::binary_search(s.self_exempt.begin(), s.self_exempt.end(), std::make_pair(a, b)))
            return;
        PenetrationDepth cb;
        impl_->world.contactPairTest(s.bodies[static_cast<size_t>(a)].get(),
                                     s.bodies[static_cast<size_t>(b)].get(), cb);
        if (cb.depth > btScalar(tolerance) && (!out || cb.depth > out->depth)) {
            out = Overlap{};
            out->body = a;
            out->other_body = b;
            out->depth = cb.depth;
        }
    });
    return out;
}

JointError PhysicsWorld::joint_error(int joint) const {
    const Impl::Joint& j = impl_->joints[static_cast<size_t>(joint)];
    const btTransform& c = j.child->getWorldTransform();
    const btTransform& p = j.parent->getWorldTransform();
    JointError e;
    e.separation = (c * j.pivot_in_child - p * j.pivot_in_parent).length();
    const btVector3 a = c.getBasis() * j.axis_in_child, b = p.getBasis() * j.axis_in_parent;
    e.axis_angle = std::atan2(a.cross(b).length(), a.dot(b));
    return e;
}

int PhysicsWorld::contact_count() const {
    int n = 0;
    btDispatcher& d = impl_->dispatcher;
    for (int i = 0; i < d.getNumManifolds(); ++i) {
        n += d.getManifoldByIndexInternal(i)->getNumContacts();
    }
    return n;
}

void PhysicsWorld::copy_state_from(const PhysicsWorld& from, double impulse_scale) {
    Impl& s = *impl_;
    const Impl& o = *from.impl_;
    if (s.bodies.size() != o.bodies.size() || s.fixed.size() != o.fixed.size() ||
        s.joints.size() != o.joints.size()) {
        throw Error(
            "cannot copy a physics state between worlds of different bodies or joints (an "
            "internal error: a copy is built from its original's spec)");
    }
    // the same body in both worlds: robots' bodies and dynamic objects, then fixed bodies, in
    // build order
    std::unordered_map<const btCollisionObject*, btCollisionObject*> same;
    for (size_t i = 0; i < o.bodies.size(); ++i)
        same[o.bodies[i].get()] = s.bodies[i].get();
    for (size_t i = 0; i < o.fixed.size(); ++i)
        same[o.fixed[i].get()] = s.fixed[i].get();

    for (size_t i = 0; i < o.bodies.size(); ++i) {
        const btRigidBody& a = *o.bodies[i];
        btRigidBody& b = *s.bodies[i];
        // the world inertia tensor is recomputed from the same transform: the same bits
        b.setCenterOfMassTransform(a.getCenterOfMassTransform());
        b.setLinearVelocity(a.getLinearVelocity());
        b.setAngularVelocity(a.getAngularVelocity());
        b.setInterpolationWorldTransform(a.getInterpolationWorldTransform());
        b.setInterpolationLinearVelocity(a.getInterpolationLinearVelocity());
        b.setInterpolationAngularVelocity(a.getInterpolationAngularVelocity());
        b.setDeactivationTime(a.getDeactivationTime());
        b.setHitFraction(a.getHitFraction());
        b.forceActivationState(a.getActivationState());
    }
    for (size_t j = 0; j < o.joints.size(); ++j) {
        btHingeConstraint& from_hinge = *o.joints[j].hinge;
        s.joints[j].hinge->setMotorTargetVelocity(from_hinge.getMotorTargetVelocity());
        s.joints[j].feedback = o.joints[j].feedback;
        btScalar impulse = from_hinge.getAppliedImpulse();
        if (impulse_scale != 1) impulse *= static_cast<btScalar>(impulse_scale);
        s.joints[j].hinge->internalSetAppliedImpulse(impulse);
    }
    s.solver.setRandSeed(o.solver.getRandSeed());

    // the broadphase finds the pairs of the bodies where they are now; then they are put in
    // the original's order, which is the order contacts are generated and solved in
    s.world.updateAabbs();
    btOverlappingPairCache& pairs = *s.world.getBroadphase()->getOverlappingPairCache();
    for (const auto& list : {&s.bodies, &s.fixed}) {
        for (const auto& b : *list)
            pairs.removeOverlappingPairsContainingProxy(b->getBroadphaseHandle(), &s.dispatcher);
    }
    // Bullet offers no const access to the pairs; nothing here changes them
    btBroadphaseInterface& from_broadphase = const_cast<btDbvtBroadphase&>(o.broadphase);
    const btBroadphasePairArray& from_pairs =
        from_broadphase.getOverlappingPairCache()->getOverlappingPairArray();
    const auto proxy = [&](const btBroadphaseProxy* p) {
        return same.at(static_cast<const btCollisionObject*>(p->m_clientObject))
            ->getBroadphaseHandle();
    };
    for (int i = 0; i < from_pairs.size(); ++i) {
        pairs.addOverlappingPair(proxy(from_pairs[i].m_pProxy0), proxy(from_pairs[i].m_pProxy1));
    }
    // one collision pass makes the algorithms and their contact manifolds, pair by pair;
    // their points are then replaced by the original's (positions, normals, the impulses the
    // next solve starts from, lifetimes), and the manifolds put in the original's order. A
    // manifold the original does not have (a pair that begins to touch now) is emptied: the
    // original's next step makes it then, at the end of the list, where it stays here
    s.world.performDiscreteCollisionDetection();
    const int n = s.dispatcher.getNumManifolds();
    btPersistentManifold** mine = s.dispatcher.getInternalManifoldPointer();
    std::vector<btPersistentManifold*> order;
    std::vector<char> used(static_cast<size_t>(n), 0);
    for (int i = 0; i < o.dispatcher.getNumManifolds(); ++i) {
        const btPersistentManifold& from_m = *o.dispatcher.getManifoldByIndexInternal(i);
        const btCollisionObject* b0 = same.at(from_m.getBody0());
        const btCollisionObject* b1 = same.at(from_m.getBody1());
        for (int k = 0; k < n; ++k) {
            btPersistentManifold& m = *mine[k];
            if (used[static_cast<size_t>(k)] || m.getBody0() != b0 || m.getBody1() != b1) continue;
            used[static_cast<size_t>(k)] = 1;
            m.clearManifold();
            m.setNumContacts(from_m.getNumContacts());
            for (int p = 0; p < from_m.getNumContacts(); ++p) {
                btManifoldPoint& point = m.getContactPoint(p);
                point = from_m.getContactPoint(p);
                point.m_userPersistentData = nullptr;
                if (impulse_scale != 1) {
                    const auto scale = static_cast<btScalar>(impulse_scale);
                    point.m_appliedImpulse *= scale;
                    point.m_appliedImpulseLateral1 *= scale;
                    point.m_appliedImpulseLateral2 *= scale;
                }
            }
            order.push_back(&m);
            break;
        }
    }
    for (int k = 0; k < n; ++k) {
        if (used[static_cast<size_t>(k)]) continue;
        mine[k]->clearManifold();
        order.push_back(mine[k]);
    }
    for (int k = 0; k < n; ++k) {
        mine[k] = order[static_cast<size_t>(k)];
        mine[k]->m_index1a = k;
    }
}

void PhysicsWorld::contacts(std::vector<ContactPoint>& out, double dt) const {
    out.clear();
    btDispatcher& d = impl_->dispatcher;
    for (int i = 0; i < d.getNumManifolds(); ++i) {
        const btPersistentManifold* m = d.getManifoldByIndexInternal(i);
        for (int k = 0; k < m->getNumContacts(); ++k) {
            const btManifoldPoint& p = m->getContactPoint(k);
            // Bullet keeps points a little apart too (they may touch next step): not contacts
            if (p.getDistance() > 0.001) continue;
            const btVector3& at = p.getPositionWorldOnB();
            const btVector3& n = p.m_normalWorldOnB;
            // the normal points from body B into body A: the friction on A, A's slip over B
            const btVector3 f = p.m_lateralFrictionDir1 * p.m_appliedImpulseLateral1 +
                                p.m_lateralFrictionDir2 * p.m_appliedImpulseLateral2;
            const auto* a = btRigidBody::upcast(m->getBody0());
            const auto* b = btRigidBody::upcast(m->getBody1());
            btVector3 v(0, 0, 0);
            if (a)
                v += a->getVelocityInLocalPoint(p.getPositionWorldOnA() -
                                                a->getCenterOfMassPosition());
            if (b) v -= b->getVelocityInLocalPoint(at - b->getCenterOfMassPosition());
            const btVector3 slip = v - n * n.dot(v);
            ContactPoint c;
            c.position = from_bt(at);
            c.normal = from_bt(n);
            c.force = dt > 0 ? p.getAppliedImpulse() / dt : 0.0;
            c.friction = dt > 0 ? from_bt(f / btScalar(dt)) : Vec3{};
            c.slip = from_bt(slip);
            out.push_back(c);
        }
    }
}

btDiscreteDynamicsWorld& PhysicsWorld::bullet_world() const {
    return impl_->world;
}

btRigidBody& PhysicsWorld::bullet_body(int body) const {
    return *impl_->bodies[static_cast<size_t>(body)];
}

}  // namespace gaitlab
