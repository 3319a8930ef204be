// A request's JSON body as the viewer's routes read it: valid JSON, numbers that fit a double,
// strings without NUL characters (messages quote the strings they refuse, and a NUL would cut
// such a message short).
#pragma once

#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace gaitlab::viewer {

/// Parses `body` into `out`; false, with `error` saying what is wrong, when it is not valid JSON
/// ("malformed JSON at byte N"), holds a number beyond a double's range (nlohmann's parser
/// throws out_of_range there, which is no server fault) or a string holding "\u0000".
inline bool parse_request_json(const std::string& body, nlohmann::json& out, std::string& error) {
    try {
        out = nlohmann::json::parse(body);
    } catch (const nlohmann::json::parse_error& e) {
        error = fmt::format("malformed JSON at byte {}", e.byte);
        return false;
    } catch (const nlohmann::json::exception&) {
        error = "malformed JSON: a number beyond the range of a double (about ±1.8e308)";
        return false;
    }
    // every string, keys too, without recursion (a body may nest thousands deep)
    std::vector<const nlohmann::json*> todo{&out};
    while (!todo.empty()) {
        const nlohmann::json* j = todo.back();
        todo.pop_back();
        if (j->is_string() && j->get_ref<const std::string&>().find('\0') != std::string::npos) {
            error = "malformed JSON: a string holds a NUL character (\\u0000)";
            return false;
        }
        if (j->is_object()) {
            for (auto it = j->begin(); it != j->end(); ++it) {
                if (it.key().find('\0') != std::string::npos) {
                    error = "malformed JSON: a key holds a NUL character (\\u0000)";
                    return false;
                }
                todo.push_back(&it.value());
            }
        } else if (j->is_array()) {
            for (const auto& e : *j)
                todo.push_back(&e);
        }
    }
    return true;
}

}  // namespace gaitlab::viewer
