// Tests for engine/src/spec/geometry.cpp: the world library's objects expand into the solids their
// parameters say, heightfield images become grids the right way round, and triangles enclose
// the solids.
#include "gaitlab/geometry.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "engine/png_support.h"
#include "gaitlab/error.h"

using namespace gaitlab;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

namespace {

// volume enclosed by triangles (divergence theorem): positive only if they face outwards
double enclosed_volume(const std::vector<Triangle>& tris) {
    double v = 0;
    for (const Triangle& t : tris)
        v += t.a.dot(t.b.cross(t.c)) / 6;
    return v;
}

// the lowest and highest z of the triangles
std::pair<double, double> z_range(const std::vector<Triangle>& tris) {
    double lo = 1e30, hi = -1e30;
    for (const Triangle& t : tris) {
        for (const Vec3& p : {t.a, t.b, t.c}) {
            lo = std::min(lo, p.z);
            hi = std::max(hi, p.z);
        }
    }
    return {lo, hi};
}

std::vector<Solid> solids_of(const WorldSpec& w) {
    return world_solids(w);
}

}  // namespace

TEST_CASE("a world without objects has no solids") {
    CHECK(world_solids(WorldSpec{}).empty());
}

TEST_CASE("triangles enclose boxes, cylinders and convex solids, facing outwards") {
    Solid box;
    box.size = {0.3, 0.2, 0.1};
    box.pose = {{1, 2, 3}, Quat::from_axis_angle({0, 0, 1}, 0.7)};
    CHECK(triangles(box).size() == 12);
    CHECK(enclosed_volume(triangles(box)) == Approx(0.006));

    Solid cyl;
    cyl.kind = Solid::Kind::cylinder;
    cyl.size = {0.5, 0.2, 0.2};
    // a regular 24-gon of circumradius r has area 12 r² sin(15°)
    CHECK(enclosed_volume(triangles(cyl, 24)) ==
          Approx(0.5 * 12 * 0.01 * std::sin(kPi / 12)).epsilon(1e-9));
    const auto [lo, hi] = z_range(triangles(cyl));
    CHECK(lo == Approx(-0.1));
    CHECK(hi == Approx(0.1));
}

TEST_CASE("a wall stands on its base, turned by its yaw") {
    WorldSpec w;
    WallSpec wall;
    wall.length = 2;
    wall.height = 0.3;
    wall.thickness = 0.05;
    wall.position = {1, 1, 0};
    wall.yaw = kPi / 2;
    w.walls.push_back(wall);
    const std::vector<Solid> s = solids_of(w);
    REQUIRE(s.size() == 1);
    CHECK(s[0].object == "wall 1");
    CHECK(s[0].kind == Solid::Kind::box);
    CHECK(s[0].size == Vec3{2, 0.05, 0.3});
    CHECK(s[0].pose.position.z == Approx(0.15));
    // turned by 90 degrees, it runs along y
    const Vec3 along = s[0].pose.orientation.rotate({1, 0, 0});
    CHECK(along.y == Approx(1));
    CHECK(s[0].mass == 0);
}

TEST_CASE("a ramp is a wedge rising length · tan(slope) towards its +x") {
    WorldSpec w;
    RampSpec ramp;
    ramp.slope = deg_to_rad(20);
    ramp.length = 1.5;
    ramp.width = 0.4;
    ramp.position = {0.5, -0.2, 0};
    ramp.friction = 0.3;
    w.ramps.push_back(ramp);
    const std::vector<Solid> s = solids_of(w);
    REQUIRE(s.size() == 1);
    CHECK(s[0].kind == Solid::Kind::convex);
    CHECK(s[0].friction == 0.3);
    const std::vector<Triangle> t = triangles(s[0]);
    const double h = 1.5 * std::tan(deg_to_rad(20));
    CHECK(enclosed_volume(t) == Approx(1.5 * 0.4 * h / 2));
    const auto [lo, hi] = z_range(t);
    CHECK(lo == Approx(0).margin(1e-12));
    CHECK(hi == Approx(h));
    // the top edge is at the far end: x = 0.5 + 1.5
    for (const Triangle& tri : t) {
        for (const Vec3& p : {tri.a, tri.b, tri.c}) {
            if (p.z > h / 2) CHECK(p.x == Approx(2.0));
            CHECK(p.x >= 0.5 - 1e-12);
        }
    }
}

