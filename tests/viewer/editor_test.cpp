// The environment editor's routes (editor.h): what a page opens, the shapes it draws, and
// saving: a saved world reads back as the engine reads environment files; every bad input
// (negative sizes, friction below 0, NaN, an unknown kind or field, a name outside the folder,
// a file changed on disk) is refused naming the object and field, and nothing is written.
// Then the same routes through the server (content type, token), and `gaitlab edit`'s command
// line.
#include "gaitlab/viewer/editor.h"

#include <filesystem>
#include <string>

#include <httplib.h>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "cli/run_gaitlab.h"
#include "gaitlab/geometry.h"
#include "gaitlab/xml.h"

using namespace gaitlab;
using namespace gaitlab::viewer;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;
using json = nlohmann::json;

namespace {

const char* kFlat = R"(<?xml version="1.0"?>
<!-- a floor and a step -->
<gaitlab version="1">
    <environment gravity="0 0 -9.81">
        <floor friction="0.8"/>
        <box size="0.05 0.4 0.01" position="-0.45 0 0.005" friction="0.8"/>
        <stairs steps="2" step_height="0.02" step_depth="0.2" width="0.5" position="1 0 0" yaw="90"/>
        <heightfield length="0.6" width="0.4" position="0 -2 0" samples="3 2">
            <heights>
                0 0.003 0.006
                0.002 0.005 0.008
            </heights>
        </heightfield>
        <place robot="snake" position="0 0.1 0"/>
    </environment>
</gaitlab>
)";

// an editor of `path`, as `gaitlab edit` makes it
Editor editor_of(const std::string& path) {
    return Editor([path] { return load_editor_source(path, {}); }, "edit");
}

// the refusal of `fn` (it must throw EditError)
template <class Fn>
EditError refusal(Fn fn) {
    try {
        fn();
    } catch (const EditError& e) {
        return e;
    }
    FAIL("no EditError");
    return EditError(0, "");
}

// the opened environment with `change` made to it, as a save request
std::string with(const json& opened, const std::function<void(json&)>& change) {
    json env = opened["environment"];
    change(env);
    return json{{"environment", env}, {"source", opened["source"]}}.dump();
}

}  // namespace

TEST_CASE("editor: a page opens the file's world with its fields, defaults and robots") {
    TempDir dir("editor");
    const std::string path = dir / "flat.xml";
    write_text(path, kFlat);
    write_text(dir / "terrain.png", "");  // offered for new heightfields (by name only)
    Editor ed = editor_of(path);
    const json j = json::parse(ed.open());
    CHECK(j["mode"] == "edit");
    CHECK(j["file"] == "flat.xml");
    CHECK(j["exists"] == true);
    const json& env = j["environment"];
    CHECK(env["floor"]["friction"] == 0.8);
    REQUIRE(env["objects"].size() == 3);
    CHECK(env["objects"][0]["kind"] == "box");
    CHECK(env["objects"][0]["position"] == json({-0.45, 0, 0.005}));
    CHECK(env["objects"][1]["kind"] == "stairs");
    CHECK(env["objects"][1]["yaw"].get<double>() == Approx(90));
    CHECK(env["objects"][2]["grid"] == 0);  // its heights stay on this side
    CHECK(env["placements"][0]["robot"] == "snake");
    CHECK(env["placements"][0]["position"] == json({0, 0.1, 0}));
    CHECK(j["kinds"]["ramp"][0] == json({{"name", "slope"}, {"type", "number"}, {"unit", "deg"}}));
    CHECK(j["order"].size() == 8);
    CHECK(j["defaults"]["stairs"]["steps"] == 3);
    CHECK(j["images"] == json({"terrain.png"}));
}

