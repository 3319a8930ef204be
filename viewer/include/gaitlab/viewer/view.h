// Watching the simulations of a Lua host in a browser (`gaitlab run FILE --view`): a Server,
// the scene and frames of the newest simulation published to it, and the pages' commands
// applied on the host's thread at tick boundaries. While a View lives, the script's sim:run
// and sim:step play at the pace of the simulation's Player (real time × speed), wait for a
// first page to open, and wait while a page holds them; serve() goes on after the script.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gaitlab/viewer/server.h"

namespace gaitlab {
class Player;
class Simulation;
namespace scripting {
class LuaHost;
}
}  // namespace gaitlab

namespace gaitlab::viewer {

/// Frames published per second of wall time at most.
inline constexpr double kFrameRate = 60;
/// Simulations a view keeps (the newest; older ones are let go).
inline constexpr int kMaxViewed = 16;

struct ViewOptions {
    /// Runs wait until a page has opened (so the start is not missed).
    bool wait_for_page = true;
    /// The view serves a console (sim:view()): between typed lines the pages may play, step
    /// and reset the simulations, as after the script of `gaitlab run --view`.
    bool console = false;
    double frame_rate = kFrameRate;  ///< frames per second at most, > 0
};

class View {
  public:
    /// Serves the simulations `host` creates from now on (host must outlive the view, and the
    /// view must go before the host's simulations' Lua state: destroy it on the host's
    /// thread). Throws ServerError.
    View(scripting::LuaHost& host, ServerOptions server, ViewOptions options = {});
    ~View();
    View(const View&) = delete;
    View& operator=(const View&) = delete;

    Server& server();
    std::string url() const;

    /// A message for the pages' console panel.
    void message(const std::string& level, const std::string& text);

    /// Lets the pages edit the shown simulation's world ("Edit world", editor.h) and save it
    /// as the environment file `file`, or under another name in its folder; the simulation
    /// itself does not change.
    void edit_world(const std::string& file);

    /// Shows a simulation that exists already (sim:view()): the pages show it from now on.
    void show(const std::shared_ptr<Player>& player, int index);

    /// One round of serving between a console's keystrokes: applies the pages' commands,
    /// advances what they play, publishes a frame when one is due. Returns the wall seconds
    /// until it should be called again (at most 0.05).
    double poll();

    /// Serves after the script has ended, until `stop()` says so (checked at least every
    /// 50 ms): applies the pages' commands, plays what they play, and pumps the host (hot
    /// reload; simulations the script left playing). `script_error` ("" if none) is shown.
    void serve(const std::function<bool()>& stop, const std::string& script_error = {});

  private:
    struct Session;
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::shared_ptr<Impl*> alive_;  // what the host's on_player function reaches
};

/// The scene of `sim` as the page reads it: robots' bodies with their shapes, world objects
/// (boxes, cylinders, meshes for ramps, pipes and heightfields), the floor, the controllers
/// and their parameters (with ranges and units). `controls` gets the parameters commands are
/// checked against.
std::string scene_json(const Simulation& sim, int index, std::vector<ParamControl>* controls);

/// How pages and events name sensor i: "<robot label>.<sensor name>".
std::string sensor_label(const Simulation& sim, int i);

/// Where every body of `sim` is: robots' bodies, then dynamic objects (7 numbers each).
void frame_poses(const Simulation& sim, std::vector<double>& out);

}  // namespace gaitlab::viewer
