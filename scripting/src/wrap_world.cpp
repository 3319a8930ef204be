// gaitlab.world: gravity, floor, the world library's objects, placing robots, and the world's
// geometry as triangles.
#include <algorithm>
#include <cmath>
#include <new>
#include <optional>

#include <fmt/format.h>

#include "config_files.h"
#include "gaitlab/checked.h"
#include "gaitlab/files.h"
#include "gaitlab/geometry.h"
#include "gaitlab/xml.h"
#include "lua_util.h"
#include "recording.h"
#include "scene.h"
#include "spec_fields.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

using WorldPtr = std::shared_ptr<WorldBinding>;

WorldBinding& check_world(lua_State* L, int index) {
    return *check_object<WorldPtr>(L, index, kWorldType);
}

Quat yaw_rotation(double deg) {
    return Quat::from_axis_angle({0, 0, 1}, deg_to_rad(deg));
}

int world_new(lua_State* L) {
    // called as gaitlab.world{...}: argument 1 is the gaitlab.world table itself
    return protect(L, [&] {
        auto world = std::make_shared<WorldBinding>();
        if (!lua_isnoneornil(L, 2)) {
            Fields f(L, 2, 1, {"floor", "gravity"});
            world->spec.gravity = f.vec3("gravity", world->spec.gravity);
            const int t = f.push("floor");
            if (t == LUA_TBOOLEAN) {
                world->spec.floor.enabled = lua_toboolean(L, -1);
            } else if (t == LUA_TTABLE) {
                Fields floor(L, -1, 1, {"enabled", "friction", "rigid", "stiffness", "damping"});
                world->spec.floor.enabled = floor.boolean("enabled", true);
                world->spec.floor.friction = floor.number("friction", 1.0);
                world->spec.floor.rigid = floor.boolean("rigid", false);
                // absent: the default (validate refuses them on a rigid floor)
                if (floor.has("stiffness"))
                    world->spec.floor.stiffness = floor.number("stiffness", 0);
                if (floor.has("damping")) world->spec.floor.damping = floor.number("damping", 0);
            } else if (t != LUA_TNIL) {
                f.fail("floor", "table or boolean expected, got " + type_name(L, -1));
            }
            lua_pop(L, 1);
        }
        try {
            validate(world->spec);
        } catch (const SpecError& e) {
            throw ArgError(1, e.what());
        }
        push_world(L, std::move(world));
        return 1;
    });
}

int world_add(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = check_world(L, 1);
        auto robot = to_robot(L, 2);
        if (robot->in_world) {
            throw ArgError(2, "robot '" + robot->spec.name + "' is already in a world");
        }
        // the robot frame has its tail at the origin and the floor at z = 0; yaw, then pitch
        // (a positive pitch raises the head, like a pitch joint), then roll about the chain.
        // Without a pose the world's placement for the robot's name (from an environment
        // file) applies
        std::optional<Pose> pose;
        if (!lua_isnoneornil(L, 3)) {
            pose = Pose{};
            Fields f(L, 3, 3, {"x", "y", "z", "yaw", "pitch", "roll"});
            pose->position = {f.number("x", 0), f.number("y", 0), f.number("z", 0)};
            const double angles[3] = {pose_angle_field(f, "yaw"), pose_angle_field(f, "pitch"),
                                      pose_angle_field(f, "roll")};
            for (double c : {pose->position.x, pose->position.y, pose->position.z}) {
                if (!std::isfinite(c)) throw ArgError(3, "x, y and z must be finite numbers");
            }
            pose->orientation = yaw_rotation(angles[0]) *
                                Quat::from_axis_angle({0, -1, 0}, deg_to_rad(angles[1])) *
                                Quat::from_axis_angle({1, 0, 0}, deg_to_rad(angles[2]));
        }
        w.add(robot, pose);
        lua_settop(L, 1);
        return 1;
    });
}

