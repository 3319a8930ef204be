#include "gaitlab_scene.h"

#include <lua.hpp>

#include <fmt/format.h>

#include <stdexcept>

#include "gaitlab/controllers/registry.h"
#include "gaitlab/robot.h"

namespace gaitlab_bench {

gaitlab::WorldSpec make_world(const Scenario& sc) {
    gaitlab::ChainSpec chain;
    chain.name = "snake";
    chain.modules = sc.modules;
    chain.connection =
        sc.pitch_yaw ? gaitlab::Connection::pitch_yaw : gaitlab::Connection::pitch_pitch;
    gaitlab::PlacedRobot placed;
    placed.robot = gaitlab::make_chain(chain);
    auto drive = [&](const char* role, double amplitude) {
        std::shared_ptr<gaitlab::Controller> c = gaitlab::controllers::make_builtin(sc.controller);
        if (!c) throw std::runtime_error("no built-in controller '" + sc.controller + "'");
        const std::pair<const char*, double> params[] = {
            {"amplitude", amplitude}, {"frequency", sc.frequency}, {"phase", sc.phase}};
        for (const auto& [name, value] : params) {
            if (c->find_param(name) >= 0) c->set_param(name, value);
        }
        placed.actuation.push_back({gaitlab::select_joints(placed.robot, role), c});
    };
    drive("pitch", sc.pitch_amplitude);
    if (sc.pitch_yaw) drive("yaw", sc.yaw_amplitude);
    if (sc.sensors != "none") {
        if (sc.sensors != "off" && sc.sensors != "on") {
            throw std::runtime_error("--sensors takes none, off or on");
        }
        auto& sensors = placed.robot.sensors;
        for (int m = 0; m < sc.modules; ++m) {
            for (gaitlab::SensorKind k :
                 {gaitlab::SensorKind::joint, gaitlab::SensorKind::imu,
                  gaitlab::SensorKind::contact, gaitlab::SensorKind::range}) {
                gaitlab::SensorSpec s;
                s.kind = k;
                s.joint = m;
                s.module = m;
                s.direction = {0, 0, -1};
                sensors.push_back(s);
            }
        }
        sensors.push_back(gaitlab::SensorSpec{});
        sensors.back().kind = gaitlab::SensorKind::position;
        for (gaitlab::SensorSpec& s : sensors)
            s.enabled = sc.sensors == "on";
    }

    gaitlab::WorldSpec world;
    world.floor.friction = sc.floor_friction;
    world.robots.push_back(std::move(placed));
    return world;
}

gaitlab::SimulationOptions make_options(const Scenario& sc) {
    gaitlab::SimulationOptions o;
    o.dt = sc.dt;
    o.control_every = sc.control_every;
    o.solver_iterations = sc.solver_iterations;
    // none, as the raw Bullet loop it is compared with (a long pitch-yaw chain would get 4)
    o.newton_steps = 0;
    return o;
}

LuaScene::LuaScene(const Scenario& sc, const std::string& controller_file) {
    std::string make;
    if (controller_file.empty()) {
        make = "local function make(p) return gaitlab.controllers.sine(p) end\n";
    } else {
        make = "local make = gaitlab.controller.load([==[" + controller_file + "]==])\n";
    }
    const std::string script =
        make +
        fmt::format(
            "local robot = gaitlab.robot.chain{{ name = 'snake', modules = {}, connection = '{}' "
            "}}\n"
            "local world = gaitlab.world{{ floor = {{ friction = {} }} }}\n"
            "world:add(robot)\n"
            "robot:group('pitch'):drive(make{{ amplitude = {}, frequency = {}, phase = {} }})\n"
            "if {} then\n"
            "  robot:group('yaw'):drive(make{{ amplitude = {}, frequency = {}, phase = {} }})\n"
            "end\n"
            "sim = gaitlab.simulation{{ world = world, dt = {}, control_every = {},\n"
            "                          solver_iterations = {}, newton_steps = 0, record = false "
            "}}\n"
            "snake = robot\n",
            sc.modules, sc.pitch_yaw ? "pitch-yaw" : "pitch-pitch", sc.floor_friction,
            sc.pitch_amplitude, sc.frequency, sc.phase, sc.pitch_yaw ? "true" : "false",
            sc.yaw_amplitude, sc.frequency, sc.phase, sc.dt, sc.control_every,
            sc.solver_iterations);
    host_.run_string(script, "=bench_scene");
}

void LuaScene::step(long ticks) {
    host_.run_string(fmt::format("sim:step({})", ticks), "=step");
}

Vec LuaScene::displacement() {
    host_.run_string("local d = snake:displacement(); dx, dy, dz = d.x, d.y, d.z", "=disp");
    lua_State* L = host_.state();
    Vec out;
    lua_getglobal(L, "dx");
    out.x = lua_tonumber(L, -1);
    lua_getglobal(L, "dy");
    out.y = lua_tonumber(L, -1);
    lua_getglobal(L, "dz");
    out.z = lua_tonumber(L, -1);
    lua_pop(L, 3);
    return out;
}

std::string default_lua_controller() {
    return std::string(GAITLAB_SOURCE_DIR) + "/examples/controllers/my_sine.lua";
}

}  // namespace gaitlab_bench
