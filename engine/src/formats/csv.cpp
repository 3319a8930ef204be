#include "formats/csv.h"

#include <charconv>
#include <cmath>
#include <iterator>

#include <fmt/format.h>

namespace gaitlab::formats {

void append_field(std::string& out, std::string_view field) {
    if (field.find_first_of(",\"\n\r") == std::string_view::npos) {
        out.append(field);
        return;
    }
    out.push_back('"');
    for (char c : field) {
        if (c == '"') out.push_back('"');
        out.push_back(c);
    }
    out.push_back('"');
}

void append_number(std::string& out, double v) {
    if (std::isnan(v)) {
        out.append("nan");
        return;
    }
    // the shortest decimal that reads back to the same bits (to_chars without a precision),
    // into a local buffer: the recorder writes hundreds of numbers per row
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, static_cast<size_t>(r.ptr - buf));
}

std::string csv_line(const std::vector<std::string>& fields) {
    std::string out;
    for (size_t i = 0; i < fields.size(); ++i) {
        if (i > 0) out.push_back(',');
        append_field(out, fields[i]);
    }
    return out;
}

bool split_line(std::string_view line, std::vector<std::string>& fields) {
    fields.clear();
    std::string field;
    size_t i = 0;
    for (;;) {
        field.clear();
        if (i < line.size() && line[i] == '"') {
            ++i;
            for (;;) {
                if (i >= line.size()) return false;
                if (line[i] == '"') {
                    if (i + 1 < line.size() && line[i + 1] == '"') {
                        field.push_back('"');
                        i += 2;
                        continue;
                    }
                    ++i;
                    break;
                }
                field.push_back(line[i++]);
            }
            // anything between the closing quote and the next comma is kept as written
            while (i < line.size() && line[i] != ',')
                field.push_back(line[i++]);
        } else {
            while (i < line.size() && line[i] != ',')
                field.push_back(line[i++]);
        }
        if (!field.empty() && field.back() == '\r') field.pop_back();
        fields.push_back(field);
        if (i >= line.size()) return true;
        ++i;  // the comma
    }
}

bool parse_number(std::string_view text, double& v) {
    if (text.empty()) return false;
    const char* first = text.data();
    const char* last = first + text.size();
    if (*first == '+') ++first;  // from_chars takes no '+'
    // locale-independent and exact; out of range values are errors, as they are never written
    const auto r = std::from_chars(first, last, v);
    return r.ec == std::errc() && r.ptr == last;
}

}  // namespace gaitlab::formats
