// Events: changes made to a running simulation (a parameter, a reload of controller code, a
// reset, a sensor switch, a new drive), each stamped with the tick it happened at and who made
// it. The recorder writes them next to the data; replay applies the ones that did not come from
// the script again at their ticks.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace gaitlab {

/// Who made a change.
enum class Origin {
    script,   ///< the program that drives the simulation (a Lua script, a C++ caller)
    console,  ///< the interactive console (REPL)
    viewer,   ///< the browser viewer's controls
    file      ///< a controller file changed on disk and was hot reloaded
};

/// What changed.
enum class EventKind {
    param,   ///< a controller parameter: name = its series name, value = the new value
    reload,  ///< new code for a controller file: name = the file, value = its new version
    reset,   ///< the simulation went back to time 0
    sensor,  ///< a sensor was switched: name = "<robot label>.<sensor>", value = 1 on, 0 off
    drive    ///< a joint group got a controller while running: name = its label
};

/// "script", "console", "viewer", "file".
const char* to_string(Origin origin);
/// "param", "reload", "reset", "sensor", "drive".
const char* to_string(EventKind kind);
std::optional<Origin> parse_origin(std::string_view name);
std::optional<EventKind> parse_event_kind(std::string_view name);

/// One change to a simulation.
struct Event {
    long tick = 0;  ///< ticks done when it happened: it acts from tick `tick` on
    EventKind kind = EventKind::param;
    Origin origin = Origin::script;
    std::string name;    ///< what changed (see EventKind)
    double value = 0;    ///< its new value (see EventKind)
    std::string detail;  ///< more about it: for reload, the saved source (run folder path)
    int drive = -1;      ///< param events: the drive whose controller changed (-1 otherwise)
};

}  // namespace gaitlab