TEST_CASE("editor: a moved box, a new ramp and friction save as the engine reads them") {
    TempDir dir("editor");
    const std::string path = dir / "flat.xml";
    write_text(path, kFlat);
    Editor ed = editor_of(path);
    const json opened = json::parse(ed.open());
    const json r = json::parse(ed.save(with(opened, [](json& env) {
        env["objects"][0]["position"] = {0.6, 0.2, 0.005};
        env["objects"][0]["friction"] = 0.3;
        env["objects"][0]["orientation"] = {std::cos(0.25), 0, 0, std::sin(0.25)};  // 30 deg
        env["objects"].push_back({{"kind", "ramp"}, {"slope", 15}, {"position", {2, 0, 0}}});
        env["floor"]["friction"] = 0.5;
        env["placements"][0]["position"] = {0.1, -0.3, 0};
    })));
    CHECK(r["ok"] == true);
    CHECK(r["file"] == "flat.xml");
    const EnvironmentSpec back = read_environment(path);
    REQUIRE(back.world.boxes.size() == 1);
    CHECK(back.world.boxes[0].pose.position.x == 0.6);
    CHECK(back.world.boxes[0].pose.position.y == 0.2);
    CHECK(back.world.boxes[0].friction == 0.3);
    CHECK(back.world.boxes[0].pose.orientation.z == Approx(std::sin(0.25)));
    REQUIRE(back.world.ramps.size() == 1);
    CHECK(rad_to_deg(back.world.ramps[0].slope) == Approx(15));
    CHECK(back.world.ramps[0].position.x == 2);
    CHECK(back.world.floor.friction == 0.5);
    CHECK(back.world.stairs.size() == 1);
    // the stored heights went back into the file
    REQUIRE(back.world.heightfields.size() == 1);
    CHECK(back.world.heightfields[0].heights.size() == 6);
    CHECK(back.world.heightfields[0].heights[5] == 0.008);
    CHECK(back.placements[0].pose.position.y == -0.3);
    // saved again with nothing changed: the same text
    const std::string once = read_text(path);
    const json again = json::parse(ed.open());
    ed.save(with(again, [](json&) {}));
    CHECK(read_text(path) == once);
}

TEST_CASE("editor: a compliant floor keeps its stiffness and damping through the page") {
    TempDir dir("editor");
    const std::string path = dir / "soft.xml";
    std::string text = kFlat;
    text.replace(text.find("<floor friction=\"0.8\"/>"), 23,
                 "<floor friction=\"0.8\" stiffness=\"10000\" damping=\"20\"/>");
    write_text(path, text);
    Editor ed = editor_of(path);
    const json opened = json::parse(ed.open());
    CHECK(opened["environment"]["floor"]["stiffness"] == 10000.0);
    CHECK(opened["environment"]["floor"]["damping"] == 20.0);
    // an edit elsewhere keeps them
    ed.save(with(opened, [](json& env) { env["floor"]["friction"] = 0.5; }));
    EnvironmentSpec back = read_environment(path);
    CHECK(back.world.floor.friction == 0.5);
    CHECK(back.world.floor.stiffness == 1e4);
    CHECK(back.world.floor.damping == 20.0);
    // rigid with a stiffness is refused as the engine refuses it
    const json again = json::parse(ed.open());
    const EditError e =
        refusal([&] { ed.save(with(again, [](json& env) { env["floor"]["rigid"] = true; })); });
    CHECK(e.status() == 400);
    CHECK_THAT(e.what(), Catch::Contains("a rigid floor takes no stiffness"));
    back = read_environment(path);
    CHECK_FALSE(back.world.floor.rigid);
    CHECK(back.world.floor.damping == 20.0);
    // both removed: the defaults, written out
    const json third = json::parse(ed.open());
    ed.save(with(third, [](json& env) {
        env["floor"].erase("stiffness");
        env["floor"].erase("damping");
    }));
    CHECK(read_text(path).find("stiffness=\"3000\" damping=\"60\"") != std::string::npos);
    // rigid, as the page's check box sends it: neither value
    const json fourth = json::parse(ed.open());
    ed.save(with(fourth, [](json& env) {
        env["floor"].erase("stiffness");
        env["floor"].erase("damping");
        env["floor"]["rigid"] = true;
    }));
    back = read_environment(path);
    CHECK(back.world.floor.rigid);
    CHECK_FALSE(back.world.floor.stiffness);
    CHECK_FALSE(back.world.floor.damping);
    CHECK(json::parse(ed.open())["environment"]["floor"]["rigid"] == true);
    const json fifth = json::parse(ed.open());
    const EditError word =
        refusal([&] { ed.save(with(fifth, [](json& env) { env["floor"]["rigid"] = "yes"; })); });
    CHECK(word.status() == 400);
    CHECK_THAT(word.what(), Catch::Contains("true or false expected"));
}