// world:place{ robot =, position =, yaw = | orientation = }: where a robot of that name goes
// when added without a pose, as an environment file's <place> says
int world_place(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = check_world(L, 1);
        Fields f(L, 2, 2, {"robot", "position", "yaw", "orientation"});
        if (!f.has("robot")) f.fail("robot", "robot name expected, got nil");
        Placement p;
        p.robot = f.string("robot", "");
        try {
            validate_name("robot name", p.robot);
        } catch (const SpecError& e) {
            f.fail("robot", e.what());
        }
        for (const Placement& other : w.placements) {
            if (other.robot == p.robot)
                f.fail("robot", fmt::format("robot '{}' is placed twice", p.robot));
        }
        p.pose.position = f.vec3("position", {});
        for (double c : {p.pose.position.x, p.pose.position.y, p.pose.position.z}) {
            if (!std::isfinite(c)) f.fail("position", "finite numbers expected");
        }
        p.pose.orientation = orientation_field(L, f);
        w.placements.push_back(p);
        lua_settop(L, 1);
        return 1;
    });
}

// Validates `spec` as the next object of its kind in `objects` (so messages number it as the
// world does), appends it, and returns the world for chained calls.
template <class Spec>
int add_object(lua_State* L, std::vector<Spec>& objects, Spec spec) {
    try {
        validate(spec, static_cast<int>(objects.size() + 1));
    } catch (const SpecError& e) {
        throw ArgError(2, e.what());
    }
    objects.push_back(std::move(spec));
    lua_settop(L, 1);
    return 1;
}

// integer field `key` of the next object of `kind` (`existing` of them so far), checked
// against [lo, hi] before it becomes an int, worded as the object's own check words it
int count_field(const Fields& f, const char* key, int fallback, size_t existing, const char* kind,
                int lo, int hi) {
    const long long v = f.integer(key, fallback);
    try {
        return checked_int(fmt::format("{} {} {}", kind, existing + 1, key), v, lo, hi);
    } catch (const SpecError& e) {
        throw ArgError(2, e.what());
    }
}

// the position, yaw (deg) and friction every object takes
template <class Spec>
void read_placement(const Fields& f, Spec& s, const Vec3& default_position) {
    s.position = f.vec3("position", default_position);
    s.yaw = deg_to_rad(f.number("yaw", 0));
    s.friction = f.number("friction", s.friction);
}

int world_box(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = check_world(L, 1);
        Fields f(L, 2, 2, {"size", "position", "yaw", "orientation", "mass", "friction"});
        BoxSpec box;
        box.size = f.vec3("size", box.size);
        box.pose.position = f.vec3("position", {0, 0, box.size.z / 2});
        const double yaw = f.number("yaw", 0);
        // worded as the objects that keep their yaw in the spec
        if (!std::isfinite(yaw)) {
            throw ArgError(
                2, fmt::format("box {} yaw must be a finite number", w.spec.boxes.size() + 1));
        }
        if (std::fabs(yaw) > kMaxAngleDegrees) {
            throw ArgError(
                2, fmt::format("box {} yaw must be in [-{}, {}] deg (got {})",
                               w.spec.boxes.size() + 1, kMaxAngleDegrees, kMaxAngleDegrees, yaw));
        }
        box.pose.orientation = orientation_field(L, f);
        box.mass = f.number("mass", 0);
        box.friction = f.number("friction", 1.0);
        return add_object(L, w.spec.boxes, box);
    });
}

int world_wall(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = check_world(L, 1);
        Fields f(L, 2, 2, {"length", "height", "thickness", "position", "yaw", "friction"});
        WallSpec s;
        s.length = f.number("length", s.length);
        s.height = f.number("height", s.height);
        s.thickness = f.number("thickness", s.thickness);
        read_placement(f, s, {});
        return add_object(L, w.spec.walls, s);
    });
}

int world_ramp(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = check_world(L, 1);
        Fields f(L, 2, 2, {"slope", "length", "width", "position", "yaw", "friction"});
        RampSpec s;
        s.slope = deg_to_rad(f.number("slope", 10));
        s.length = f.number("length", s.length);
        s.width = f.number("width", s.width);
        read_placement(f, s, {});
        return add_object(L, w.spec.ramps, s);
    });
}

int world_stairs(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = check_world(L, 1);
        Fields f(L, 2, 2,
                 {"steps", "step_height", "step_depth", "width", "landing", "position", "yaw",
                  "friction"});
        StairsSpec s;
        s.steps =
            count_field(f, "steps", s.steps, w.spec.stairs.size(), "stairs", 1, kMaxStairsSteps);
        s.step_height = f.number("step_height", s.step_height);
        s.step_depth = f.number("step_depth", s.step_depth);
        s.width = f.number("width", s.width);
        s.landing = f.number("landing", s.landing);
        read_placement(f, s, {});
        return add_object(L, w.spec.stairs, s);
    });
}

