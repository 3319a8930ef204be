// examples/embed: gaitlab from C++ — an 8-module snake on a floor, driven by a sine wave for
// 5 simulated seconds; prints how far it moved. Build it against an installed gaitlab:
//   cmake -S examples/embed -B build-embed -DCMAKE_PREFIX_PATH=/where/gaitlab/is/installed
//   cmake --build build-embed && build-embed/embed
// (docs/embedding.md; tests/consumer builds and runs this file)
#include <cstdio>
#include <exception>
#include <memory>

#include "gaitlab/controllers/sine.h"
#include "gaitlab/simulation.h"

int main() {
    try {
        gaitlab::ChainSpec chain;
        chain.name = "snake";
        chain.modules = 8;  // pitch-pitch, lying on the floor along +x, head towards +x
        gaitlab::PlacedRobot robot{gaitlab::make_chain(chain), {}, {}};

        auto sine = std::make_shared<gaitlab::controllers::Sine>();
        sine->set_param("amplitude", 40);   // degrees
        sine->set_param("frequency", 0.5);  // Hz
        sine->set_param("phase", -120);     // degrees between neighbours: < 0 crawls head first
        robot.actuation.push_back({gaitlab::select_joints(robot.robot, "pitch"), sine});

        gaitlab::WorldSpec world;
        world.floor.friction = 0.8;
        world.robots.push_back(robot);

        gaitlab::Simulation sim(world);  // dt 0.001 s, control every 30 ticks
        sim.run(5);                      // simulated seconds
        const gaitlab::Vec3 d = sim.robot_displacement(0);
        std::printf("moved %.3f m (x %.3f, y %.3f) in %.1f s\n", d.norm(), d.x, d.y, sim.time());
        return 0;
    } catch (const std::exception& e) {  // a spec the engine refuses says why
        std::fprintf(stderr, "embed: %s\n", e.what());
        return 1;
    }
}