TEST_CASE("editor: bad values name the object and field, and nothing is saved") {
    TempDir dir("editor");
    const std::string path = dir / "flat.xml";
    write_text(path, kFlat);
    Editor ed = editor_of(path);
    const json opened = json::parse(ed.open());
    struct Case {
        std::function<void(json&)> change;
        const char* message;
        int object;
        const char* field;
    };
    const Case cases[] = {
        {[](json& e) {
             e["objects"][0]["size"] = {0.1, -0.2, 0.1};
         },
         "box 1 size y must be positive (got -0.2 m)", 0, "size"},
        {[](json& e) { e["objects"][0]["friction"] = -0.5; },
         "box 1 friction must be in [0, 1] (got -0.5)", 0, "friction"},
        {[](json& e) { e["objects"][0]["friction"] = "nan"; },
         "box 1 friction must be in [0, 1] (got nan)", 0, "friction"},
        {[](json& e) { e["objects"][1]["step_depth"] = "abc"; },
         "stairs 1 step_depth: a number in m expected (got \"abc\")", 1, "step_depth"},
        {[](json& e) { e["objects"][1]["steps"] = 2.5; },
         "stairs 1 steps: a whole number in [-2147483648, 2147483647] expected (got 2.5)", 1,
         "steps"},
        {[](json& e) { e["objects"][1]["steps"] = 0; },
         "stairs 1 steps must be in [1, 1000] (got 0)", 1, "steps"},
        {[](json& e) {
             e["objects"].push_back({{"kind", "ramp"}, {"slope", 95}});
         },
         "ramp 1 slope must be between 0 and 90 deg, both excluded (got 95 deg)", 3, "slope"},
        {[](json& e) {
             e["objects"].push_back({{"kind", "boulder"}});
         },
         "object 4: unknown kind 'boulder' (box, wall, ramp, stairs, cylinder, pipe, rubble, "
         "heightfield expected)",
         3, "kind"},
        {[](json& e) { e["objects"][0]["frction"] = 0.5; },
         "box 1: unknown field 'frction' (a box has size, position, orientation, mass, friction)",
         0, "frction"},
        {[](json& e) {
             e["objects"][0]["position"] = {1, 2};
         },
         "box 1 position: three numbers (x y z, m) expected (got [1,2])", 0, "position"},
        {[](json& e) {
             e["objects"].push_back({{"kind", "cylinder"}, {"mass", -1}});
         },
         "cylinder 1 mass must not be negative (got -1 kg)", 3, "mass"},
        {[](json& e) {
             e["objects"].push_back({{"kind", "rubble"}, {"min_size", 0.1}, {"max_size", 0.05}});
         },
         "rubble 1 max_size must not be below min_size (got 0.05 < 0.1 m)", 3, "max_size"},
        {[](json& e) { e["objects"][2]["grid"] = 7; },
         "heightfield 1 grid: the number of a stored grid of the file expected (got 7)", 2, "grid"},
        {[](json& e) { e["floor"]["friction"] = 1.5; },
         "floor friction must be in [0, 1] (got 1.5)", -1, "floor"},
        {[](json& e) {
             e["placements"][0]["position"] = {20000, 0, 0};
         },
         "robot 'snake' position x must be in [-10000, 10000] m (got 20000)", -1, ""},
        {[](json& e) { e["placements"].push_back(e["placements"][0]); },
         "robot 'snake' is placed twice", -1, ""},
    };
    const std::string before = read_text(path);
    for (const Case& c : cases) {
        const std::string body = with(opened, c.change);
        INFO(body);
        const EditError e = refusal([&] { ed.save(body); });
        CHECK(e.status() == 400);
        CHECK(std::string(e.what()) == c.message);
        CHECK(e.object() == c.object);
        CHECK(e.field() == c.field);
        // check says the same
        const EditError e2 = refusal([&] { ed.check(body); });
        CHECK(std::string(e2.what()) == c.message);
    }
    CHECK(read_text(path) == before);
    // malformed requests
    auto said = [&](const std::string& body) {
        return std::string(refusal([&] { ed.save(body); }).what());
    };
    CHECK(said("{\"environment\": [") == "malformed JSON at byte 18");
    CHECK(said("[1]") == "a JSON object expected");
    CHECK(said("{}") == "field 'environment' expected: {gravity, floor, objects, placements}");
    CHECK(read_text(path) == before);
}

