#include "gaitlab/viewer/editor.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gaitlab/files.h"
#include "gaitlab/geometry.h"
#include "gaitlab/simulation.h"
#include "gaitlab/world_fields.h"
#include "request_json.h"

namespace gaitlab::viewer {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// images offered for new heightfields: at most this many PNG files of the folder
constexpr std::size_t kMaxImages = 200;
// a stored grid goes to the page as numbers (to edit) up to this many samples
constexpr std::size_t kMaxEditedHeights = 256 * 256;
// a check builds the world with its robots (to say whether one starts inside an object) only
// up to this many solids: a rubble field of 100 000 stones is checked, not built, on every edit
constexpr long long kMaxBuiltSolids = 20000;

// the kinds of objects, in the order the engine numbers and the file writes them
const std::vector<std::string>& kind_names() {
    static const std::vector<std::string> k = {"box",      "wall", "ramp",   "stairs",
                                               "cylinder", "pipe", "rubble", "heightfield"};
    return k;
}

std::string kinds_list() {
    std::string out;
    for (const std::string& k : kind_names())
        out += (out.empty() ? "" : ", ") + k;
    return out;
}

std::string dump(const json& j) {
    return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

// a value as messages quote what the page sent
std::string quoted(const json& v) {
    std::string s = dump(v);
    if (s.size() > 40) s = s.substr(0, 37) + "...";
    return s;
}

// a number from the page: a JSON number, or text holding one (a form's field: "nan" and "inf"
// come through, for the engine to refuse by name)
bool to_number(const json& v, double& out) {
    if (v.is_number()) {
        out = v.get<double>();
        return true;
    }
    if (!v.is_string()) return false;
    std::string s = v.get<std::string>();
    while (!s.empty() && s.front() == ' ')
        s.erase(0, 1);
    while (!s.empty() && s.back() == ' ')
        s.pop_back();
    if (!s.empty() && s.front() == '+') s.erase(0, 1);
    const char* end = s.data() + s.size();
    const auto r = std::from_chars(s.data(), end, out);
    return !s.empty() && r.ec == std::errc() && r.ptr == end;
}

// the fields of each kind, walked to describe, read and write them; names are the file's
// attributes. A box's are the page's own (the file gives it a yaw or a quaternion); the other
// kinds' are the file's (gaitlab/world_fields.h)
template <class V, class S>
void fields(V& v, S& s, BoxSpec*) {
    v.vec3("size", s.size, "m");
    v.vec3("position", s.pose.position, "m");
    v.quat("orientation", s.pose.orientation);
    v.number("mass", s.mass, "kg");
    v.number("friction", s.friction, "");
}

template <class V, class S, class Kind>
void fields(V& v, S& s, Kind* kind) {
    world_object_fields(v, s, kind);
}

// describes the fields for the page's forms
struct Describe {
    json out = json::array();
    void add(const char* name, const char* type, const char* unit) {
        out.push_back({{"name", name}, {"type", type}, {"unit", unit}});
    }
    template <class T>
    void number(const char* n, const T&, const char* unit) {
        add(n, "number", unit);
    }
    template <class T>
    void vec3(const char* n, const T&, const char* unit) {
        add(n, "vec3", unit);
    }
    template <class T>
    void quat(const char* n, const T&) {
        add(n, "orientation", "");
    }
    template <class T>
    void angle(const char* n, const T&) {
        add(n, "number", "deg");
    }
    template <class T>
    void count(const char* n, const T&, int, int) {
        add(n, "count", "");
    }
    template <class T>
    void seed(const char* n, const T&) {
        add(n, "count", "");
    }
    template <class T>
    void flag(const char* n, const T&) {
        add(n, "flag", "");
    }
};

// writes a spec's fields as the page edits them
struct Write {
    json& out;
    void number(const char* n, double v, const char*) { out[n] = v; }
    void vec3(const char* n, const Vec3& v, const char*) { out[n] = {v.x, v.y, v.z}; }
    void quat(const char* n, const Quat& q) { out[n] = {q.w, q.x, q.y, q.z}; }
    void angle(const char* n, double v) { out[n] = rad_to_deg(v); }
    void count(const char* n, int v, int, int) { out[n] = v; }
    void seed(const char* n, std::uint64_t v) { out[n] = v; }
    void flag(const char* n, bool v) { out[n] = v; }
};

// reads the page's fields into a spec; a field left out keeps the spec's default (as in the
// file). `what` names the object in messages ("box 2"), `index` is its place in the page's list
struct Read {
    const json& in;
    std::string what;
    int index;
    std::vector<std::string> seen;

    [[noreturn]] void fail(const std::string& field, const std::string& message) const {
        throw EditError(400, fmt::format("{} {}: {}", what, field, message), index, field);
    }
    const json* find(const char* n) {
        seen.emplace_back(n);
        const auto it = in.find(n);
        return it == in.end() ? nullptr : &*it;
    }
    void number(const char* n, double& v, const char* unit) {
        if (const json* j = find(n); j && !to_number(*j, v)) {
            fail(n, fmt::format("a number{} expected (got {})",
                                *unit ? fmt::format(" in {}", unit) : "", quoted(*j)));
        }
    }
    // a field the spec may lack (a compliant floor's stiffness): absent or null, it lacks it
    void number(const char* n, std::optional<double>& v, const char* unit) {
        const json* j = find(n);
        if (!j || j->is_null()) return;
        double d = 0;
        number(n, d, unit);
        v = d;
    }
    void vec3(const char* n, Vec3& v, const char* unit) {
        const json* j = find(n);
        if (!j) return;
        double x = 0, y = 0, z = 0;
        if (!j->is_array() || j->size() != 3 || !to_number((*j)[0], x) || !to_number((*j)[1], y) ||
            !to_number((*j)[2], z)) {
            fail(n, fmt::format("three numbers (x y z, {}) expected (got {})", unit, quoted(*j)));
        }
        v = {x, y, z};
    }
    void quat(const char* n, Quat& q) {
        const json* j = find(n);
        if (!j) return;
        double c[4] = {};
        bool ok = j->is_array() && j->size() == 4;
        for (std::size_t i = 0; ok && i < 4; ++i)
            ok = to_number((*j)[i], c[i]);
        if (!ok) fail(n, fmt::format("four numbers (w x y z) expected (got {})", quoted(*j)));
        q = {c[0], c[1], c[2], c[3]};
    }
    void angle(const char* n, double& v) {
        double deg = rad_to_deg(v);
        number(n, deg, "deg");
        v = deg_to_rad(deg);
    }
    void whole(const char* n, long long& v, long long lo, long long hi) {
        const json* j = find(n);
        if (!j) return;
        double d = 0;
        if (!to_number(*j, d) || d != std::floor(d) || !(d >= static_cast<double>(lo)) ||
            !(d <= static_cast<double>(hi))) {
            fail(n,
                 fmt::format("a whole number in [{}, {}] expected (got {})", lo, hi, quoted(*j)));
        }
        v = static_cast<long long>(d);
    }
    // counts are checked by the engine's validation; here only that they are whole numbers
    void count(const char* n, int& v, int, int) {
        long long w = v;
        whole(n, w, std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
        v = static_cast<int>(w);
    }
    void seed(const char* n, std::uint64_t& v) {
        long long w = static_cast<long long>(v);
        // whole numbers a double holds exactly, as the page's numbers are
        whole(n, w, 0, 9007199254740992LL);
        v = static_cast<std::uint64_t>(w);
    }
    void flag(const char* n, bool& v) {
        const json* j = find(n);
        if (!j) return;
        if (!j->is_boolean()) fail(n, fmt::format("true or false expected (got {})", quoted(*j)));
        v = j->get<bool>();
    }
    // what the page sent that no field takes
    void finish(std::initializer_list<const char*> extra = {}) {
        for (const char* e : extra)
            seen.emplace_back(e);
        for (const auto& item : in.items()) {
            if (std::find(seen.begin(), seen.end(), item.key()) != seen.end()) continue;
            std::string list;
            for (const std::string& s : seen)
                if (s != "kind") list += (list.empty() ? "" : ", ") + s;
            throw EditError(
                400,
                fmt::format("{}: unknown field '{}' (a {} has {})", what, item.key().substr(0, 40),
                            what.substr(0, what.find(' ')), list),
                index, item.key().substr(0, 40));
        }
    }
};

template <class S>
json describe() {
    Describe d;
    S probe;
    fields(d, probe, static_cast<S*>(nullptr));
    return d.out;
}

// the field an engine message is about: "box 2 size x must be positive" is about "size"
template <class S>
std::string field_of(const std::string& message, const std::string& prefix) {
    if (message.rfind(prefix, 0) != 0) return "";
    const std::string rest = message.substr(prefix.size());
    std::string best;
    for (const json& f : describe<S>()) {
        const std::string n = f["name"].get<std::string>();
        if (rest.rfind(n, 0) == 0 && (rest.size() == n.size() || rest[n.size()] == ' ') &&
            n.size() > best.size()) {
            best = n;
        }
    }
    return best;
}

// checks object `number` of its kind, as the engine does; EditError names it and its field
template <class S>
void check_object(const S& s, const std::string& kind, int number, int index) {
    try {
        validate(s, number);
    } catch (const SpecError& e) {
        throw EditError(400, e.what(), index,
                        field_of<S>(e.what(), fmt::format("{} {} ", kind, number)));
    }
}

// a page's path inside `folder`: one plain file name ending in `extension`, no folders (so
// nothing outside the folder can ever be named, whoever asks)
fs::path inside(const fs::path& folder, const std::string& name, const char* extension,
                const char* what) {
    const bool plain = !name.empty() && name.size() <= 255 &&
                       name.find_first_of(std::string("/\\\0", 3)) == std::string::npos &&
                       name != "." && name != ".." && name.front() != '.';
    const std::string ext(extension);
    if (!plain || name.size() <= ext.size() ||
        name.compare(name.size() - ext.size(), ext.size(), ext) != 0) {
        throw EditError(400, fmt::format("{}: a file name in the folder {} ending in {} expected, "
                                         "without folders (got '{}')",
                                         what, folder.string(), ext, name.substr(0, 80)));
    }
    return folder / name;
}

}  // namespace

struct Editor::Impl {
    std::function<EditorSource()> opener;
    std::string mode;
    mutable std::mutex mutex;
    // the world the pages opened last: its heightfields' stored heights are referred to by
    // index ("grid"), its images may be kept
    EditorSource source;
    fs::path folder;
    std::string disk_text;  // the file when the page opened it
    bool disk_exists = false;
    int version = 0;

    // ---- spec -> the page's JSON ----

    json object_json(const BoxSpec& b) const {
        json o{{"kind", "box"}};
        Write w{o};
        fields(w, b, static_cast<BoxSpec*>(nullptr));
        return o;
    }
    template <class S>
    json object_json(const S& s, const char* kind) const {
        json o{{"kind", kind}};
        Write w{o};
        fields(w, s, static_cast<S*>(nullptr));
        return o;
    }

    json environment_json(const EnvironmentSpec& env) const {
        const WorldSpec& w = env.world;
        json objects = json::array();
        for (const BoxSpec& b : w.boxes)
            objects.push_back(object_json(b));
        for (const WallSpec& s : w.walls)
            objects.push_back(object_json(s, "wall"));
        for (const RampSpec& s : w.ramps)
            objects.push_back(object_json(s, "ramp"));
        for (const StairsSpec& s : w.stairs)
            objects.push_back(object_json(s, "stairs"));
        for (const CylinderSpec& s : w.cylinders)
            objects.push_back(object_json(s, "cylinder"));
        for (const PipeSpec& s : w.pipes)
            objects.push_back(object_json(s, "pipe"));
        for (const RubbleSpec& s : w.rubble)
            objects.push_back(object_json(s, "rubble"));
        for (std::size_t k = 0; k < w.heightfields.size(); ++k) {
            const HeightfieldSpec& h = w.heightfields[k];
            json o = object_json(h, "heightfield");
            if (h.heights.empty()) {
                o["image"] = relative_path(h.image, source.file);
            } else {
                o["grid"] = k;
                o["samples"] = {h.samples_x, h.samples_y};
                // its heights by rows along y, each row along x, m
                if (h.heights.size() <= kMaxEditedHeights) {
                    json rows = json::array();
                    for (int j = 0; j < h.samples_y; ++j) {
                        const auto first = h.heights.begin() + static_cast<long>(j) * h.samples_x;
                        rows.push_back(std::vector<double>(first, first + h.samples_x));
                    }
                    o["heights"] = std::move(rows);
                }
            }
            objects.push_back(std::move(o));
        }
        json places = json::array();
        for (const Placement& p : env.placements) {
            const Quat& q = p.pose.orientation;
            places.push_back(
                {{"robot", p.robot},
                 {"position", {p.pose.position.x, p.pose.position.y, p.pose.position.z}},
                 {"orientation", {q.w, q.x, q.y, q.z}}});
        }
        json floor = {{"enabled", w.floor.enabled}, {"friction", w.floor.friction}};
        if (w.floor.rigid) floor["rigid"] = true;
        if (w.floor.stiffness) floor["stiffness"] = *w.floor.stiffness;
        if (w.floor.damping) floor["damping"] = *w.floor.damping;
        return {{"gravity", {w.gravity.x, w.gravity.y, w.gravity.z}},
                {"floor", floor},
                {"objects", objects},
                {"placements", places}};
    }

    // ---- the page's JSON -> spec, checked by the engine ----

    template <class S>
    void read_object(const json& o, int index, int number, std::vector<S>& out,
                     const std::string& kind) {
        S s;
        Read r{o, fmt::format("{} {}", kind, number), index, {"kind"}};
        fields(r, s, static_cast<S*>(nullptr));
        r.finish();
        check_object(s, kind, number, index);
        out.push_back(std::move(s));
    }

    void read_heightfield(const json& o, int index, int number,
                          std::vector<HeightfieldSpec>& out) const {
        HeightfieldSpec h;
        Read r{o, fmt::format("heightfield {}", number), index, {"kind"}};
        fields(r, h, static_cast<HeightfieldSpec*>(nullptr));
        r.finish({"image", "grid", "samples", "heights"});
        const auto image = o.find("image");
        const auto grid = o.find("grid");
        const auto heights = o.find("heights");
        if ((image == o.end()) == (grid == o.end() && heights == o.end())) {
            r.fail("image",
                   "an image (a PNG file of the folder), heights (rows of numbers) or the grid it "
                   "was loaded with expected, one of them");
        }
        if (grid != o.end()) {
            const std::vector<HeightfieldSpec>& base = source.environment.world.heightfields;
            if (!grid->is_number_integer() || grid->get<long long>() < 0 ||
                grid->get<long long>() >= static_cast<long long>(base.size()) ||
                base[grid->get<std::size_t>()].heights.empty()) {
                r.fail("grid", fmt::format("the number of a stored grid of the file expected "
                                           "(got {})",
                                           quoted(*grid)));
            }
            const HeightfieldSpec& g = base[grid->get<std::size_t>()];
            h.heights = g.heights;
            h.samples_x = g.samples_x;
            h.samples_y = g.samples_y;
        }
        if (heights != o.end()) {
            // rows along y, each of the heights along x, m; they replace a grid's
            const char* expected =
                "rows of heights in m expected ([[h, h, ...], [h, h, ...], "
                "...]: a row per y, the same number in each, at least 2 by 2)";
            if (!heights->is_array() || heights->size() < 2 || !heights->at(0).is_array() ||
                heights->at(0).size() < 2) {
                r.fail("heights", fmt::format("{} (got {})", expected, quoted(*heights)));
            }
            const std::size_t columns = heights->at(0).size();
            if (heights->size() > kMaxEditedHeights / 2 || columns > kMaxEditedHeights / 2 ||
                heights->size() * columns > kMaxEditedHeights) {
                r.fail("heights", fmt::format("at most {} heights expected (got {} rows of {})",
                                              kMaxEditedHeights, heights->size(), columns));
            }
            h.heights.clear();  // the numbers replace the grid's
            h.heights.reserve(heights->size() * columns);
            for (std::size_t j = 0; j < heights->size(); ++j) {
                const json& row = heights->at(j);
                if (!row.is_array() || row.size() != columns) {
                    r.fail("heights",
                           fmt::format("row {} has {} heights, row 1 has {}: {}", j + 1,
                                       row.is_array() ? row.size() : 0, columns, expected));
                }
                for (std::size_t i = 0; i < columns; ++i) {
                    const json& v = row[i];
                    if (!v.is_number() || !std::isfinite(v.get<double>())) {
                        r.fail("heights", fmt::format("row {} column {}: a height in m expected "
                                                      "(got {})",
                                                      j + 1, i + 1, quoted(v)));
                    }
                    h.heights.push_back(v.get<double>());
                }
            }
            h.samples_x = static_cast<int>(columns);
            h.samples_y = static_cast<int>(heights->size());
        }
        if (image != o.end()) {
            if (!image->is_string()) {
                r.fail("image", fmt::format("a PNG file name expected (got {})", quoted(*image)));
            }
            h.image = image_path(image->get<std::string>(), r);
        }
        check_object(h, "heightfield", number, index);
        out.push_back(std::move(h));
    }

    // an image the page names: one the opened world had (as it names it), or a PNG of the folder
    std::string image_path(const std::string& name, const Read& r) const {
        for (const HeightfieldSpec& h : source.environment.world.heightfields) {
            if (!h.image.empty() && relative_path(h.image, source.file) == name) return h.image;
        }
        try {
            return inside(folder, name, ".png", "image").string();
        } catch (const EditError& e) {
            r.fail("image", e.what());
        }
    }

    // object `index` of the page's list into `w`, numbered `number` among its kind (0: after
    // those of its kind in `w`)
    void read_one(const json& o, int index, int number, WorldSpec& w) {
        // "object 3" of the page's list; an object posted alone (index -1) is "the object"
        const std::string which =
            index >= 0 ? fmt::format("object {}", index + 1) : std::string("the object");
        const auto kind = o.is_object() ? o.find("kind") : o.end();
        if (!o.is_object() || kind == o.end() || !kind->is_string()) {
            throw EditError(
                400, fmt::format("{}: an object with a 'kind' expected ({})", which, kinds_list()),
                index, "kind");
        }
        const std::string k = kind->get<std::string>();
        auto n = [number](const auto& v) {
            return number > 0 ? number : static_cast<int>(v.size()) + 1;
        };
        if (k == "box") {
            read_object(o, index, n(w.boxes), w.boxes, k);
        } else if (k == "wall") {
            read_object(o, index, n(w.walls), w.walls, k);
        } else if (k == "ramp") {
            read_object(o, index, n(w.ramps), w.ramps, k);
        } else if (k == "stairs") {
            read_object(o, index, n(w.stairs), w.stairs, k);
        } else if (k == "cylinder") {
            read_object(o, index, n(w.cylinders), w.cylinders, k);
        } else if (k == "pipe") {
            read_object(o, index, n(w.pipes), w.pipes, k);
        } else if (k == "rubble") {
            read_object(o, index, n(w.rubble), w.rubble, k);
        } else if (k == "heightfield") {
            read_heightfield(o, index, n(w.heightfields), w.heightfields);
        } else {
            throw EditError(400,
                            fmt::format("{}: unknown kind '{}' ({} expected)", which,
                                        k.substr(0, 40), kinds_list()),
                            index, "kind");
        }
    }

    EnvironmentSpec environment(const json& body) {
        if (!body.is_object()) throw EditError(400, "a JSON object expected");
        const auto given = body.find("environment");
        if (given == body.end() || !given->is_object()) {
            throw EditError(400,
                            "field 'environment' expected: {gravity, floor, objects, "
                            "placements}");
        }
        const json& j = *given;
        for (const auto& item : j.items()) {
            const std::string& k = item.key();
            if (k != "gravity" && k != "floor" && k != "objects" && k != "placements") {
                throw EditError(400, fmt::format("environment: unknown field '{}' (it has "
                                                 "gravity, floor, objects, placements)",
                                                 k.substr(0, 40)));
            }
        }
        EnvironmentSpec env;
        WorldSpec& w = env.world;
        {
            Read r{j, "environment", -1, {}};
            r.vec3("gravity", w.gravity, "m/s²");
        }
        if (const auto f = j.find("floor"); f != j.end()) {
            if (!f->is_object())
                throw EditError(
                    400,
                    "floor: an object {enabled, friction, rigid, stiffness, damping} expected");
            Read r{*f, "floor", -1, {}};
            r.flag("enabled", w.floor.enabled);
            r.number("friction", w.floor.friction, "");
            r.flag("rigid", w.floor.rigid);
            r.number("stiffness", w.floor.stiffness, "N/m");
            r.number("damping", w.floor.damping, "N·s/m");
            r.finish();
        }
        const auto objects = j.find("objects");
        if (objects != j.end() && !objects->is_array()) {
            throw EditError(400, "objects: a list of objects expected");
        }
        int index = 0;
        for (const json& o : objects == j.end() ? json::array() : *objects) {
            const auto kind = o.is_object() ? o.find("kind") : o.end();
            if (!o.is_object() || kind == o.end() || !kind->is_string()) {
                throw EditError(400,
                                fmt::format("object {}: an object with a 'kind' expected ({})",
                                            index + 1, kinds_list()),
                                index, "kind");
            }
            read_one(o, index, 0, w);
            ++index;
        }
        const auto places = j.find("placements");
        if (places != j.end() && !places->is_array()) {
            throw EditError(400, "placements: a list of {robot, position, orientation} expected");
        }
        for (const json& p : places == j.end() ? json::array() : *places) {
            const auto robot = p.is_object() ? p.find("robot") : p.end();
            if (robot == p.end() || !robot->is_string() || robot->get<std::string>().empty()) {
                throw EditError(400, "placements: each one names its 'robot'");
            }
            Placement pl;
            pl.robot = robot->get<std::string>();
            for (const Placement& other : env.placements) {
                if (other.robot == pl.robot) {
                    throw EditError(400, fmt::format("robot '{}' is placed twice", pl.robot));
                }
            }
            Read r{p, fmt::format("robot '{}'", pl.robot.substr(0, 60)), -1, {"robot"}};
            r.vec3("position", pl.pose.position, "m");
            r.quat("orientation", pl.pose.orientation);
            r.finish();
            env.placements.push_back(pl);
        }
        // the floor, gravity, limits of the whole world, placements: the engine's words
        try {
            validate(w);
            // where each robot goes, checked on a robot of one module named as it is
            static const RobotSpec probe = make_chain(ChainSpec{});
            for (const Placement& p : env.placements) {
                WorldSpec one;
                one.robots.push_back({probe, p.pose, {}});
                one.robots.back().robot.name = p.robot;
                validate(one);
            }
        } catch (const SpecError& e) {
            const std::string m = e.what();
            throw EditError(400, m, -1, m.rfind("floor", 0) == 0 ? "floor" : "");
        }
        return env;
    }

    json images() const {
        json out = json::array();
        std::error_code ec;
        std::vector<std::string> names;
        for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string n = it->path().filename().string();
            if (n.size() > 4 && n.compare(n.size() - 4, 4, ".png") == 0 && n.front() != '.' &&
                it->is_regular_file(ec)) {
                names.push_back(n);
            }
            if (names.size() >= kMaxImages) break;
        }
        std::sort(names.begin(), names.end());
        for (const std::string& n : names)
            out.push_back(n);
        return out;
    }
};

Editor::Editor(std::function<EditorSource()> open, std::string mode)
    : impl_(std::make_unique<Impl>()) {
    impl_->opener = std::move(open);
    impl_->mode = std::move(mode);
}

Editor::~Editor() = default;

std::string Editor::open() {
    EditorSource src = impl_->opener();
    Impl& m = *impl_;
    std::lock_guard<std::mutex> lock(m.mutex);
    // a page that opens the same world again does not make another page's edits stale
    const std::string before = m.version > 0 ? dump(m.environment_json(m.source.environment)) : "";
    const std::string file_before = m.source.file;
    m.source = std::move(src);
    m.folder = fs::path(m.source.file).parent_path();
    if (m.version == 0 || file_before != m.source.file ||
        before != dump(m.environment_json(m.source.environment))) {
        ++m.version;
    }
    std::error_code ec;
    m.disk_exists = fs::exists(m.source.file, ec);
    m.disk_text.clear();
    if (m.disk_exists) {
        try {
            m.disk_text = read_file(m.source.file);
        } catch (const IoError& e) {
            throw EditError(500, e.what());
        }
    }
    json j;
    j["mode"] = m.mode;
    j["file"] = fs::path(m.source.file).filename().string();
    j["folder"] = m.folder.string();
    j["exists"] = m.disk_exists;
    j["source"] = m.version;
    json kinds = json::object();
    kinds["box"] = describe<BoxSpec>();
    kinds["wall"] = describe<WallSpec>();
    kinds["ramp"] = describe<RampSpec>();
    kinds["stairs"] = describe<StairsSpec>();
    kinds["cylinder"] = describe<CylinderSpec>();
    kinds["pipe"] = describe<PipeSpec>();
    kinds["rubble"] = describe<RubbleSpec>();
    kinds["heightfield"] = describe<HeightfieldSpec>();
    j["kinds"] = kinds;
    j["order"] = kind_names();
    // a new object of each kind: the engine's defaults
    json defaults = json::object();
    defaults["box"] = m.object_json(BoxSpec{});
    defaults["wall"] = m.object_json(WallSpec{}, "wall");
    defaults["ramp"] = m.object_json(RampSpec{}, "ramp");
    defaults["stairs"] = m.object_json(StairsSpec{}, "stairs");
    defaults["cylinder"] = m.object_json(CylinderSpec{}, "cylinder");
    defaults["pipe"] = m.object_json(PipeSpec{}, "pipe");
    defaults["rubble"] = m.object_json(RubbleSpec{}, "rubble");
    defaults["heightfield"] = m.object_json(HeightfieldSpec{}, "heightfield");
    j["defaults"] = defaults;
    j["environment"] = m.environment_json(m.source.environment);
    json robots = json::array();
    for (const RobotSpec& r : m.source.robots) {
        json bodies = json::array();
        for (const BodySpec& b : r.bodies) {
            const Pose& p = b.pose;
            bodies.push_back({{"name", b.name},
                              {"shape", to_string(b.shape)},
                              {"size", {b.size.x, b.size.y, b.size.z}},
                              {"pose",
                               {p.position.x, p.position.y, p.position.z, p.orientation.w,
                                p.orientation.x, p.orientation.y, p.orientation.z}}});
        }
        robots.push_back({{"name", r.name}, {"bodies", bodies}});
    }
    j["robots"] = robots;
    j["images"] = m.images();
    return dump(j);
}

namespace {

json parse_body(const std::string& body) {
    json j;
    std::string error;
    if (!parse_request_json(body, j, error)) throw EditError(400, error);
    return j;
}

json pose_json(const Pose& p) {
    return {p.position.x,    p.position.y,    p.position.z,   p.orientation.w,
            p.orientation.x, p.orientation.y, p.orientation.z};
}

}  // namespace

std::string Editor::shape(const std::string& body) const {
    const json j = parse_body(body);
    Impl& m = *impl_;
    std::lock_guard<std::mutex> lock(m.mutex);
    const auto o = j.is_object() ? j.find("object") : j.end();
    if (o == j.end() || !o->is_object()) throw EditError(400, "field 'object' expected");
    int number = 1;
    if (const auto n = j.find("number"); n != j.end()) {
        if (!n->is_number_integer() || n->get<long long>() < 1 || n->get<long long>() > 1000000) {
            throw EditError(400, "field 'number': the object's number among its kind expected");
        }
        number = n->get<int>();
    }
    // the object alone, numbered as the page numbers it, at the origin without a turn
    json alone = *o;
    if (alone.is_object()) {
        alone["position"] = {0, 0, 0};
        if (alone.contains("yaw")) alone["yaw"] = 0;
        if (alone.contains("orientation")) alone["orientation"] = {1, 0, 0, 0};
    }
    WorldSpec w;
    m.read_one(alone, -1, number, w);
    std::vector<Solid> solids;
    try {
        solids = world_solids(w);
    } catch (const SpecError& e) {
        throw EditError(400, e.what(), -1, "image");
    }
    json out = json::array();
    for (const Solid& s : solids) {
        json so;
        if (s.kind == Solid::Kind::box || s.kind == Solid::Kind::cylinder) {
            so["kind"] = s.kind == Solid::Kind::box ? "box" : "cylinder";
            so["size"] = {s.size.x, s.size.y, s.size.z};
            so["pose"] = pose_json(s.pose);
        } else {
            so["kind"] = "mesh";
            json pos = json::array();
            Solid drawn = s;
            // a heightfield is drawn from at most 257 samples a side
            if (s.kind == Solid::Kind::heightfield &&
                (s.grid.samples_x > 257 || s.grid.samples_y > 257)) {
                HeightGrid& d = drawn.grid;
                const HeightGrid& g = s.grid;
                d.samples_x = std::min(g.samples_x, 257);
                d.samples_y = std::min(g.samples_y, 257);
                d.heights.assign(
                    static_cast<size_t>(d.samples_x) * static_cast<size_t>(d.samples_y), 0);
                for (int b = 0; b < d.samples_y; ++b) {
                    for (int a = 0; a < d.samples_x; ++a) {
                        const int si = static_cast<int>(std::lround(
                            static_cast<double>(a) * (g.samples_x - 1) / (d.samples_x - 1)));
                        const int sj = static_cast<int>(std::lround(
                            static_cast<double>(b) * (g.samples_y - 1) / (d.samples_y - 1)));
                        d.heights[static_cast<size_t>(b) * static_cast<size_t>(d.samples_x) +
                                  static_cast<size_t>(a)] = g.at(si, sj);
                    }
                }
            }
            for (const Triangle& t : triangles(drawn, 24)) {
                for (const Vec3* v : {&t.a, &t.b, &t.c}) {
                    pos.push_back(std::round(v->x * 1e4) / 1e4);
                    pos.push_back(std::round(v->y * 1e4) / 1e4);
                    pos.push_back(std::round(v->z * 1e4) / 1e4);
                }
            }
            so["positions"] = std::move(pos);
        }
        out.push_back(std::move(so));
    }
    return dump({{"solids", out}});
}

std::string Editor::check(const std::string& body) const {
    const json j = parse_body(body);
    Impl& m = *impl_;
    std::lock_guard<std::mutex> lock(m.mutex);
    const EnvironmentSpec env = m.environment(j);
    // the robots where they start, built as gaitlab run builds them: what it would warn of
    json warnings = json::array();
    WorldSpec world = env.world;
    for (const Placement& p : env.placements) {
        for (const RobotSpec& r : m.source.robots) {
            if (r.name == p.robot) world.robots.push_back({r, p.pose, {}});
        }
    }
    if (!world.robots.empty() && solid_count(world) <= kMaxBuiltSolids) {
        try {
            const Simulation sim(world);
            for (const std::string& w : sim.warnings())
                warnings.push_back(w);
        } catch (const Error& e) {
            // an image that cannot be read: the save says so
            warnings.push_back(e.what());
        }
    }
    return dump({{"ok", true}, {"solids", solid_count(env.world)}, {"warnings", warnings}});
}

std::string Editor::save(const std::string& body) {
    const json j = parse_body(body);
    Impl& m = *impl_;
    std::lock_guard<std::mutex> lock(m.mutex);
    if (m.source.file.empty()) throw EditError(409, "open the editor first (GET /api/world)");
    if (!j.is_object()) throw EditError(400, "a JSON object expected");
    for (const auto& item : j.items()) {
        const std::string& k = item.key();
        if (k != "environment" && k != "file" && k != "overwrite" && k != "source") {
            throw EditError(400, fmt::format("save: unknown field '{}' (it takes environment, "
                                             "file, overwrite, source)",
                                             k.substr(0, 40)));
        }
    }
    if (const auto s = j.find("source");
        s != j.end() && (!s->is_number_integer() || s->get<long long>() != m.version)) {
        throw EditError(409,
                        "the world was opened again since (another page, or a new "
                        "simulation): open the editor again");
    }
    const EnvironmentSpec env = m.environment(j);
    std::string target = m.source.file;
    if (const auto f = j.find("file"); f != j.end()) {
        if (!f->is_string()) throw EditError(400, "field 'file': a file name expected");
        target = inside(m.folder, f->get<std::string>(), ".xml", "file").string();
    }
    bool overwrite = false;
    if (const auto o = j.find("overwrite"); o != j.end()) {
        if (!o->is_boolean()) throw EditError(400, "field 'overwrite': true or false expected");
        overwrite = o->get<bool>();
    }
    const std::string name = fs::path(target).filename().string();
    std::error_code ec;
    if (fs::is_symlink(target, ec) ||
        (fs::exists(target, ec) && !fs::is_regular_file(target, ec))) {
        throw EditError(400, fmt::format("{} is not a regular file: nothing saved", name));
    }
    // what another program (an editor, git) changed since the page opened it is not lost
    if (!overwrite && fs::exists(target, ec)) {
        std::string now;
        try {
            now = read_file(target);
        } catch (const IoError& e) {
            throw EditError(500, fmt::format("{}: nothing saved", e.what()));
        }
        const bool same_file = target == m.source.file;
        if (!same_file || !m.disk_exists || now != m.disk_text) {
            throw EditError(409,
                            fmt::format("{} {}: save with overwrite, or under another name", name,
                                        same_file ? "changed on disk since the editor opened it"
                                                  : "exists already"));
        }
    }
    std::string text;
    try {
        text = checked_environment_text(format_environment(env, target));
    } catch (const SpecError& e) {
        throw EditError(400, e.what());
    }
    try {
        write_file_atomic(target, text, MissingFolders::refuse);
    } catch (const IoError& e) {
        throw EditError(500, fmt::format("{} (the file was left as it was)", e.what()));
    }
    if (target == m.source.file) {
        m.disk_text = text;
        m.disk_exists = true;
    }
    return dump({{"ok", true},
                 {"file", name},
                 {"path", target},
                 {"bytes", text.size()},
                 {"solids", solid_count(env.world)}});
}

Server::WorldProvider Editor::provider() {
    return [this](const std::string& action, const std::string& body) {
        Server::Reply r;
        try {
            if (action == "open") {
                r.body = open();
            } else if (action == "shape") {
                r.body = shape(body);
            } else if (action == "check") {
                r.body = check(body);
            } else if (action == "save") {
                r.body = save(body);
            } else {
                throw EditError(404, "no such edit: " + action);
            }
        } catch (const EditError& e) {
            r.status = e.status();
            json j{{"error", e.what()}};
            if (e.object() >= 0) j["object"] = e.object();
            if (!e.field().empty()) j["field"] = e.field();
            r.body = dump(j);
        } catch (const std::exception& e) {
            r.status = 500;
            r.body = dump({{"error", e.what()}});
        }
        return r;
    };
}

EditorSource load_editor_source(const std::string& path,
                                const std::vector<std::string>& robot_files) {
    EditorSource s;
    std::error_code ec;
    s.file = fs::absolute(path, ec).lexically_normal().string();
    if (fs::exists(s.file, ec)) s.environment = read_environment(s.file);
    for (const std::string& f : robot_files) {
        const std::string text = read_file(f);
        // a simulation file names its robots' files; a robot file is one robot
        if (text.find("<simulation") != std::string::npos) {
            const SimulationFile sim = read_simulation(f);
            for (const RobotEntry& r : sim.robots)
                s.robots.push_back(read_robot(resolve_path(f, r.robot)));
        } else {
            s.robots.push_back(read_robot(f));
        }
    }
    return s;
}

}  // namespace gaitlab::viewer
