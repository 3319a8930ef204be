// The environment editor's engine side (docs/viewer.md, "Editing a world"): the page edits a
// world as JSON (its objects with the fields of the environment file, angles in degrees); every
// edit comes back here, where the engine's own spec validation checks it and the engine's own
// XML writer saves it, atomically, into the folder of the environment file and nowhere else.
// It knows no Lua and no Bullet; the server's threads call it (it is thread-safe).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gaitlab/robot.h"
#include "gaitlab/viewer/server.h"
#include "gaitlab/xml.h"

namespace gaitlab::viewer {

/// What an editor route refuses: the HTTP status, the message (naming the object and field, as
/// the engine names them: "box 2 friction must be in [0, 1] (got -1)"), and which object of
/// the page's list (-1: none) and which of its fields ("": none) it is about.
class EditError : public ServerError {
  public:
    EditError(int status, const std::string& message, int object = -1, std::string field = {})
        : ServerError(message), status_(status), object_(object), field_(std::move(field)) {}
    int status() const { return status_; }
    int object() const { return object_; }
    const std::string& field() const { return field_; }

  private:
    int status_;
    int object_;
    std::string field_;
};

/// What the editor edits: an environment, the robots drawn at its placements, and the file it
/// saves to.
struct EditorSource {
    EnvironmentSpec environment;
    std::vector<RobotSpec> robots;  ///< drawn where the environment places their names
    /// The environment file (absolute): saves go there, or to another name in its folder.
    std::string file;
};

class Editor {
  public:
    /// `open` gives the world to edit each time a page opens the editor (GET /api/world):
    /// the file as it is on disk (`gaitlab edit`), the world of the simulation shown (`--view`).
    /// It may throw EditError. `mode` is "edit" (`gaitlab edit`) or "view" (the page's "Edit
    /// world" under --view), for the page.
    Editor(std::function<EditorSource()> open, std::string mode);
    ~Editor();
    Editor(const Editor&) = delete;
    Editor& operator=(const Editor&) = delete;

    /// GET /api/world: the environment as the page edits it, the fields of every kind of
    /// object (name, type, unit), the robots' bodies, the file and the PNG images of its folder.
    std::string open();
    /// POST /api/world/shape {"object": {...}, "number": N}: the solids object number N of its
    /// kind expands into, in its own frame (position 0, yaw 0), as the scene gives objects.
    std::string shape(const std::string& body) const;
    /// POST /api/world/check {"environment": {...}}: {"ok": true, "solids": N} if the engine
    /// takes it.
    std::string check(const std::string& body) const;
    /// POST /api/world/save {"environment": {...}, "file"?: "NAME.xml", "overwrite"?: bool}:
    /// checks it, then writes it with the engine's writer, atomically, to the file (or NAME.xml
    /// in its folder). A file changed on disk since the page opened it is not overwritten
    /// (409) unless "overwrite" is true.
    std::string save(const std::string& body);

    /// The server's world routes, answered by this editor (it must outlive the server's use).
    Server::WorldProvider provider();

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Reads the environment file at `path` for `gaitlab edit`: an EditorSource with the robots
/// of `robot_files` (robot files, or simulation files whose robots are taken). A missing
/// environment file gives an empty environment (a floor). Throws FormatError, IoError.
EditorSource load_editor_source(const std::string& path,
                                const std::vector<std::string>& robot_files);

}  // namespace gaitlab::viewer