TEST_CASE("stairs have the step heights and depths given") {
    WorldSpec w;
    StairsSpec st;
    st.steps = 4;
    st.step_height = 0.03;
    st.step_depth = 0.25;
    st.width = 0.6;
    st.landing = 0.5;
    st.position = {1, 0, 0};
    w.stairs.push_back(st);
    const std::vector<Solid> s = solids_of(w);
    REQUIRE(s.size() == 4);
    for (int k = 0; k < 4; ++k) {
        CAPTURE(k);
        const Solid& step = s[static_cast<size_t>(k)];
        CHECK(step.object == "stairs 1");
        // the tread of step k + 1 is at (k + 1) · step_height, from x = 1 + k · depth
        CHECK(step.pose.position.z + step.size.z / 2 == Approx((k + 1) * 0.03));
        CHECK(step.pose.position.z - step.size.z / 2 == Approx(0).margin(1e-12));
        CHECK(step.pose.position.x - step.size.x / 2 == Approx(1 + k * 0.25));
        CHECK(step.size.x == Approx(k == 3 ? 0.75 : 0.25));
        CHECK(step.size.y == 0.6);
    }
}

TEST_CASE("cylinders stand upright or lie along their yaw") {
    WorldSpec w;
    CylinderSpec c;
    c.radius = 0.1;
    c.length = 0.4;
    c.position = {0, 0, 0.2};
    c.mass = 2;
    w.cylinders.push_back(c);
    c.lying = true;
    c.yaw = kPi / 2;
    c.position = {1, 0, 0.1};
    w.cylinders.push_back(c);
    const std::vector<Solid> s = solids_of(w);
    REQUIRE(s.size() == 2);
    CHECK(s[0].mass == 2);
    CHECK(s[1].object == "cylinder 2");
    const auto [lo0, hi0] = z_range(triangles(s[0]));
    CHECK(lo0 == Approx(0).margin(1e-12));
    CHECK(hi0 == Approx(0.4));
    const auto [lo1, hi1] = z_range(triangles(s[1]));
    CHECK(lo1 == Approx(0).margin(1e-12));
    CHECK(hi1 == Approx(0.2));
    const Vec3 axis = s[1].pose.orientation.rotate({1, 0, 0});
    CHECK(axis.y == Approx(1));
}

TEST_CASE("a pipe's walls surround a bore of the given radius, flat at the bottom") {
    WorldSpec w;
    PipeSpec p;
    p.radius = 0.08;
    p.thickness = 0.01;
    p.length = 1.2;
    p.sides = 12;
    p.position = {0.5, 0.3, 0.09};
    w.pipes.push_back(p);
    const std::vector<Solid> s = solids_of(w);
    REQUIRE(s.size() == 12);
    double nearest = 1e30, farthest = 0;
    for (const Solid& wall : s) {
        CHECK(wall.object == "pipe 1");
        // each wall's inner face touches the bore
        const Vec3 c = wall.pose.position;
        CHECK(std::hypot(c.y - 0.3, c.z - 0.09) - 0.01 / 2 == Approx(0.08));
        for (const Triangle& t : triangles(wall)) {
            for (const Vec3& v : {t.a, t.b, t.c}) {
                CHECK(v.x >= 0.5 - 1e-9);
                CHECK(v.x <= 1.7 + 1e-9);
                const double r = std::hypot(v.y - 0.3, v.z - 0.09);
                nearest = std::min(nearest, r);
                farthest = std::max(farthest, r);
            }
        }
    }
    // nothing enters the bore, the inner faces touch it, and the outer corners close the tube
    CHECK(nearest >= 0.08 - 1e-12);
    CHECK(farthest <= 0.09 / std::cos(kPi / 12) * 1.2);
    // the first wall lies flat at the bottom: its inner face is at z = 0.09 - 0.08
    CHECK(s[0].pose.position.z + 0.01 / 2 == Approx(0.09 - 0.08));
    CHECK(std::abs(s[0].pose.orientation.rotate({0, 0, 1}).z) == Approx(1));
}

TEST_CASE("a rubble field is drawn from its seed") {
    RubbleSpec r;
    r.length = 2;
    r.width = 1;
    r.count = 40;
    r.min_size = 0.02;
    r.max_size = 0.05;
    r.min_height = 0.01;
    r.max_height = 0.04;
    r.position = {3, 0, 0};
    r.seed = 7;
    WorldSpec a, b, c;
    a.rubble.push_back(r);
    b.rubble.push_back(r);
    r.seed = 8;
    c.rubble.push_back(r);
    const std::vector<Solid> sa = solids_of(a), sb = solids_of(b), sc = solids_of(c);
    REQUIRE(sa.size() == 40);
    REQUIRE(sc.size() == 40);
    int same_as_other_seed = 0;
    for (size_t k = 0; k < sa.size(); ++k) {
        CAPTURE(k);
        // the same seed gives bit-identical stones
        CHECK(sa[k].pose.position == sb[k].pose.position);
        CHECK(sa[k].pose.orientation == sb[k].pose.orientation);
        CHECK(sa[k].size == sb[k].size);
        if (sa[k].pose.position == sc[k].pose.position) ++same_as_other_seed;
        // inside the area, standing on the ground, sizes in their ranges
        const Solid& s = sa[k];
        CHECK(std::abs(s.pose.position.x - 3) <= 1);
        CHECK(std::abs(s.pose.position.y) <= 0.5);
        CHECK(s.pose.position.z - s.size.z / 2 == Approx(0).margin(1e-12));
        CHECK(s.size.x >= 0.02);
        CHECK(s.size.x <= 0.05);
        CHECK(s.size.y >= 0.02);
        CHECK(s.size.y <= 0.05);
        CHECK(s.size.z >= 0.01);
        CHECK(s.size.z <= 0.04);
    }
    CHECK(same_as_other_seed == 0);
}