TEST_CASE("editor: saves go into the file's folder only, and never over changes made meanwhile") {
    TempDir dir("editor");
    std::filesystem::create_directories(dir.path / "sub");
    const std::string path = dir.file("sub/flat.xml");
    write_text(path, kFlat);
    write_text(dir / "outside.xml", "mine");
    Editor ed = editor_of(path);
    const json opened = json::parse(ed.open());
    auto save_as = [&](const json& file, bool overwrite = false) {
        json body = json::parse(with(opened, [](json&) {}));
        body["file"] = file;
        if (overwrite) body["overwrite"] = true;
        return body.dump();
    };
    for (const char* bad : {"../outside.xml", "/tmp/x.xml", "a/b.xml", "..", ".hidden.xml",
                            "flat.txt", "", "x.xml\\..\\y.xml"}) {
        INFO(bad);
        const EditError e = refusal([&] { ed.save(save_as(bad)); });
        CHECK(e.status() == 400);
        CHECK(std::string(e.what()).find("file: a file name in the folder " +
                                         (dir.path / "sub").string() +
                                         " ending in .xml expected, without folders") == 0);
    }
    const std::string not_a_name = refusal([&] { ed.save(save_as(3)); }).what();
    CHECK(not_a_name == "field 'file': a file name expected");
    CHECK(read_text(dir / "outside.xml") == "mine");
    // another name in the folder
    CHECK(json::parse(ed.save(save_as("copy.xml")))["file"] == "copy.xml");
    CHECK(read_environment(dir.file("sub/copy.xml")).world.stairs.size() == 1);
    // it exists now: not replaced without overwrite
    const EditError exists = refusal([&] { ed.save(save_as("copy.xml")); });
    CHECK(exists.status() == 409);
    CHECK(std::string(exists.what()) ==
          "copy.xml exists already: save with overwrite, or under another name");
    ed.save(save_as("copy.xml", true));
    // the file changed on disk since the page opened it (another editor, git)
    write_text(path, std::string(kFlat) + "<!-- by hand -->\n");
    const EditError changed = refusal([&] { ed.save(with(opened, [](json&) {})); });
    CHECK(changed.status() == 409);
    CHECK(std::string(changed.what()) ==
          "flat.xml changed on disk since the editor opened it: save with overwrite, or under "
          "another name");
    CHECK(read_text(path).find("by hand") != std::string::npos);
    // a page that opened the world before it changed (another page opened it since)
    json stale = json::parse(with(opened, [](json&) {}));
    std::string other = kFlat;
    other.replace(other.find("0.8"), 3, "0.7");
    write_text(path, other);
    const json reopened = json::parse(ed.open());
    const int stale_status = refusal([&] { ed.save(stale.dump()); }).status();
    CHECK(stale_status == 409);
    stale["source"] = reopened["source"];
    stale["overwrite"] = true;
    CHECK(json::parse(ed.save(stale.dump()))["ok"] == true);
    CHECK(read_environment(path).world.floor.friction == 0.8);
}

