// Watching a recorded run in a browser (`gaitlab view RUN_FOLDER`): the run's scene rebuilt
// from the configuration in its folder, its bodies played back from the recorded pose series
// on a timeline the pages scrub (play, pause, step, seek, speed), its series for the pages'
// plots and CSV downloads, other run folders to open, and `--video`: the page records the
// playback as WebM in a headless chromium and posts it back.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gaitlab/run_data.h"
#include "gaitlab/viewer/server.h"
#include "gaitlab/viewer/view.h"

namespace gaitlab::viewer {

/// What a recorded run shows in 3D.
struct RecordedScene {
    std::string scene;          ///< the scene as the page reads it (view.h, scene_json)
    std::vector<double> poses;  ///< where every body and moving object starts (7 each)
    std::string problem;        ///< why the scene could not be rebuilt ("" if it was)
};

/// Rebuilds the scene of `run`: runs its script from config/ (with its seed and arguments,
/// recording nothing, printing nothing) until the run's simulation first steps, for at most
/// `seconds` of wall time. When that fails (no script, a script error, a file outside the
/// run folder that is gone), the scene is made of the bodies the pose series name, drawn as
/// small boxes, and `problem` says why. `cancel` (checked every 50 ms) stops it early (Ctrl-C).
RecordedScene rebuild_scene(const RunData& run, double seconds = 20,
                            const std::function<bool()>& cancel = {});

struct RunViewOptions {
    std::string video;       ///< "": serve the pages; else the WebM file the page records
    double video_speed = 1;  ///< the real-time factor of the video's playback
    double frame_rate = kFrameRate;
    double rebuild_seconds = 20;   ///< wall time rebuilding a scene may take
    std::function<bool()> cancel;  ///< stops rebuilding the first scene (Ctrl-C); may be empty
};

class RunView {
  public:
    /// Opens the run folder `dir` (throws IoError or FormatError naming the file and line of
    /// what is wrong) and serves it (throws ServerError).
    RunView(const std::string& dir, ServerOptions server, RunViewOptions options = {});
    ~RunView();
    RunView(const RunView&) = delete;
    RunView& operator=(const RunView&) = delete;

    Server& server();
    std::string url() const;
    /// What the run lacks for the 3D view (no pose series, a scene not rebuilt), for the
    /// terminal; the pages get them as messages.
    std::vector<std::string> notes() const;
    /// Seconds of recorded time the current run spans.
    double duration() const;

    /// Serves until `stop()` says so (checked at least every 50 ms) or, with a video, until
    /// the page has posted it: applies the pages' commands and plays the timeline.
    void serve(const std::function<bool()>& stop);
    /// With a video: whether the page posted it, and the error it reported ("" if none).
    bool video_done() const;
    std::string video_error() const;

  private:
    struct Impl;
    std::shared_ptr<Impl> impl_;
};

/// The chromium to run: $GAITLAB_CHROMIUM, else chromium or chromium-browser on the PATH;
/// "" when there is none.
std::string find_chromium();

/// `gaitlab view RUN --video OUT.webm`: serves the run on a loopback port, runs headless
/// `chromium` on the page in video mode, which draws the run frame by frame (25 a second of
/// video, `width` x `height` pixels), and waits until the page has posted the WebM (at most
/// 60 s and a second a frame). Returns "" or what went wrong (no chromium, with
/// how to install it; chromium failed, with its last messages; the page's error).
std::string render_video(const std::string& dir, const std::string& out, double speed,
                         const std::function<bool()>& stop, const std::string& chromium,
                         int width = 960, int height = 540);

}  // namespace gaitlab::viewer
