#include "gaitlab/event.h"

namespace gaitlab {

namespace {

constexpr Origin kOrigins[] = {Origin::script, Origin::console, Origin::viewer, Origin::file};
constexpr EventKind kKinds[] = {EventKind::param, EventKind::reload, EventKind::reset,
                                EventKind::sensor, EventKind::drive};

}  // namespace

const char* to_string(Origin origin) {
    switch (origin) {
        case Origin::script:
            return "script";
        case Origin::console:
            return "console";
        case Origin::viewer:
            return "viewer";
        case Origin::file:
            return "file";
    }
    return "?";
}

const char* to_string(EventKind kind) {
    switch (kind) {
        case EventKind::param:
            return "param";
        case EventKind::reload:
            return "reload";
        case EventKind::reset:
            return "reset";
        case EventKind::sensor:
            return "sensor";
        case EventKind::drive:
            return "drive";
    }
    return "?";
}

std::optional<Origin> parse_origin(std::string_view name) {
    for (Origin o : kOrigins) {
        if (name == to_string(o)) return o;
    }
    return std::nullopt;
}

std::optional<EventKind> parse_event_kind(std::string_view name) {
    for (EventKind k : kKinds) {
        if (name == to_string(k)) return k;
    }
    return std::nullopt;
}

}  // namespace gaitlab