TEST_CASE("editor: a save that cannot be written leaves the old file as it was") {
    TempDir dir("editor");
    const std::string path = dir / "flat.xml";
    write_text(path, kFlat);
    Editor ed = editor_of(path);
    const json opened = json::parse(ed.open());
    // a folder where the file would go: the write fails, the old file stays
    std::filesystem::create_directories(dir.path / "taken.xml");
    json body = json::parse(with(opened, [](json& e) { e["objects"].clear(); }));
    body["file"] = "taken.xml";
    const EditError e = refusal([&] { ed.save(body.dump()); });
    CHECK(std::string(e.what()) == "taken.xml is not a regular file: nothing saved");
    CHECK(read_text(path) == kFlat);
}

TEST_CASE("editor: shapes are the engine's solids of one object in its own frame") {
    TempDir dir("editor");
    const std::string path = dir / "flat.xml";
    write_text(path, kFlat);
    Editor ed = editor_of(path);
    ed.open();
    const json s = json::parse(ed.shape(
        R"({"object": {"kind": "stairs", "steps": 2, "step_depth": 0.2, "position": [5, 5, 0], "yaw": 40}, "number": 2})"));
    REQUIRE(s["solids"].size() == 2);
    CHECK(s["solids"][1]["kind"] == "box");
    CHECK(s["solids"][1]["pose"][0].get<double>() == Approx(0.3));  // not moved, not turned
    CHECK(s["solids"][1]["size"][2].get<double>() == Approx(0.04));
    const json ramp = json::parse(ed.shape(R"({"object": {"kind": "ramp"}})"));
    CHECK(ramp["solids"][0]["kind"] == "mesh");
    CHECK(ramp["solids"][0]["positions"].size() % 9 == 0);
    const json hf = json::parse(ed.shape(R"({"object": {"kind": "heightfield", "grid": 0}})"));
    CHECK(hf["solids"][0]["kind"] == "mesh");
    const EditError e =
        refusal([&] { ed.shape(R"({"object": {"kind": "pipe", "sides": 2}, "number": 3})"); });
    CHECK(std::string(e.what()) == "pipe 3 sides must be in [3, 256] (got 2)");
    CHECK(e.field() == "sides");
    const EditError img =
        refusal([&] { ed.shape(R"({"object": {"kind": "heightfield", "image": "../etc.png"}})"); });
    CHECK(img.field() == "image");
    CHECK(std::string(img.what()).find("heightfield 1 image: image: a file name in the folder") ==
          0);
    // an object posted alone is "the object", not "object 0" (the list's objects count from 1)
    const EditError kind =
        refusal([&] { ed.shape(R"({"object": {"kind": "nope"}, "number": 1})"); });
    CHECK_THAT(std::string(kind.what()), Catch::StartsWith("the object: unknown kind 'nope' ("));
}