int world_cylinder(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = check_world(L, 1);
        Fields f(L, 2, 2, {"radius", "length", "lying", "position", "yaw", "mass", "friction"});
        CylinderSpec s;
        s.radius = f.number("radius", s.radius);
        s.length = f.number("length", s.length);
        s.lying = f.boolean("lying", false);
        // resting on the floor at the origin unless told otherwise
        read_placement(f, s, {0, 0, s.lying ? s.radius : s.length / 2});
        s.mass = f.number("mass", 0);
        return add_object(L, w.spec.cylinders, s);
    });
}

int world_pipe(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = check_world(L, 1);
        Fields f(L, 2, 2,
                 {"radius", "thickness", "length", "sides", "position", "yaw", "friction"});
        PipeSpec s;
        s.radius = f.number("radius", s.radius);
        s.thickness = f.number("thickness", s.thickness);
        s.length = f.number("length", s.length);
        s.sides = count_field(f, "sides", s.sides, w.spec.pipes.size(), "pipe", 3, kMaxPipeSides);
        // lying on the floor unless told otherwise
        read_placement(f, s, {0, 0, s.radius + s.thickness});
        return add_object(L, w.spec.pipes, s);
    });
}

int world_rubble(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = check_world(L, 1);
        Fields f(L, 2, 2,
                 {"length", "width", "count", "min_size", "max_size", "min_height", "max_height",
                  "seed", "position", "yaw", "friction"});
        RubbleSpec s;
        s.length = f.number("length", s.length);
        s.width = f.number("width", s.width);
        s.count =
            count_field(f, "count", s.count, w.spec.rubble.size(), "rubble", 0, kMaxRubbleCount);
        s.min_size = f.number("min_size", s.min_size);
        s.max_size = f.number("max_size", s.max_size);
        s.min_height = f.number("min_height", s.min_height);
        s.max_height = f.number("max_height", s.max_height);
        const long long seed = f.integer("seed", 1);
        if (seed < 0) f.fail("seed", "non-negative integer expected");
        s.seed = static_cast<std::uint64_t>(seed);
        read_placement(f, s, {});
        return add_object(L, w.spec.rubble, s);
    });
}

// samples = {nx, ny}: two integers in [2, 4096]
std::pair<int, int> read_samples(lua_State* L, const Fields& f) {
    const char* expected = "{nx, ny} with two integers in [2, 4096] expected";
    if (f.push("samples") != LUA_TTABLE || lua_rawlen(L, -1) != 2) {
        lua_pop(L, 1);
        f.fail("samples", expected);
    }
    int n[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        lua_rawgeti(L, -1, k + 1);
        lua_Integer v = 0;
        const bool ok = read_integer(L, -1, v).empty();
        lua_pop(L, 1);
        if (!ok || v < 2 || v > 4096) {
            lua_pop(L, 1);
            f.fail("samples", expected);
        }
        n[k] = static_cast<int>(v);
    }
    lua_pop(L, 1);
    return {n[0], n[1]};
}

// heights = function(x, y): sampled on the grid, in the field's own frame (centred on it)
void sample_function(lua_State* L, const Fields& f, int fn, HeightfieldSpec& s) {
    const int nx = s.samples_x, ny = s.samples_y;
    s.heights.reserve(static_cast<size_t>(nx) * static_cast<size_t>(ny));
    for (int j = 0; j < ny; ++j) {
        const double y = -s.width / 2 + j * (s.width / (ny - 1));
        for (int i = 0; i < nx; ++i) {
            const double x = -s.length / 2 + i * (s.length / (nx - 1));
            lua_pushvalue(L, fn);
            lua_pushnumber(L, x);
            lua_pushnumber(L, y);
            protected_call(L, 2, 1);  // a Lua error becomes a ScriptError naming its line
            int ok = 0;
            const double h = lua_tonumberx(L, -1, &ok);
            const std::string t = type_name(L, -1);
            lua_pop(L, 1);
            if (!ok || !std::isfinite(h)) {
                f.fail("heights", fmt::format("the function returned {} at x = {:g}, y = {:g} (a "
                                              "finite number of metres expected)",
                                              !ok             ? t
                                              : std::isnan(h) ? "nan"
                                                              : fmt::format("{}", h),
                                              x, y));
            }
            s.heights.push_back(h);
        }
    }
}

