#include "edit.h"

#include <signal.h>

#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "gaitlab/files.h"
#include "gaitlab/terminal.h"
#include "gaitlab/viewer/editor.h"
#include "gaitlab/viewer/server.h"
#include "gaitlab/xml.h"

namespace gaitlab::cli {

namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t g_stop = 0;

extern "C" void on_edit_signal(int sig) {
    g_stop = sig;
}

}  // namespace

struct EditCommand::Args {
    CLI::App* command = nullptr;
    std::string file;
    std::vector<std::string> robots;  // --robot
    std::string sim;                  // --sim
    std::string port;
    std::string host;
};

EditCommand::EditCommand(CLI::App& app) : a_(std::make_unique<Args>()) {
    Args& a = *a_;
    a.command = app.add_subcommand(
        "edit", "Edit an environment file in a browser: objects, friction, where robots start");
    a.command->allow_extras();
    a.command
        ->add_option("file", a.file,
                     "The environment file (ENV.xml; made if missing; with --sim: the "
                     "simulation's, by default)")
        ->type_name("ENV.xml");
    a.command
        ->add_option("--robot", a.robots,
                     "A robot file whose robot is drawn where the environment places it "
                     "(repeatable)")
        ->type_name("ROBOT.xml");
    a.command
        ->add_option("--sim", a.sim,
                     "A simulation file: its robots are drawn, and its environment is edited "
                     "when no ENV.xml is given")
        ->type_name("SIM.xml");
    a.command->add_option("--port", a.port, "The port (default: any free port)")->type_name("P");
    a.command
        ->add_option("--host", a.host,
                     "The address to listen on (default 127.0.0.1, this machine only; any "
                     "other needs the token of the printed address)")
        ->type_name("ADDR");
    a.command->footer(
        "Serves a page with a top view, a side view and a 3D view of the environment: add,\n"
        "move, resize and rotate objects, set their friction and the floor's, place the robots,\n"
        "and save. Saving checks the world as 'gaitlab run' does and writes the file atomically,\n"
        "only into its own folder. Ctrl-C quits. See docs/viewer.md.");
}

EditCommand::~EditCommand() = default;

bool EditCommand::chosen() const {
    return a_->command->parsed();
}

int EditCommand::run() {
    Args& a = *a_;
    viewer::ServerOptions options;
    if (!a.port.empty()) {
        int v = 0;
        const char* end = a.port.data() + a.port.size();
        const auto r = std::from_chars(a.port.data(), end, v);
        if (r.ec != std::errc() || r.ptr != end || v < 1 || v > 65535) {
            print_message(stderr,
                          "gaitlab: --port: a port number from 1 to 65535 expected (got '%s'; "
                          "leave --port out for any free port)\n",
                          a.port.c_str());
            return 2;
        }
        options.port = v;
    }
    if (!a.host.empty()) options.host = a.host;
    std::vector<std::string> robot_files = a.robots;
    std::string file = a.file;
    try {
        if (!a.sim.empty()) {
            const SimulationFile sim = read_simulation(a.sim);
            if (file.empty()) file = resolve_path(a.sim, sim.environment);
            robot_files.push_back(a.sim);
        }
    } catch (const Error& e) {
        report_line(e.what());
        return 1;
    }
    if (file.empty()) {
        print_message(stderr,
                      "gaitlab: edit: an environment file expected (gaitlab edit ENV.xml, or "
                      "--sim SIM.xml)\n");
        return 2;
    }
    if (file.size() < 5 || file.compare(file.size() - 4, 4, ".xml") != 0) {
        print_message(stderr, "gaitlab: %s: an environment file (ENV.xml) expected\n",
                      file.c_str());
        return 2;
    }
    viewer::EditorSource first;
    try {
        std::error_code ec;
        if (!fs::exists(file, ec)) {
            const fs::path folder = fs::absolute(file, ec).parent_path();
            if (!fs::is_directory(folder, ec)) {
                print_message(stderr, "gaitlab: %s: the folder %s does not exist\n", file.c_str(),
                              folder.string().c_str());
                return 1;
            }
            print_message(stderr,
                          "gaitlab: %s does not exist: creating it (a floor, nothing on "
                          "it)\n",
                          file.c_str());
            write_file_atomic(file, format_environment(EnvironmentSpec{}, file));
        }
        // read once here, so a file gaitlab cannot read is said before anything is served
        first = viewer::load_editor_source(file, robot_files);
    } catch (const Error& e) {
        report_line(e.what());
        return 1;
    }
    const std::string path = first.file;
    // every page that opens the editor gets the file as it is on disk now
    viewer::Editor editor(
        [path, robot_files] { return viewer::load_editor_source(path, robot_files); }, "edit");
    g_stop = 0;
    struct sigaction sa {};
    sa.sa_handler = on_edit_signal;
    sigemptyset(&sa.sa_mask);
    for (int sig : {SIGINT, SIGTERM, SIGHUP})
        sigaction(sig, &sa, nullptr);
    try {
        viewer::Server server(options);
        server.set_world_provider(editor.provider());
        print_message(stderr, "editor: %s\n  open it in a browser to edit %s (Ctrl-C quits)\n",
                      server.url().c_str(), path.c_str());
        if (options.host == "0.0.0.0" || options.host == "::") {
            print_message(stderr,
                          "  from another machine: this machine's address in place of "
                          "127.0.0.1, with the token (whoever has it can save into %s)\n",
                          fs::path(path).parent_path().string().c_str());
        }
        while (g_stop == 0)
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        server.stop();
    } catch (const Error& e) {
        report_line(e.what());
        return 1;
    }
    return 0;
}

}  // namespace gaitlab::cli
