// Tests for the engine's box colliders (engine/src/bullet/box_collider.h, box_plane.h,
// box_heightfield.h), called directly through Bullet's dispatcher as a step calls them: a box
// whose transform is not finite (NaN or infinite position, NaN orientation, as in the step
// before a diverged simulation is stopped) gets no contact point from the plane or the
// heightfield, and the points it held before are dropped (a box-plane pair once kept them at
// depth -inf when the box went to z = -inf). Built under the sanitizer preset this also checks that
// the colliders' arithmetic on such a box stays defined (float-to-int conversions included, see
// tests/engine/CMakeLists.txt).
#include <catch2/catch.hpp>

#include <limits>
#include <vector>

#include "bullet/box_plane.h"

using namespace gaitlab;

namespace {

constexpr btScalar kNaN = std::numeric_limits<btScalar>::quiet_NaN();
constexpr btScalar kInf = std::numeric_limits<btScalar>::infinity();
constexpr btScalar kMargin = btScalar(0.001);  // as the engine sets it (physics_world.cpp)

// the box's position: a finite place offset by `bad` (what is not finite in it); `turn_nan`:
// its orientation NaN too (a NaN quaternion, as a diverged step leaves it)
struct BadPosition {
    const char* name;
    btVector3 bad;
    bool turn_nan = false;
};

const std::vector<BadPosition>& bad_positions() {
    static const std::vector<BadPosition> all = {
        {"x NaN", {kNaN, 0, 0}},
        {"y NaN", {0, kNaN, 0}},
        {"z NaN", {0, 0, kNaN}},
        {"all NaN", {kNaN, kNaN, kNaN}},
        {"x +inf", {kInf, 0, 0}},
        {"x -inf", {-kInf, 0, 0}},
        {"y +inf", {0, kInf, 0}},
        {"y -inf", {0, -kInf, 0}},
        {"z +inf", {0, 0, kInf}},
        {"z -inf", {0, 0, -kInf}},
        {"x, y -inf", {-kInf, -kInf, 0}},
        {"x +inf, z -inf", {kInf, 0, -kInf}},
        {"all +inf", {kInf, kInf, kInf}},
        {"all -inf", {-kInf, -kInf, -kInf}},
        {"orientation NaN", {0, 0, 0}, true},
    };
    return all;
}

// A box and another static shape in the engine's collision configuration, their algorithm made
// by the dispatcher as for a pair the broadphase found (the box first or second: `swapped`).
class Pair {
  public:
    Pair(btCollisionShape& other, const btTransform& other_at, bool swapped)
        : dispatcher_(&config_), box_shape_(btVector3(0.026f, 0.026f, 0.018f)), swapped_(swapped) {
        box_shape_.setMargin(kMargin);
        box_.setCollisionShape(&box_shape_);
        other_.setCollisionShape(&other);
        other_.setWorldTransform(other_at);
        other_.setCollisionFlags(btCollisionObject::CF_STATIC_OBJECT);
        box_.setWorldTransform(btTransform::getIdentity());
        const Wrappers w(*this);
        algorithm_ =
            dispatcher_.findAlgorithm(w.first(), w.second(), nullptr, BT_CONTACT_POINT_ALGORITHMS);
    }
    ~Pair() {
        algorithm_->~btCollisionAlgorithm();
        dispatcher_.freeCollisionAlgorithm(algorithm_);
    }
    Pair(const Pair&) = delete;
    Pair& operator=(const Pair&) = delete;

    btCollisionAlgorithm* algorithm() const { return algorithm_; }
    btScalar half_height() const { return box_shape_.getHalfExtentsWithMargin().z(); }

    // one step's collision of the box at `at`: the number of points the pair's manifold holds
    int collide(const btTransform& at) {
        box_.setWorldTransform(at);
        const Wrappers w(*this);
        btManifoldResult result(w.first(), w.second());
        algorithm_->processCollision(w.first(), w.second(), btDispatcherInfo(), &result);
        btManifoldArray manifolds;
        algorithm_->getAllContactManifolds(manifolds);
        int n = 0;
        for (int i = 0; i < manifolds.size(); ++i)
            n += manifolds[i]->getNumContacts();
        return n;
    }