// heights = { row1, row2, ... }: row j is y = -width/2 + (j - 1) · width/(rows - 1)
void read_rows(lua_State* L, const Fields& f, int rows_index, HeightfieldSpec& s) {
    const auto ny = static_cast<lua_Integer>(lua_rawlen(L, rows_index));
    if (ny < 2 || ny > 4096) {
        f.fail("heights", fmt::format("2 to 4096 rows expected (got {})", ny));
    }
    for (lua_Integer j = 1; j <= ny; ++j) {
        if (lua_rawgeti(L, rows_index, j) != LUA_TTABLE) {
            const std::string t = type_name(L, -1);
            lua_pop(L, 1);
            f.fail("heights", fmt::format("row {} is a {} (a list of numbers expected)", j, t));
        }
        const auto nx = static_cast<lua_Integer>(lua_rawlen(L, -1));
        if (j == 1) {
            if (nx < 2 || nx > 4096) {
                lua_pop(L, 1);
                f.fail("heights", fmt::format("2 to 4096 numbers per row expected (got {})", nx));
            }
            s.samples_x = static_cast<int>(nx);
        } else if (nx != s.samples_x) {
            lua_pop(L, 1);
            f.fail("heights", fmt::format("row {} has {} numbers, row 1 has {} (rows must be "
                                          "equally long)",
                                          j, nx, s.samples_x));
        }
        for (lua_Integer i = 1; i <= nx; ++i) {
            lua_rawgeti(L, -1, i);
            int ok = 0;
            const double h = lua_tonumberx(L, -1, &ok);
            lua_pop(L, 1);
            if (!ok) {
                lua_pop(L, 1);
                f.fail("heights", fmt::format("row {}, entry {} is not a number", j, i));
            }
            s.heights.push_back(h);
        }
        lua_pop(L, 1);
    }
    s.samples_y = static_cast<int>(ny);
}

int world_heightfield(lua_State* L) {
    return protect(L, [&] {
        try {
            WorldBinding& w = check_world(L, 1);
            Fields f(L, 2, 2,
                     {"length", "width", "heights", "samples", "resolution", "image", "max_height",
                      "position", "yaw", "friction"});
            HeightfieldSpec s;
            s.length = f.number("length", s.length);
            s.width = f.number("width", s.width);
            read_placement(f, s, {});
            const int number = static_cast<int>(w.spec.heightfields.size() + 1);
            // sizes and placement first (on a stand-in grid), so no sampling runs before they pass
            HeightfieldSpec probe = s;
            probe.samples_x = probe.samples_y = 2;
            probe.heights.assign(4, 0.0);
            try {
                validate(probe, number);
            } catch (const SpecError& e) {
                throw ArgError(2, e.what());
            }
            const int ht = f.push("heights");
            const int heights = lua_gettop(L);
            const bool has_image = f.has("image");
            if ((ht == LUA_TNIL) == !has_image) {
                f.fail(has_image ? "image" : "heights",
                       "give either heights (a function or a table of rows) or an image");
            }
            if (!has_image && f.has("max_height")) {
                f.fail("max_height", "only an image takes max_height (heights are in metres)");
            }
            if (ht != LUA_TFUNCTION && (f.has("samples") || f.has("resolution"))) {
                f.fail(f.has("samples") ? "samples" : "resolution",
                       "only a heights function is sampled");
            }
            if (ht == LUA_TFUNCTION) {
                if (f.has("samples") && f.has("resolution")) {
                    f.fail("samples", "give samples or resolution, not both");
                }
                if (f.has("samples")) {
                    const auto [nx, ny] = read_samples(L, f);
                    s.samples_x = nx;
                    s.samples_y = ny;
                } else {
                    const double res = f.number("resolution", 0.02);
                    if (!(std::isfinite(res) && res > 0)) {
                        f.fail("resolution", "positive number of metres expected");
                    }
                    auto count = [&](double extent) {
                        const double n = std::round(extent / res) + 1;
                        if (n > 4096) {
                            f.fail("resolution", fmt::format("{:g} m gives more than 4096 samples "
                                                             "across {:g} m",
                                                             res, extent));
                        }
                        return std::max(2, static_cast<int>(n));
                    };
                    s.samples_x = count(s.length);
                    s.samples_y = count(s.width);
                }
                sample_function(L, f, heights, s);
            } else if (ht == LUA_TTABLE) {
                read_rows(L, f, heights, s);
            } else if (ht != LUA_TNIL) {
                f.fail("heights", "function or table of rows expected, got " + type_name(L, -1));
            } else {
                // relative to the script that names it; read now, so a bad image fails here. What
                // input_path copies for the run folders is checked first: a directory or a device
                // is left to height_grid to refuse, with the path named as it names it
                const std::string image = f.string("image", "");
                s.image = Recordings::of(L).input_path(script_path(L, image));
                bool readable = true;
                try {
                    check_file(s.image);
                } catch (const ReadError&) {
                    readable = false;
                }
                if (readable) s.image = input_path(L, image);
                s.max_height = f.number("max_height", s.max_height);
                try {
                    validate(s, number);
                    height_grid(s, number);
                } catch (const SpecError& e) {
                    throw ArgError(2, e.what());
                }
            }
            lua_settop(L, 1);
            return add_object(L, w.spec.heightfields, s);
        } catch (const std::bad_alloc&) {
            throw Error(fmt::format("not enough memory for heightfield {}",
                                    check_world(L, 1).spec.heightfields.size() + 1));
        }
    });
}

