// The viewer's HTTP server: serves the page (embedded in the program), streams what the
// simulation publishes to every open page as server-sent events, and queues the commands the
// pages post. It knows nothing of Lua or Bullet, nor of simulations: the simulation's thread
// publishes descriptions, frames and messages here and takes the commands at tick boundaries
// (view.h does that). Publishing never waits for a client: each page gets the latest frame
// when it is ready for one, and a page that stops reading is dropped after a write timeout.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gaitlab/error.h"

namespace gaitlab::viewer {

/// The server could not start (port in use, bad address): the message says what to do.
class ServerError : public Error {
  public:
    using Error::Error;
};

/// Limits and defaults of a server.
inline constexpr int kMaxStreams = 16;                      ///< pages (event streams) open at once
inline constexpr int kMaxQueuedCommands = 256;              ///< commands waiting for the simulation
inline constexpr std::size_t kMaxCommandBytes = 64 * 1024;  ///< body of one POST
inline constexpr std::size_t kMaxWorldBytes = 16 * 1024 * 1024;  ///< body of one world edit
inline constexpr double kMaxDelay = 10;  ///< s between two physics steps (Player's limit)

struct ServerOptions {
    /// The address to listen on: "127.0.0.1" (the default) serves this machine only; any
    /// other (e.g. "0.0.0.0") needs a token in every request.
    std::string host = "127.0.0.1";
    int port = 0;  ///< 0: any free port
    /// A token every request must carry (?token=...); "" and `host` not loopback: a random
    /// one is made. Loopback servers need none unless one is given.
    std::string token;
    /// Seconds a write to a page may block before the page is dropped (a client that never
    /// reads).
    double write_timeout = 2;
};

/// A controller parameter the pages may set, as the simulation declared it (what commands
/// are checked against).
struct ParamControl {
    int simulation = 0;      ///< creation index, from 1
    int drive = 0;           ///< index among the simulation's drives
    std::string controller;  ///< its label ("sine", "sine_2")
    std::string name;
    double min = 0;
    double max = 0;
    std::string unit;
};

/// One command from a page, checked against the published controls.
struct Command {
    enum class Kind {
        play,      ///< play at the simulation's speed
        pause,     ///< hold
        step,      ///< `count` ticks, then hold
        reset,     ///< back to time 0
        speed,     ///< `value`: real-time factor, > 0 (inf: as fast as possible)
        param,     ///< controller `drive`'s parameter `name` = `value`
        live,      ///< live buffers' settings: `sample_every`, `refresh`, `size` (0 / < 0: kept)
        sensor,    ///< switches sensor `name` ("<robot>.<sensor>") on (`value` 1) or off (0)
        delay,     ///< `value`: wall seconds between two physics steps, in [0, kMaxDelay]
        contacts,  ///< frames carry the contact points (`value` 1) or not (0)
        seek,      ///< a recorded run (set_run_provider): go to time `value`, s
        show,      ///< the pages show `simulation` (one of publish_simulations' list)
    };
    Kind kind = Kind::play;
    int simulation = 0;  ///< creation index (0: the newest)
    int drive = -1;
    std::string name;
    double value = 0;
    long count = 0;
    int sample_every = 0;  ///< live: ticks between samples
    double refresh = -1;   ///< live: wall seconds between publications
    int size = 0;          ///< live: samples kept per series
};

/// "play", "pause", ...
const char* to_string(Command::Kind kind);

/// A frame: where every body is at one tick, as the page draws it.
struct Frame {
    int simulation = 0;
    long tick = 0;
    double time = 0;             ///< s
    std::vector<double> poses;   ///< 7 per body (x y z, m; qw qx qy qz), in the scene's order
    std::vector<double> params;  ///< every parameter of every controller, in the scene's order
    std::string state;           ///< a JSON object: playing, speed, measured speed ...
    /// Contact points, 7 numbers each (x y z, m; normal x y z; force, N); sent only when
    /// `with_contacts` (a page asked for them).
    std::vector<double> contacts;
    bool with_contacts = false;
};

/// Counters for tests and for the status route.
struct ServerStats {
    std::uint64_t frames = 0;    ///< frames published
    std::uint64_t sent = 0;      ///< frames written to pages, all pages together
    int streams = 0;             ///< pages connected now
    std::uint64_t dropped = 0;   ///< pages dropped because a write failed or timed out
    std::uint64_t commands = 0;  ///< commands accepted
    std::uint64_t refused = 0;   ///< requests answered with an error status
};

/// A request to /api/run... (Server::set_run_provider).
struct RunRequest {
    std::string method;  ///< "GET" or "POST"
    std::string path;    ///< "/api/run", "/api/run/data" ...
    std::map<std::string, std::string> query;
    std::string body;
    std::string type;  ///< the request's Content-Type
};

/// The answer to a RunRequest.
struct RunReply {
    int status = 200;
    std::string body;
    std::string type = "application/json";
    std::string filename;  ///< not empty: a download (Content-Disposition: attachment)
};

using RunProvider = std::function<RunReply(const RunRequest&)>;

class Server {
  public:
    /// Listens at once, serving from its own threads; throws ServerError naming the address
    /// and what to do (another --port, a --host that exists).
    explicit Server(ServerOptions options);
    /// Stops serving: every stream ends, the threads are joined.
    ~Server();
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    /// The port it listens on.
    int port() const;
    /// The address to open: http://HOST:PORT/ with ?token=... when one is needed.
    std::string url() const;
    /// The token requests must carry ("" if none).
    const std::string& token() const;

