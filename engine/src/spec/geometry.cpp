#include "gaitlab/geometry.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "formats/png_image.h"
#include "gaitlab/error.h"
#include "spec/random.h"

namespace gaitlab {

namespace {

Quat yaw_rotation(double yaw) {
    return Quat::from_axis_angle({0, 0, 1}, yaw);
}

// an object's own frame: its reference point, turned by yaw about +z
Pose frame(const Vec3& position, double yaw) {
    return {position, yaw_rotation(yaw)};
}

// `local`, given in `parent`'s frame, in the world frame
Pose compose(const Pose& parent, const Pose& local) {
    return {parent.apply(local.position), parent.orientation * local.orientation};
}

Solid box_solid(std::string object, const Pose& pose, const Vec3& size, double mass,
                double friction) {
    Solid s;
    s.kind = Solid::Kind::box;
    s.object = std::move(object);
    s.pose = pose;
    s.size = size;
    s.mass = mass;
    s.friction = friction;
    return s;
}

void add_wall(std::vector<Solid>& out, const WallSpec& w, int number) {
    const Pose local{{0, 0, w.height / 2}, {}};
    out.push_back(box_solid(fmt::format("wall {}", number),
                            compose(frame(w.position, w.yaw), local),
                            {w.length, w.thickness, w.height}, 0, w.friction));
}

void add_ramp(std::vector<Solid>& out, const RampSpec& r, int number) {
    const double l = r.length, w = r.width / 2, h = r.length * std::tan(r.slope);
    Solid s;
    s.kind = Solid::Kind::convex;
    s.object = fmt::format("ramp {}", number);
    s.pose = frame(r.position, r.yaw);
    // the lower edge (0, 1), the bottom of the back face (2, 3) and the top edge (4, 5)
    s.points = {{0, -w, 0}, {0, w, 0}, {l, -w, 0}, {l, w, 0}, {l, -w, h}, {l, w, h}};
    s.faces = {{0, 1, 3, 2}, {0, 4, 5, 1}, {2, 3, 5, 4}, {0, 2, 4}, {1, 5, 3}};
    s.friction = r.friction;
    out.push_back(std::move(s));
}

void add_stairs(std::vector<Solid>& out, const StairsSpec& s, int number) {
    const Pose f = frame(s.position, s.yaw);
    for (int k = 0; k < s.steps; ++k) {
        // each step is a block from the ground up, so no gap opens under a tread
        const double x0 = k * s.step_depth;
        const double x1 = (k + 1) * s.step_depth + (k == s.steps - 1 ? s.landing : 0);
        const double top = (k + 1) * s.step_height;
        const Pose local{{(x0 + x1) / 2, 0, top / 2}, {}};
        out.push_back(box_solid(fmt::format("stairs {}", number), compose(f, local),
                                {x1 - x0, s.width, top}, 0, s.friction));
    }
}

void add_cylinder(std::vector<Solid>& out, const CylinderSpec& c, int number) {
    Solid s;
    s.kind = Solid::Kind::cylinder;
    s.object = fmt::format("cylinder {}", number);
    s.pose = frame(c.position, c.yaw);
    // a solid cylinder's axis is its local x: an upright one turns x onto z
    if (!c.lying) {
        s.pose.orientation = s.pose.orientation * Quat::from_axis_angle({0, 1, 0}, -kPi / 2);
    }
    s.size = {c.length, 2 * c.radius, 2 * c.radius};
    s.mass = c.mass;
    s.friction = c.friction;
    out.push_back(std::move(s));
}

void add_pipe(std::vector<Solid>& out, const PipeSpec& p, int number) {
    const Pose f = frame(p.position, p.yaw);
    const double half_angle = kPi / p.sides;
    // each wall is as wide as a side of the outer polygon, so the outer corners meet; inside,
    // the walls overlap beyond the inner polygon's corners, which leaves the bore exact
    const double wall_width = 2 * (p.radius + p.thickness) * std::tan(half_angle);
    const double mid = p.radius + p.thickness / 2;
    for (int k = 0; k < p.sides; ++k) {
        // wall 0 lies flat at the bottom
        const double phi = -kPi / 2 + 2 * half_angle * k;
        const Pose local{{p.length / 2, mid * std::cos(phi), mid * std::sin(phi)},
                         Quat::from_axis_angle({1, 0, 0}, phi - kPi / 2)};
        out.push_back(box_solid(fmt::format("pipe {}", number), compose(f, local),
                                {p.length, wall_width, p.thickness}, 0, p.friction));
    }
}

void add_rubble(std::vector<Solid>& out, const RubbleSpec& r, int number) {
    const Pose f = frame(r.position, r.yaw);
    detail::SplitMix64 rng(r.seed);
    for (int k = 0; k < r.count; ++k) {
        // the draws are made in this fixed order for every stone
        const double x = rng.uniform(-r.length / 2, r.length / 2);
        const double y = rng.uniform(-r.width / 2, r.width / 2);
        const double yaw = rng.uniform(0, 2 * kPi);
        const double sx = rng.uniform(r.min_size, r.max_size);
        const double sy = rng.uniform(r.min_size, r.max_size);
        const double h = rng.uniform(r.min_height, r.max_height);
        const Pose local{{x, y, h / 2}, yaw_rotation(yaw)};
        out.push_back(box_solid(fmt::format("rubble {}", number), compose(f, local), {sx, sy, h}, 0,
                                r.friction));
    }
}

void add_heightfield(std::vector<Solid>& out, const HeightfieldSpec& h, int number) {
    Solid s;
    s.kind = Solid::Kind::heightfield;
    s.object = fmt::format("heightfield {}", number);
    s.pose = frame(h.position, h.yaw);
    s.grid = height_grid(h, number);
    s.friction = h.friction;
    out.push_back(std::move(s));
}

}  // namespace

HeightGrid height_grid(const HeightfieldSpec& h, int number) {
    HeightGrid g;
    g.length = h.length;
    g.width = h.width;
    if (!h.heights.empty()) {
        g.samples_x = h.samples_x;
        g.samples_y = h.samples_y;
        g.heights = h.heights;
        return g;
    }
    detail::GreyImage image;
    try {
        image = detail::read_png_grey(h.image);
    } catch (const SpecError& e) {
        throw SpecError(fmt::format("heightfield {} {}", number, e.what()));
    }
    g.samples_x = image.width;
    g.samples_y = image.height;
    g.heights.resize(image.levels.size());
    // the image's top row is the grid's last row (+y)
    const size_t w = static_cast<size_t>(image.width);
    for (size_t j = 0; j < static_cast<size_t>(image.height); ++j) {
        const size_t row = static_cast<size_t>(image.height) - 1 - j;
        for (size_t i = 0; i < w; ++i)
            g.heights[j * w + i] = image.levels[row * w + i] * h.max_height;
    }
    return g;
}

std::vector<Solid> world_solids(const WorldSpec& world) {
    std::vector<Solid> out;
    out.reserve(static_cast<size_t>(std::min(solid_count(world), kMaxWorldSolids)));
    for (size_t i = 0; i < world.boxes.size(); ++i) {
        const BoxSpec& b = world.boxes[i];
        out.push_back(box_solid(fmt::format("box {}", i + 1), b.pose, b.size, b.mass, b.friction));
    }
    auto each = [&out](const auto& objects, auto add) {
        for (size_t i = 0; i < objects.size(); ++i)
            add(out, objects[i], static_cast<int>(i + 1));
    };
    each(world.walls, add_wall);
    each(world.ramps, add_ramp);
    each(world.stairs, add_stairs);
    each(world.cylinders, add_cylinder);
    each(world.pipes, add_pipe);
    each(world.rubble, add_rubble);
    each(world.heightfields, add_heightfield);
    // images are only read here: their samples count against the world's limit now
    long long samples = 0;
    for (const Solid& s : out)
        samples += static_cast<long long>(s.grid.heights.size());
    if (samples > kMaxHeightSamples) {
        throw SpecError(
            fmt::format("the world's heightfields have {} samples together (at most {})", samples,
                        kMaxHeightSamples));
    }
    return out;
}

Solid body_solid(const RobotSpec& robot, int body, const Pose& pose) {
    const BodySpec& b = robot.bodies[static_cast<size_t>(body)];
    Solid s = box_solid(robot.name + " " + b.name, pose, b.size, b.mass, b.friction);
    if (b.shape == Shape::cylinder) s.kind = Solid::Kind::cylinder;
    s.inertia = b.inertia;
    s.center_of_mass = b.center_of_mass;
    return s;
}

std::vector<Triangle> triangles(const Solid& s, int segments) {
    std::vector<Triangle> out;
    auto tri = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        out.push_back({s.pose.apply(a), s.pose.apply(b), s.pose.apply(c)});
    };
    // a convex polygon given counter-clockwise, as a fan
    auto polygon = [&](const std::vector<Vec3>& p) {
        for (size_t k = 2; k < p.size(); ++k)
            tri(p[0], p[k - 1], p[k]);
    };
    switch (s.kind) {
        case Solid::Kind::box: {
            const Vec3 h = s.size * 0.5;
            auto c = [&](int sx, int sy, int sz) { return Vec3{sx * h.x, sy * h.y, sz * h.z}; };
            polygon({c(-1, -1, -1), c(-1, 1, -1), c(1, 1, -1), c(1, -1, -1)});  // -z
            polygon({c(-1, -1, 1), c(1, -1, 1), c(1, 1, 1), c(-1, 1, 1)});      // +z
            polygon({c(-1, -1, -1), c(1, -1, -1), c(1, -1, 1), c(-1, -1, 1)});  // -y
            polygon({c(-1, 1, -1), c(-1, 1, 1), c(1, 1, 1), c(1, 1, -1)});      // +y
            polygon({c(-1, -1, -1), c(-1, -1, 1), c(-1, 1, 1), c(-1, 1, -1)});  // -x
            polygon({c(1, -1, -1), c(1, 1, -1), c(1, 1, 1), c(1, -1, 1)});      // +x
            break;
        }
        case Solid::Kind::cylinder: {
            const double hl = s.size.x / 2, r = s.size.y / 2;
            std::vector<Vec3> back, front;
            for (int k = 0; k < segments; ++k) {
                const double a = 2 * kPi * k / segments;
                back.push_back({-hl, r * std::cos(a), r * std::sin(a)});
                front.push_back({hl, r * std::cos(a), r * std::sin(a)});
            }
            for (int k = 0; k < segments; ++k) {
                const int n = (k + 1) % segments;
                tri(back[k], back[n], front[n]);
                tri(back[k], front[n], front[k]);
            }
            polygon(front);
            polygon(std::vector<Vec3>(back.rbegin(), back.rend()));
            break;
        }
        case Solid::Kind::convex:
            for (const std::vector<int>& face : s.faces) {
                std::vector<Vec3> p;
                for (int i : face)
                    p.push_back(s.points[static_cast<size_t>(i)]);
                polygon(p);
            }
            break;
        case Solid::Kind::heightfield: {
            const HeightGrid& g = s.grid;
            const double dx = g.length / (g.samples_x - 1), dy = g.width / (g.samples_y - 1);
            auto p = [&](int i, int j) {
                return Vec3{-g.length / 2 + i * dx, -g.width / 2 + j * dy, g.at(i, j)};
            };
            for (int j = 0; j + 1 < g.samples_y; ++j) {
                for (int i = 0; i + 1 < g.samples_x; ++i) {
                    tri(p(i, j), p(i + 1, j), p(i + 1, j + 1));
                    tri(p(i, j), p(i + 1, j + 1), p(i, j + 1));
                }
            }
            break;
        }
    }
    return out;
}

}  // namespace gaitlab
