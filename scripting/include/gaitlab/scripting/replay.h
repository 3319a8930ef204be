// gaitlab replay: reruns a recorded run headless from the configuration in its folder (the
// script and controller files it ran, with its seed and arguments), applies the changes that
// did not come from the script (console, viewer, reloads from disk) at their ticks, records the
// same series into a new folder and compares the data bit for bit.
#pragma once

#include <functional>
#include <string>

#include "gaitlab/run_data.h"

namespace gaitlab::scripting {

class LuaHost;

struct ReplayResult {
    std::string into;            ///< the replay's run folder
    Comparison comparison;       ///< the data, bit for bit
    std::string divergence;      ///< how the replay departed from the recorded events ("" if not)
    int applied = 0;             ///< recorded events applied (the others came from the script)
    bool stopped_early = false;  ///< the run did not finish: the replay stopped at its last row
    std::string script_error;    ///< the replayed script failed ("" if not)
    /// a run that failed (its script or a controller raised an error): how the replay's end
    /// departs from it (another error, another time, none); "" if it failed the same way
    std::string failure;
    /// the error the run failed with, which the replay met again at the same time ("" if the
    /// run did not fail), and that time, s
    std::string run_error;
    double failed_at = 0;
    /// identical data, no divergence, no error (other than the one the run ended with)
    bool ok() const {
        return comparison.identical && divergence.empty() && failure.empty() &&
               script_error.empty();
    }
};

/// Replays the run in `run_dir` into `into` ("" : RUN_DIR-replay). Throws IoError or
/// FormatError for a folder that is not a run, Error for a run that cannot be replayed (no
/// script). What the script prints goes to the replay's log only. `on_host`, if given, is
/// called with the host that runs the script once it exists and with nullptr before it goes,
/// so a caller can interrupt it (LuaHost::interrupt, e.g. from a signal handler): the replay
/// then stops, its folder is closed as "interrupted" and `script_error` says so.
ReplayResult replay(const std::string& run_dir, const std::string& into = {},
                    const std::function<void(LuaHost*)>& on_host = {});

}  // namespace gaitlab::scripting