    // --- the simulation's side (any thread, never blocks on a client) ---

    /// Replaces the scene (a JSON object: bodies, objects, controllers; see view.cpp) and the
    /// controls commands are checked against (parameters, and sensors by their
    /// "<robot>.<sensor>" names); every page gets it, then frames.
    void publish_scene(std::string json, std::vector<ParamControl> controls,
                       std::vector<std::string> sensors = {});
    /// Replaces the list of simulations the pages may choose from (a JSON object, view.cpp
    /// describes it) and their numbers, which the command `show` is checked against; every page
    /// gets it (the event `simulations`, and GET /api/simulations). Until it is published
    /// `show` is refused (a recorded run has one simulation).
    void publish_simulations(std::string json, std::vector<int> simulations);
    /// Makes `frame` the latest; pages that are ready get it, the others get a later one.
    void publish_frame(Frame frame);
    /// A message for the pages' console panel ("info", "error" ...), kept in a bounded log.
    void publish_message(const std::string& level, const std::string& text);
    /// Takes the commands queued so far, oldest first.
    std::vector<Command> take_commands();
    /// Whether commands are waiting (cheap: an atomic read).
    bool has_commands() const;
    /// Waits until a command arrives or `seconds` pass.
    void wait_for_commands(double seconds);
    /// Answers GET /api/live (`query` has "series", "since", "simulation") and GET
    /// /api/live/series (`query` has "simulation" and "list"): `fn` returns the JSON body, or
    /// throws ServerError for a 400 saying why. Called on the server's threads: it must be
    /// thread-safe. Without one, both answer 404.
    using LiveProvider = std::function<std::string(const std::map<std::string, std::string>&)>;
    void set_live_provider(LiveProvider fn);
    /// Answers GET and POST requests to /api/run and the routes below it (a recorded run,
    /// run_view.h): `fn` gets the request and returns the answer, or throws ServerError for a
    /// 400 saying why. POSTs must be application/json or application/octet-stream (415
    /// otherwise; neither can come from a page of another site without the browser asking) and
    /// at most kMaxCommandBytes. Called on the server's threads: it must be thread-safe.
    /// Without one, they answer 404 and the command `seek` is refused.
    void set_run_provider(RunProvider fn);

    /// Answers the environment editor's routes (editor.h): GET /api/world (`action` "open")
    /// and POST /api/world/shape, /api/world/check, /api/world/save (`action` "shape",
    /// "check", "save", `body` the request's JSON): `fn` returns the HTTP status and the JSON
    /// body. Called on the server's threads: it must be thread-safe. Without one, they answer
    /// 404.
    struct Reply {
        int status = 200;
        std::string body;
    };
    using WorldProvider = std::function<Reply(const std::string& action, const std::string& body)>;
    void set_world_provider(WorldProvider fn);
    /// Stops serving now (the destructor does it too): pages are disconnected, the threads
    /// joined; nothing is called on the server's threads any more.
    void stop();
    /// Whether a page has ever opened its event stream.
    bool page_seen() const;
    ServerStats stats() const;

  private:
    struct State;
    std::shared_ptr<State> state_;
};

/// Whether `host` names this machine only (127.0.0.0/8, ::1, localhost).
bool is_loopback(const std::string& host);

/// A random token: 32 hex digits from the system's random source.
std::string random_token();

}  // namespace gaitlab::viewer
