// Actuation files: joint groups and the controller that drives each, with its parameter values.
// Parameter names are checked when the controller is built (they depend on the controller),
// so each ControllerRef keeps the file and line it came from. See docs/formats.md.
#include <cerrno>
#include <cstdlib>
#include <sstream>

#include <fmt/format.h>

#include "gaitlab/files.h"
#include "gaitlab/robot.h"
#include "gaitlab/xml.h"
#include "xml/xml_io.h"

namespace gaitlab {

namespace {

using xml::Element;

void read_joints(const Element& e, GroupSpec& g) {
    const std::string text = e.required_string("joints");
    e.check([&] {
        try {
            parse_group_joints(text, g);
        } catch (const SpecError& err) {
            throw SpecError(fmt::format("attribute 'joints': {}", err.what()));
        }
    });
}

}  // namespace

void parse_group_joints(const std::string& text, GroupSpec& g) {
    std::istringstream in(text);
    std::string word;
    std::vector<std::string> words;
    while (in >> word)
        words.push_back(word);
    if (words.empty()) throw SpecError("a role or joint numbers expected, got ''");
    if (words.size() == 1 && (words[0] == "pitch" || words[0] == "yaw" || words[0] == "all")) {
        g.role = words[0];
        return;
    }
    // no robot has more joints than kMaxRobotBodies: a mark per joint finds repeats in one pass
    std::vector<bool> listed(static_cast<size_t>(kMaxRobotBodies), false);
    for (const std::string& w : words) {
        char* end = nullptr;
        errno = 0;
        const long n = std::strtol(w.c_str(), &end, 10);
        if (*end != '\0' || errno == ERANGE || n < 1) {
            throw SpecError(fmt::format(
                "'pitch', 'yaw', 'all' or joint numbers (from 1) expected, got '{}'", text));
        }
        if (n > kMaxRobotBodies) {
            throw SpecError(
                fmt::format("joint numbers must be in [1, {}] (got {})", kMaxRobotBodies, n));
        }
        if (listed[static_cast<size_t>(n - 1)]) {
            throw SpecError(fmt::format("joint {} is listed twice", n));
        }
        listed[static_cast<size_t>(n - 1)] = true;
        g.joints.push_back(static_cast<int>(n - 1));
    }
}

namespace {

ControllerRef read_controller(const Element& e) {
    e.children({});
    ControllerRef ref;
    ref.source = e.file();
    ref.line = e.line();
    int kinds = 0;
    for (const std::string& a : e.attribute_names()) {
        bool is_kind = false;
        for (size_t k = 0; k < xml::attrs::controller.size(); ++k) {
            if (a == xml::attrs::controller[k]) {
                ref.kind = static_cast<ControllerRef::Kind>(k);
                ref.name = e.string(a.c_str(), "");
                is_kind = true;
                ++kinds;
            }
        }
        if (!is_kind) ref.params.emplace_back(a, e.required_number(a.c_str()));
    }
    if (kinds != 1) {
        e.fail(
            "exactly one of 'builtin', 'file' or 'template' expected (which controller), "
            "then its parameters, e.g. <controller builtin=\"sine\" amplitude=\"30\"/>");
    }
    if (ref.name.empty()) e.fail(fmt::format("attribute '{}' is empty", to_string(ref.kind)));
    return ref;
}

ActuationSpec read_actuation_element(const Element& root) {
    root.allow(xml::attrs::actuation);
    ActuationSpec a;
    for (const Element& g : root.children({"group"})) {
        // each group makes a controller: as many as a robot can have joints
        if (a.groups.size() >= static_cast<size_t>(kMaxRobotBodies)) {
            g.fail(fmt::format("an actuation has at most {} groups", kMaxRobotBodies));
        }
        g.allow(xml::attrs::group);
        GroupSpec group;
        read_joints(g, group);
        const std::vector<Element> kids = g.children({"controller"});
        if (kids.size() != 1) g.fail("one <controller> per group expected");
        group.controller = read_controller(kids[0]);
        a.groups.push_back(std::move(group));
    }
    return a;
}

void check(const ActuationSpec& a) {
    for (size_t i = 0; i < a.groups.size(); ++i) {
        const GroupSpec& g = a.groups[i];
        const std::string p = fmt::format("group {}: ", i + 1);
        if (g.role.empty() == g.joints.empty()) {
            throw SpecError(p + "a group is a role or a list of joints, exactly one of them");
        }
        if (g.controller.name.empty()) throw SpecError(p + "the controller has no name");
        for (int j : g.joints) {
            if (j < 0) throw SpecError(p + fmt::format("joint numbers start at 1 (got {})", j + 1));
        }
    }
}

}  // namespace

ActuationSpec parse_actuation(std::string_view text, const std::string& file) {
    const xml::Document doc(text, file, "actuation");
    return read_actuation_element(doc.root());
}

ActuationSpec read_actuation(const std::string& path) {
    return parse_actuation(xml::read_text(path), path);
}

std::string format_actuation(const ActuationSpec& a) {
    check(a);
    xml::Writer w;
    w.open("actuation");
    for (const GroupSpec& g : a.groups) {
        w.open("group");
        if (!g.role.empty()) {
            w.attr("joints", g.role);
        } else {
            std::string list;
            for (int j : g.joints)
                list += (list.empty() ? "" : " ") + std::to_string(j + 1);
            w.attr("joints", list);
        }
        w.open("controller");
        w.attr(to_string(g.controller.kind), g.controller.name);
        for (const auto& [name, value] : g.controller.params)
            w.attr(name.c_str(), value);
        w.close();
        w.close();
    }
    w.close();
    return w.text();
}

void write_actuation(const std::string& path, const ActuationSpec& a) {
    write_file_atomic(path, format_actuation(a), MissingFolders::create);
}

}  // namespace gaitlab