  private:
    // the two objects as a step hands them to the algorithm, in the pair's order
    struct Wrappers {
        btCollisionObjectWrapper box, other;
        bool swapped;
        explicit Wrappers(const Pair& p)
            : box(nullptr, p.box_.getCollisionShape(), &p.box_, p.box_.getWorldTransform(), -1, -1),
              other(nullptr, p.other_.getCollisionShape(), &p.other_, p.other_.getWorldTransform(),
                    -1, -1),
              swapped(p.swapped_) {}
        const btCollisionObjectWrapper* first() const { return swapped ? &other : &box; }
        const btCollisionObjectWrapper* second() const { return swapped ? &box : &other; }
    };

    BoxPlaneConfiguration config_;
    btCollisionDispatcher dispatcher_;
    btBoxShape box_shape_;
    btCollisionObject box_, other_;
    bool swapped_;
    btCollisionAlgorithm* algorithm_ = nullptr;
};

btTransform at(const btVector3& p, const btQuaternion& q = btQuaternion::getIdentity()) {
    return btTransform(q, p);
}

// the box resting at `rest` with orientation `q` (it touches there), then at every bad position:
// no point from a fresh algorithm, and none left in the manifold of one that held the resting
// points
void check_not_finite(btCollisionShape& other, const btTransform& other_at, const btVector3& rest,
                      const btQuaternion& q) {
    for (const bool swapped : {false, true}) {
        for (const BadPosition& b : bad_positions()) {
            CAPTURE(swapped, b.name);
            const btTransform bad =
                at(rest + b.bad, b.turn_nan ? btQuaternion(kNaN, kNaN, kNaN, kNaN) : q);
            {
                Pair fresh(other, other_at, swapped);
                CHECK(fresh.collide(bad) == 0);
            }
            Pair held(other, other_at, swapped);
            REQUIRE(held.collide(at(rest, q)) > 0);
            CHECK(held.collide(bad) == 0);
            // and the pair recovers when the box is back
            CHECK(held.collide(at(rest, q)) > 0);
        }
    }
}

}  // namespace

TEST_CASE("the box-plane collider gives a box that is not finite no contact") {
    btStaticPlaneShape floor(btVector3(0, 0, 1), 0);
    floor.setMargin(kMargin);
    const btTransform floor_at = at(btVector3(0.3f, -0.2f, 0.01f));
    {
        Pair p(floor, floor_at, false);
        REQUIRE(dynamic_cast<BoxPlaneAlgorithm*>(p.algorithm()) != nullptr);
    }
    Pair probe(floor, floor_at, false);
    const btScalar z = btScalar(0.01) + probe.half_height() - btScalar(0.0005);
    SECTION("lying flat") {
        check_not_finite(floor, floor_at, btVector3(0.1f, 0.05f, z), btQuaternion::getIdentity());
    }
    SECTION("tilted onto an edge") {
        const btQuaternion q(btVector3(1, 1, 0).normalized(), btScalar(0.3));
        check_not_finite(floor, floor_at, btVector3(0.1f, 0.05f, z), q);
    }
}

TEST_CASE("the box-heightfield collider gives a box that is not finite no contact") {
    // 7 x 6 samples 5 cm apart with bumps of up to 2 cm
    constexpr int nx = 7, ny = 6;
    std::vector<float> heights(nx * ny);
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i)
            heights[static_cast<size_t>(j * nx + i)] =
                0.02f * static_cast<float>((i * 3 + j) % 5) / 4;
    }
    HeightfieldShape field(nx, ny, heights.data(), 0, btScalar(0.02));
    field.setLocalScaling(btVector3(0.05f, 0.05f, 1));
    field.setMargin(kMargin);
    const btTransform field_at =
        at(btVector3(0.2f, 0.1f, 0.01f), btQuaternion(btVector3(0, 0, 1), btScalar(0.4)));
    {
        Pair p(field, field_at, false);
        REQUIRE(dynamic_cast<BoxHeightfieldAlgorithm*>(p.algorithm()) != nullptr);
    }
    // the box resting on grid point (3, 2): its centre a half height above it
    btVector3 v;
    field.getVertex(3, 2, v);
    Pair probe(field, field_at, false);
    const btVector3 rest = field_at * (v + btVector3(0, 0, probe.half_height() - 0.0005f));
    SECTION("lying flat") {
        check_not_finite(field, field_at, rest, field_at.getRotation());
    }
    SECTION("tilted onto an edge") {
        const btQuaternion q =
            field_at.getRotation() * btQuaternion(btVector3(1, 0, 0), btScalar(0.25));
        check_not_finite(field, field_at, rest, q);
    }
}