// world:triangles(): the world's solids (and its robots, where they are now if they run) as
// { object =, kind =, vertices = { x1, y1, z1, x2, ... } }, nine numbers per triangle
int world_triangles(lua_State* L) {
    return protect(L, [&] {
        try {
            WorldBinding& w = check_world(L, 1);
            std::vector<std::pair<std::string, Solid>> solids;
            try {
                for (Solid& s : world_solids(w.spec)) {
                    std::string kind = s.object.substr(0, s.object.find(' '));
                    solids.emplace_back(std::move(kind), std::move(s));
                }
            } catch (const SpecError& e) {
                throw Error(e.what());
            }
            for (const WorldBinding::Entry& e : w.robots) {
                const RobotSpec& robot = e.robot->spec;
                auto sim = e.robot->sim.lock();
                for (size_t b = 0; b < robot.bodies.size(); ++b) {
                    const Pose& local = robot.bodies[b].pose;
                    const Pose pose = sim ? sim->body(e.robot->index, static_cast<int>(b)).pose
                                          : Pose{e.pose.apply(local.position),
                                                 e.pose.orientation * local.orientation};
                    solids.emplace_back("robot", body_solid(robot, static_cast<int>(b), pose));
                }
            }
            lua_createtable(L, static_cast<int>(solids.size()), 0);
            for (size_t k = 0; k < solids.size(); ++k) {
                const std::vector<Triangle> tris = triangles(solids[k].second);
                lua_createtable(L, 0, 3);
                lua_pushstring(L, solids[k].second.object.c_str());
                lua_setfield(L, -2, "object");
                lua_pushstring(L, solids[k].first.c_str());
                lua_setfield(L, -2, "kind");
                lua_createtable(L, static_cast<int>(tris.size() * 9), 0);
                lua_Integer i = 0;
                for (const Triangle& t : tris) {
                    for (const Vec3& p : {t.a, t.b, t.c}) {
                        for (double c : {p.x, p.y, p.z}) {
                            lua_pushnumber(L, c);
                            lua_rawseti(L, -2, ++i);
                        }
                    }
                }
                lua_setfield(L, -2, "vertices");
                lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
            }
            return 1;
        } catch (const std::bad_alloc&) {
            throw Error("not enough memory for the triangles of the world");
        }
    });
}

// gaitlab.world.load(path): a world from an environment file (objects, and where robots of
// the names it places go when added), or nil and a message
int world_load(lua_State* L) {
    return protect(L, [&] {
        const std::string arg = check_string(L, 1);
        return file_read(L, [&] {
            const std::string path = checked_input_path(L, arg);
            EnvironmentSpec env = read_environment(path);
            auto world = std::make_shared<WorldBinding>();
            world->spec = std::move(env.world);
            world->placements = std::move(env.placements);
            push_world(L, std::move(world));
        });
    });
}