TEST_CASE("editor: through the server, edits need JSON, and the token beyond loopback") {
    TempDir dir("editor");
    const std::string path = dir / "flat.xml";
    write_text(path, kFlat);
    Editor ed = editor_of(path);
    {
        Server plain({});
        httplib::Client c("127.0.0.1", plain.port());
        {  // no editor here: the page is told so, the editing routes are not there
            auto none = c.Get("/api/world");
            REQUIRE(none);
            CHECK(none->status == 200);
            CHECK(json::parse(none->body) == json{{"editable", false}});
            CHECK(c.Post("/api/world/check", "{}", "application/json")->status == 404);
        }
        plain.set_world_provider(ed.provider());
        auto r = c.Get("/api/world");
        REQUIRE(r);
        CHECK(r->status == 200);
        const json opened = json::parse(r->body);
        // a form post (what another site's page may send) is refused
        r = c.Post("/api/world/save", with(opened, [](json&) {}), "text/plain");
        CHECK(r->status == 415);
        r = c.Post("/api/world/save",
                   with(opened, [](json& e) { e["objects"][0]["friction"] = -1; }),
                   "application/json");
        CHECK(r->status == 400);
        const json err = json::parse(r->body);
        CHECK(err["error"] == "box 1 friction must be in [0, 1] (got -1)");
        CHECK(err["object"] == 0);
        CHECK(err["field"] == "friction");
        r = c.Post("/api/world/check", with(opened, [](json&) {}), "application/json");
        CHECK(r->status == 200);
        CHECK(json::parse(r->body)["solids"] == 4);  // a box, two steps, a heightfield
        CHECK(read_text(path) == kFlat);
    }
    {
        ServerOptions o;
        o.token = "0123456789abcdef0123456789abcdef";
        Server guarded(o);
        guarded.set_world_provider(ed.provider());
        httplib::Client c("127.0.0.1", guarded.port());
        CHECK(c.Get("/api/world")->status == 403);
        CHECK(c.Post("/api/world/save", "{}", "application/json")->status == 403);
        CHECK(c.Get("/api/world?token=0123456789abcdef0123456789abcdef")->status == 200);
    }
}

TEST_CASE("gaitlab edit: a missing file is made after saying so, unreadable ones are refused") {
    TempDir dir("editor_cli");
    // a file that does not parse: its file and line, and it stays
    write_text(dir / "bad.xml",
               std::string(kFlat).replace(std::string(kFlat).find("0.8"), 3, "-0.8"));
    auto r = test::run_gaitlab({"edit", "bad.xml", "--port", "0"}, dir.str());
    CHECK(r.status == 2);
    CHECK(r.err ==
          "gaitlab: --port: a port number from 1 to 65535 expected (got '0'; leave --port out "
          "for any free port)\n");
    Server taken({});
    r = test::run_gaitlab({"edit", "bad.xml", "--port", std::to_string(taken.port())}, dir.str());
    CHECK(r.status == 1);
    CHECK(r.err.find("bad.xml:5: environment/floor[1]: floor friction must be in [0, 1] (got "
                     "-0.8)") != std::string::npos);
    r = test::run_gaitlab({"edit", "world.txt"}, dir.str());
    CHECK(r.status == 2);
    CHECK(r.err == "gaitlab: world.txt: an environment file (ENV.xml) expected\n");
    r = test::run_gaitlab({"edit", "nowhere/new.xml"}, dir.str());
    CHECK(r.status == 1);
    CHECK(r.err.find("gaitlab: nowhere/new.xml: the folder ") == 0);
    r = test::run_gaitlab({"edit"}, dir.str());
    CHECK(r.status == 2);
    CHECK(r.err.find("an environment file expected") != std::string::npos);
    // a new file, on a taken port: said, made, then the port's message
    r = test::run_gaitlab({"edit", "new.xml", "--port", std::to_string(taken.port())}, dir.str());
    CHECK(r.status == 1);
    CHECK(r.err.find("gaitlab: new.xml does not exist: creating it (a floor, nothing on it)\n") ==
          0);
    CHECK(r.err.find("port " + std::to_string(taken.port()) + " is in use") != std::string::npos);
    CHECK(read_environment(dir / "new.xml").world.floor.enabled);
}

TEST_CASE("editor: a robot placed inside an object is warned of, as gaitlab run warns") {
    TempDir dir("editor");
    const std::string path = dir / "flat.xml";
    write_text(path, kFlat);
    EditorSource src = load_editor_source(path, {});
    ChainSpec chain;
    chain.name = "snake";
    chain.modules = 4;
    src.robots.push_back(make_chain(chain));
    Editor ed([src] { return src; }, "edit");
    const json opened = json::parse(ed.open());
    // clear of everything: no warning
    json r = json::parse(ed.check(with(opened, [](json&) {})));
    CHECK(r["warnings"].empty());
    // a box over its tail
    r = json::parse(ed.check(with(opened, [](json& e) {
        e["objects"][0]["position"] = {0.02, 0.1, 0.005};
        e["objects"][0]["size"] = {0.1, 0.1, 0.1};
        e["objects"][0]["position"][2] = 0.05;
    })));
    REQUIRE(r["warnings"].size() == 1);
    CHECK(r["warnings"][0].get<std::string>().find("deep inside box 1: the contact solver will "
                                                   "throw it out") != std::string::npos);
}