TEST_CASE("the stones of a rubble field spread over its whole area") {
    RubbleSpec r;
    r.count = 400;
    WorldSpec w;
    w.rubble.push_back(r);
    int quadrant[4] = {0, 0, 0, 0};
    for (const Solid& s : solids_of(w)) {
        quadrant[(s.pose.position.x > 0 ? 1 : 0) + (s.pose.position.y > 0 ? 2 : 0)]++;
    }
    for (int q : quadrant)
        CHECK(q > 70);  // 100 expected in each
}

TEST_CASE("a heightfield from stored heights keeps them, centred on its position") {
    HeightfieldSpec h;
    h.length = 2;
    h.width = 1;
    h.samples_x = 3;
    h.samples_y = 2;
    h.heights = {0, 0.1, 0.2, 0.3, 0.4, 0.5};
    h.position = {1, 1, 0.5};
    WorldSpec w;
    w.heightfields.push_back(h);
    const std::vector<Solid> s = solids_of(w);
    REQUIRE(s.size() == 1);
    CHECK(s[0].kind == Solid::Kind::heightfield);
    CHECK(s[0].grid.at(2, 0) == 0.2);
    CHECK(s[0].grid.at(0, 1) == 0.3);
    const std::vector<Triangle> t = triangles(s[0]);
    CHECK(t.size() == 2 * 2 * 1);
    // grid point (2, 1) is at x = 1 + 1, y = 1 + 0.5, z = 0.5 + 0.5
    bool found = false;
    for (const Triangle& tri : t) {
        for (const Vec3& p : {tri.a, tri.b, tri.c}) {
            if (std::abs(p.x - 2) < 1e-12 && std::abs(p.y - 1.5) < 1e-12) {
                CHECK(p.z == Approx(1.0));
                found = true;
            }
        }
        // every triangle faces up
        CHECK((tri.b - tri.a).cross(tri.c - tri.a).z > 0);
    }
    CHECK(found);
}

TEST_CASE("a heightfield image gives heights from its grey levels, top row at +y") {
    // 3 x 2 pixels, rows from the top: 0 128 255 / 255 0 51
    const test::TempPng png(3, 2, {0, 128, 255, 255, 0, 51});
    HeightfieldSpec h;
    h.image = png.path;
    h.max_height = 0.2;
    const HeightGrid g = height_grid(h);
    REQUIRE(g.samples_x == 3);
    REQUIRE(g.samples_y == 2);
    // grid row 0 (y = -width/2) is the image's bottom row
    CHECK(g.at(0, 0) == Approx(0.2));
    CHECK(g.at(1, 0) == Approx(0));
    CHECK(g.at(2, 0) == Approx(0.04));
    CHECK(g.at(0, 1) == Approx(0));
    CHECK(g.at(1, 1) == Approx(0.2 * 128 / 255));
    CHECK(g.at(2, 1) == Approx(0.2));
}

TEST_CASE("an unreadable heightfield image is an error naming the heightfield and the path") {
    HeightfieldSpec h;
    h.image = "/tmp/gaitlab_no_such_dir/terrain.png";
    REQUIRE_THROWS_AS(height_grid(h, 2), SpecError);
    REQUIRE_THROWS_WITH(
        height_grid(h, 2),
        Equals("heightfield 2 cannot read image "
               "'/tmp/gaitlab_no_such_dir/terrain.png': no such file or directory"));
    WorldSpec w;
    w.heightfields.push_back(h);
    REQUIRE_THROWS_WITH(world_solids(w), Contains("heightfield 1 cannot read image"));
}

TEST_CASE("robot bodies become solids of their own shape") {
    ChainSpec chain;
    chain.name = "c";
    chain.modules = 2;
    chain.module.shape = Shape::cylinder;
    chain.module.radius = 0.03;
    const RobotSpec robot = make_chain(chain);
    const Solid s = body_solid(robot, 1, {{1, 0, 0}, {}});
    CHECK(s.kind == Solid::Kind::cylinder);
    CHECK(s.object == "c segment1");
    CHECK(s.size.y == Approx(0.06));
    CHECK(s.mass == Approx(0.05));
    CHECK(s.pose.position.x == 1);
}