// world:save(path): writes the environment file, with where its robots are; the path, or nil
// and a message
int world_save(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = *check_object<WorldPtr>(L, 1, kWorldType);
        const ScriptPath path(L, check_string(L, 2));
        const EnvironmentSpec env = environment_of(w);
        return file_written(L, path, [&] { write_environment(path.path(), env); });
    });
}

// read_source(path): the text of a file, read with the one bounded reader (a directory, a
// FIFO, a device or a huge file is refused up front), or nil and "cannot read PATH: REASON".
// For stdlib/worlds.lua, which loads world files (registry "gaitlab.read_source")
int world_read_source(lua_State* L) {
    return protect(L, [&] {
        const std::string path = check_string(L, 1);
        refuse_zero_byte(path);  // the system would read the file named by the part before it
        std::string text;
        std::optional<std::string> unreadable;
        try {
            text = read_file(path);
        } catch (const ReadError& e) {
            unreadable = e.what();
        }
        if (unreadable) return push_fail(L, *unreadable);
        lua_pushlstring(L, text.data(), text.size());
        return 1;
    });
}

int world_eq(lua_State* L) {
    return handle_eq<WorldPtr>(L, kWorldType);
}

int world_tostring(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = check_world(L, 1);
        const WorldSpec& s = w.spec;
        // "1 robot", "2 robots"; stairs are stairs either way
        const auto count = [](size_t n, const char* one, const char* many) {
            return fmt::format("{} {}", n, n == 1 ? one : many);
        };
        std::string text = "gaitlab.World (" + count(w.robots.size(), "robot", "robots") + ", " +
                           count(s.boxes.size(), "box", "boxes");
        struct Kind {
            size_t n;
            const char* one;
            const char* many;
        };
        const Kind others[] = {{s.walls.size(), "wall", "walls"},
                               {s.ramps.size(), "ramp", "ramps"},
                               {s.stairs.size(), "stairs", "stairs"},
                               {s.cylinders.size(), "cylinder", "cylinders"},
                               {s.pipes.size(), "pipe", "pipes"},
                               {s.rubble.size(), "rubble field", "rubble fields"},
                               {s.heightfields.size(), "heightfield", "heightfields"}};
        for (const Kind& k : others) {
            if (k.n > 0) text += ", " + count(k.n, k.one, k.many);
        }
        lua_pushstring(L, (text + ")").c_str());
        return 1;
    });
}

}  // namespace

void push_world(lua_State* L, std::shared_ptr<WorldBinding> world) {
    push_canonical<WorldPtr>(L, kWorldType, std::move(world));
}

std::shared_ptr<WorldBinding> to_world(lua_State* L, int index) {
    return check_object<WorldPtr>(L, index, kWorldType);
}

void open_world(lua_State* L) {
    const luaL_Reg methods[] = {{"add", world_add},
                                {"place", world_place},
                                {"box", world_box},
                                {"wall", world_wall},
                                {"ramp", world_ramp},
                                {"stairs", world_stairs},
                                {"cylinder", world_cylinder},
                                {"pipe", world_pipe},
                                {"rubble", world_rubble},
                                {"heightfield", world_heightfield},
                                {"triangles", world_triangles},
                                {"save", world_save},
                                {nullptr, nullptr}};
    const luaL_Reg meta[] = {
        {"__tostring", world_tostring}, {"__eq", world_eq}, {nullptr, nullptr}};
    register_type<WorldPtr>(L, kWorldType, methods, meta);

    // gaitlab.world is a table (load and preset come from stdlib/worlds.lua) that is called to
    // make a world
    lua_newtable(L);
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, world_new);
    lua_setfield(L, -2, "__call");
    lua_setmetatable(L, -2);
    lua_pushcfunction(L, world_load);
    lua_setfield(L, -2, "load");
    lua_setfield(L, -2, "world");
    lua_pushcfunction(L, world_read_source);
    lua_setfield(L, LUA_REGISTRYINDEX, "gaitlab.read_source");
}

}  // namespace gaitlab::scripting