TEST_CASE(
    "editor: a heightfield from numbers saves as the engine reads it, and its heights round-trip") {
    TempDir dir("editor");
    const std::string path = dir / "flat.xml";
    write_text(path, kFlat);
    Editor ed = editor_of(path);
    const json opened = json::parse(ed.open());
    // the stored grid comes as numbers: rows along y
    CHECK(opened["environment"]["objects"][2]["heights"] ==
          json::parse("[[0, 0.003, 0.006], [0.002, 0.005, 0.008]]"));
    // a new one of 3 rows of 4, 0.1 m cells; and the stored one edited by its numbers
    const json rows = json::parse(
        "[[0, 0.01, 0.02, 0.03], [0.005, 0.015, 0.025, 0.035], "
        "[-0.01, 0, 0.0125, 0.1]]");
    const json r = json::parse(ed.save(with(opened, [&rows](json& env) {
        env["objects"][2]["heights"][1][2] = 0.02;
        env["objects"].push_back({{"kind", "heightfield"},
                                  {"length", 0.3},
                                  {"width", 0.2},
                                  {"position", {1, 1, 0}},
                                  {"heights", rows}});
    })));
    CHECK(r["ok"] == true);
    const EnvironmentSpec back = read_environment(path);
    REQUIRE(back.world.heightfields.size() == 2);
    CHECK(back.world.heightfields[0].heights ==
          std::vector<double>{0, 0.003, 0.006, 0.002, 0.005, 0.02});
    const HeightfieldSpec& made = back.world.heightfields[1];
    CHECK(made.samples_x == 4);
    CHECK(made.samples_y == 3);
    CHECK(made.length == 0.3);
    CHECK(made.width == 0.2);
    std::vector<double> flat;
    for (const json& row : rows)
        for (const json& v : row)
            flat.push_back(v.get<double>());
    CHECK(made.heights == flat);
    // opened again, the numbers are the same
    const json again = json::parse(ed.open());
    CHECK(again["environment"]["objects"][3]["heights"] == rows);

    // bad grids: the object, the field and what is expected; nothing is saved
    const std::string saved = read_text(path);
    struct Case {
        json heights;
        const char* says;
    };
    const Case cases[] = {
        {json::parse("[[0, 1, 2]]"), "heightfield 3 heights: rows of heights in m expected"},
        {json::parse("[[0, 1], [2]]"), "heightfield 3 heights: row 2 has 1 heights, row 1 has 2"},
        {json::parse("[[0, 1], [2, \"x\"]]"),
         "heightfield 3 heights: row 2 column 2: a height in m expected (got \"x\")"},
        {json::parse("[[0], [1]]"), "at least 2 by 2) (got [[0],[1]])"},
        {json::parse("\"1 2 3\""), "heightfield 3 heights: rows of heights in m expected"},
    };
    for (const Case& c : cases) {
        const EditError e = refusal([&] {
            ed.save(with(again, [&c](json& env) {
                env["objects"].push_back(
                    {{"kind", "heightfield"}, {"position", {2, 2, 0}}, {"heights", c.heights}});
            }));
        });
        INFO(e.what());
        CHECK(std::string(e.what()).find(c.says) != std::string::npos);
        CHECK(e.field() == "heights");
        CHECK(e.object() == 4);
    }
    // an image and heights: one of them
    const EditError both = refusal([&] {
        ed.save(with(again, [](json& env) { env["objects"][3]["image"] = "terrain.png"; }));
    });
    CHECK(std::string(both.what()).find("one of them") != std::string::npos);
    CHECK(read_text(path) == saved);
}
