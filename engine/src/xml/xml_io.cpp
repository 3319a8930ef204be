#include "xml/xml_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>

#include <fmt/format.h>

#include "gaitlab/files.h"
#include "gaitlab/suggest.h"

namespace gaitlab::xml {

namespace {

std::vector<std::string> to_strings(std::initializer_list<const char*> names) {
    return {names.begin(), names.end()};
}

std::string quoted_list(const std::vector<const char*>& names) {
    std::string out;
    for (const char* n : names) {
        if (!out.empty()) out += ", ";
        out += fmt::format("'{}'", n);
    }
    return out;
}

// what a tinyxml2 parse error means, in the words of someone who wrote the file
std::string describe_xml_error(tinyxml2::XMLError e) {
    switch (e) {
        case tinyxml2::XML_ERROR_EMPTY_DOCUMENT:
            return "the file holds no element (it is empty, or spaces only)";
        case tinyxml2::XML_ERROR_PARSING_ELEMENT:
            return "an element that is not well formed (<name attribute=\"value\" ...> or "
                   "<name ... /> expected)";
        case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE:
            return "an attribute that is not name=\"value\" (values are quoted)";
        case tinyxml2::XML_ERROR_PARSING_TEXT:
            return "text where an element is expected (a stray '<' or '&', or text outside the "
                   "root element; write &lt; and &amp; for the characters themselves)";
        case tinyxml2::XML_ERROR_PARSING_CDATA:
            return "a <![CDATA[ section that does not end with ]]>";
        case tinyxml2::XML_ERROR_PARSING_COMMENT:
            return "a comment that does not end with -->";
        case tinyxml2::XML_ERROR_PARSING_DECLARATION:
            return "a declaration that is not <?xml version=\"1.0\"?>";
        case tinyxml2::XML_ERROR_PARSING_UNKNOWN:
            return "a <! ...> that is not XML";
        case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT:
            return "the element that starts here is closed by an end tag of another name (an "
                   "element <a ...> ends with </a>)";
        case tinyxml2::XML_ERROR_PARSING:
            return "the element that starts here is never closed (its end tag is missing, or the "
                   "file ends early)";
        case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED:
            return "elements nested deeper than XML files here ever need";
        default:
            return tinyxml2::XMLDocument::ErrorIDToName(e);
    }
}

bool is_name_char(char c) {
    const auto u = static_cast<unsigned char>(c);
    return std::isalnum(u) || c == '_' || c == '-' || c == '.' || c == ':' || u >= 0x80;
}

// the name in the reference that starts at text[i] ('&'): "lt", "#65", "#x41"; empty when
// the '&' starts no reference
std::string_view reference_name(std::string_view text, size_t i) {
    const size_t start = i + 1;
    const bool hex = text.substr(start, 2) == "#x";
    const bool number = hex || text.substr(start, 1) == "#";
    const size_t first = start + (hex ? 2 : number ? 1 : 0);
    size_t end = first;
    while (end < text.size()) {
        const auto c = static_cast<unsigned char>(text[end]);
        if (!(hex ? std::isxdigit(c) : number ? std::isdigit(c) : is_name_char(text[end]))) break;
        ++end;
    }
    if (end == first || end == text.size() || text[end] != ';') return {};
    return text.substr(start, end - start);
}

// tinyxml2 replaces XML's five entities and character references and keeps any other &name;
// as written: a DTD's entity would be read as its own name ("&h;"), and a '&' that is no
// reference becomes another character when a reference precedes it in the same value. So
// entity declarations, other entities and stray '&' are refused, at their line, before tinyxml2
// reads the text.
void check_entities(std::string_view text, const std::string& file) {
    int line = 1;
    size_t i = 0;
    const auto at = [&](std::string_view s) { return text.substr(i, s.size()) == s; };
    // moves past the next `end`, counting lines; to the end of the text if there is none
    const auto skip_past = [&](std::string_view end) {
        const size_t found = text.find(end, i);
        const size_t stop = found == std::string_view::npos ? text.size() : found + end.size();
        line +=
            static_cast<int>(std::count(text.begin() + static_cast<std::ptrdiff_t>(i),
                                        text.begin() + static_cast<std::ptrdiff_t>(stop), '\n'));
        i = stop;
    };
    const auto fail = [&](const std::string& message) {
        throw FormatError(fmt::format("{}:{}: {}", file, line, message), file, line);
    };
    while (i < text.size()) {
        if (at("<!--")) {
            skip_past("-->");
        } else if (at("<![CDATA[")) {
            skip_past("]]>");
        } else if (at("<?")) {
            skip_past("?>");
        } else if (at("<!DOCTYPE")) {
            // to its closing '>', past quoted text and the [ ... ] of declarations
            int depth = 0;
            for (i += 9; i < text.size(); ++i) {
                const char c = text[i];
                if (c == '\n') ++line;
                if (c == '"' || c == '\'') {
                    ++i;
                    skip_past(std::string_view(&c, 1));
                    --i;
                } else if (at("<!--")) {
                    skip_past("-->");
                    --i;
                } else if (at("<!ENTITY")) {
                    fail(
                        "entity declarations (<!ENTITY ...>) are not supported: write the "
                        "values out where they are used");
                } else if (c == '[') {
                    ++depth;
                } else if (c == ']') {
                    --depth;
                } else if (c == '>' && depth <= 0) {
                    break;
                }
            }
            ++i;
        } else {
            if (text[i] == '\n') ++line;
            if (text[i] == '&') {
                const std::string_view name = reference_name(text, i);
                // tinyxml2 would keep a stray '&', or write another character for it when a
                // reference came before it in the same value
                if (name.empty()) {
                    fail(
                        "a '&' that starts no entity or character reference (write &amp; for "
                        "the character itself)");
                }
                if (name[0] != '#' && name != "lt" && name != "gt" && name != "amp" &&
                    name != "quot" && name != "apos") {
                    fail(
                        fmt::format("unknown entity '&{};' (XML files here use only &lt; &gt; "
                                    "&amp; &quot; &apos; and &#...; character references: "
                                    "write the value out)",
                                    name));
                }
            }
            ++i;
        }
    }
}

}  // namespace

std::string read_text(const std::string& path) {
    try {
        return read_file(path);
    } catch (const ReadError& e) {
        throw FormatError(fmt::format("{}: cannot read the file: {}", path, e.reason()), path, 0);
    }
}

Document::Document(std::string_view text, std::string file)
    : doc_(std::make_unique<tinyxml2::XMLDocument>(true, tinyxml2::COLLAPSE_WHITESPACE)),
      file_(std::move(file)) {
    check_entities(text, file_);
    tinyxml2::XMLError parsed = tinyxml2::XML_SUCCESS;
    try {
        parsed = doc_->Parse(text.data(), text.size());
    } catch (const std::bad_alloc&) {
        throw FormatError(
            fmt::format("{}: not enough memory to read it ({} bytes of XML)", file_, text.size()),
            file_, 0);
    }
    if (parsed != tinyxml2::XML_SUCCESS) {
        // tinyxml2's own text names the line as "Line number=N"; say it our way. An empty
        // document has no line: its error is on line 1, where the text was expected
        const int line = std::max(doc_->ErrorLineNum(), 1);
        throw FormatError(fmt::format("{}:{}: malformed XML: {}", file_, line,
                                      describe_xml_error(doc_->ErrorID())),
                          file_, line);
    }
}

std::unique_ptr<Document> Document::foreign(std::string_view text, std::string file,
                                            const char* root) {
    std::unique_ptr<Document> d(new Document(text, std::move(file)));
    const tinyxml2::XMLElement* top = d->doc_->RootElement();
    if (!top || std::strcmp(top->Name(), root) != 0) {
        const int line = top ? top->GetLineNum() : 1;
        throw FormatError(fmt::format("{}:{}: expected a <{}> root element{}", d->file_, line, root,
                                      top ? fmt::format(", got <{}>", top->Name()) : ""),
                          d->file_, line);
    }
    d->root_ = top;
    return d;
}

Document::Document(std::string_view text, std::string file, const char* kind)
    : Document(text, std::move(file)) {
    const tinyxml2::XMLElement* top = doc_->RootElement();
    if (!top || std::strcmp(top->Name(), "gaitlab") != 0) {
        const int line = top ? top->GetLineNum() : 1;
        throw FormatError(
            fmt::format("{}:{}: expected a <gaitlab version=\"{}\"> root element{}", file_, line,
                        kVersion, top ? fmt::format(", got <{}>", top->Name()) : ""),
            file_, line);
    }
    Element g(*this, top, "gaitlab");
    g.allow({"version"});
    if (!g.has("version")) g.fail("attribute 'version' is required (version=\"1\")");
    const long long version = g.integer("version", 0);
    if (version != kVersion) {
        g.fail(fmt::format("version {} is not supported (this gaitlab reads version {})", version,
                           kVersion));
    }
    const tinyxml2::XMLElement* inner = top->FirstChildElement();
    if (!inner) g.fail(fmt::format("expected a <{}> element inside", kind));
    if (std::strcmp(inner->Name(), kind) != 0) {
        Element(*this, inner, "gaitlab")
            .fail(fmt::format("expected <{}>, got <{}> (is this {} {} file?)", kind, inner->Name(),
                              std::strchr("aeiou", kind[0]) ? "an" : "a", kind));
    }
    if (const tinyxml2::XMLElement* extra = inner->NextSiblingElement()) {
        Element(*this, extra, "gaitlab")
            .fail(fmt::format("one <{}> per file expected, got another <{}>", kind, extra->Name()));
    }
    root_ = inner;
}

Element Document::root() const {
    return Element(*this, root_, root_->Name());
}

Element::Element(const Document& doc, const tinyxml2::XMLElement* e, std::string path)
    : doc_(&doc), e_(e), path_(std::move(path)) {}

void Element::fail(const std::string& message) const {
    throw FormatError(fmt::format("{}:{}: {}: {}", file(), line(), path_, message), file(), line());
}

void Element::allow(std::initializer_list<const char*> allowed) const {
    allow(std::vector<const char*>(allowed));
}

void Element::allow(const std::vector<const char*>& allowed) const {
    const std::vector<std::string> names(allowed.begin(), allowed.end());
    for (const tinyxml2::XMLAttribute* a = e_->FirstAttribute(); a; a = a->Next()) {
        const std::string n = a->Name();
        if (std::find(names.begin(), names.end(), n) == names.end()) {
            fail(fmt::format("unknown attribute '{}'{}{}", n, did_you_mean(n, names),
                             names.empty() ? " (it takes none)"
                                           : fmt::format(" (expected {})", quoted_list(allowed))));
        }
    }
}

bool Element::has(const char* attr) const {
    return e_->Attribute(attr) != nullptr;
}

const char* Element::raw(const char* attr) const {
    return e_->Attribute(attr);
}

std::string Element::string(const char* attr, const std::string& fallback) const {
    const char* v = raw(attr);
    return v ? v : fallback;
}

std::string Element::required_string(const char* attr) const {
    const char* v = raw(attr);
    if (!v) fail(fmt::format("attribute '{}' is required", attr));
    return v;
}

double Element::parse_number(const char* attr, const char* text) const {
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    while (end && *end == ' ')
        ++end;
    if (end == text || (end && *end != '\0') || !std::isfinite(v)) {
        fail(fmt::format("attribute '{}': number expected, got '{}'", attr, text));
    }
    return v;
}

double Element::number(const char* attr, double fallback) const {
    const char* v = raw(attr);
    return v ? parse_number(attr, v) : fallback;
}

double Element::required_number(const char* attr) const {
    const char* v = raw(attr);
    if (!v) fail(fmt::format("attribute '{}' is required (a number)", attr));
    return parse_number(attr, v);
}

long long Element::integer(const char* attr, long long fallback) const {
    const char* v = raw(attr);
    if (!v) return fallback;
    errno = 0;
    char* end = nullptr;
    const long long n = std::strtoll(v, &end, 10);
    if (end == v || *end != '\0' || errno == ERANGE) {
        fail(fmt::format("attribute '{}': integer expected, got '{}'", attr, v));
    }
    return n;
}

bool Element::boolean(const char* attr, bool fallback) const {
    const char* v = raw(attr);
    if (!v) return fallback;
    if (std::strcmp(v, "true") == 0) return true;
    if (std::strcmp(v, "false") == 0) return false;
    fail(fmt::format("attribute '{}': 'true' or 'false' expected, got '{}'", attr, v));
}

namespace {

// splits "a b c" into numbers; empty on a malformed list
std::vector<double> split_numbers(const char* text) {
    std::vector<double> out;
    const char* p = text;
    while (*p) {
        while (*p == ' ')
            ++p;
        if (!*p) break;
        char* end = nullptr;
        const double v = std::strtod(p, &end);
        if (end == p || !std::isfinite(v) || (*end != ' ' && *end != '\0')) return {};
        out.push_back(v);
        p = end;
    }
    return out;
}

}  // namespace

std::vector<double> Element::numbers(const char* attr, size_t n,
                                     const std::vector<double>& fallback) const {
    const char* v = raw(attr);
    if (!v) return fallback;
    std::vector<double> out = split_numbers(v);
    if (out.size() != n) {
        fail(fmt::format("attribute '{}': {} numbers expected, got '{}'", attr, n, v));
    }
    return out;
}

Vec3 Element::vec3(const char* attr, const Vec3& fallback) const {
    const char* v = raw(attr);
    if (!v) return fallback;
    const std::vector<double> n = split_numbers(v);
    if (n.size() != 3)
        fail(fmt::format("attribute '{}': three numbers \"x y z\" expected, got '{}'", attr, v));
    return {n[0], n[1], n[2]};
}

Quat Element::quat(const char* attr, const Quat& fallback) const {
    const char* v = raw(attr);
    if (!v) return fallback;
    const std::vector<double> n = split_numbers(v);
    if (n.size() != 4) {
        fail(fmt::format("attribute '{}': four numbers \"w x y z\" expected, got '{}'", attr, v));
    }
    const double norm = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] + n[3] * n[3]);
    if (std::abs(norm - 1) > 1e-6) {
        fail(
            fmt::format("attribute '{}': a unit quaternion expected (its norm is {})", attr, norm));
    }
    return {n[0], n[1], n[2], n[3]};
}

double Element::angle(const char* attr, double fallback_rad) const {
    const char* v = raw(attr);
    return v ? deg_to_rad(parse_number(attr, v)) : fallback_rad;
}

std::vector<Element> Element::children(std::initializer_list<const char*> allowed) const {
    const std::vector<std::string> names = to_strings(allowed);
    std::vector<Element> out;
    std::vector<std::pair<std::string, int>> counts;
    for (const tinyxml2::XMLElement* c = e_->FirstChildElement(); c; c = c->NextSiblingElement()) {
        const std::string n = c->Name();
        if (std::find(names.begin(), names.end(), n) == names.end()) {
            Element(*doc_, c, path_ + "/" + n)
                .fail(fmt::format("unknown element <{}>{}{}", n, did_you_mean(n, names),
                                  names.empty()
                                      ? fmt::format(" (<{}> has no elements inside)", name())
                                      : fmt::format(" (expected {})", quoted_list(allowed))));
        }
        int k = 1;
        for (auto& [name, count] : counts) {
            if (name == n) k = ++count;
        }
        if (k == 1) counts.emplace_back(n, 1);
        out.emplace_back(*doc_, c, fmt::format("{}/{}[{}]", path_, n, k));
    }
    return out;
}

std::string Element::text() const {
    const char* t = e_->GetText();
    return t ? t : "";
}

std::optional<Element> Element::child(const char* name) const {
    const tinyxml2::XMLElement* c = e_->FirstChildElement(name);
    if (!c) return std::nullopt;
    return Element(*doc_, c, path_ + "/" + name);
}

std::vector<std::string> Element::attribute_names() const {
    std::vector<std::string> out;
    for (const tinyxml2::XMLAttribute* a = e_->FirstAttribute(); a; a = a->Next())
        out.emplace_back(a->Name());
    return out;
}

std::string format_number(double v) {
    // fmt's default is the shortest representation that round-trips
    return fmt::format("{}", v);
}

double degrees_for(double rad) {
    return degrees_for(rad, [rad](double deg) { return deg_to_rad(deg) == rad; });
}

double degrees_for(double rad, const std::function<bool(double)>& exact) {
    const double d = rad_to_deg(rad);
    // the number a person would have typed (30, not 29.999999999999996), when it is exact
    const double typed = std::strtod(fmt::format("{:.12g}", d).c_str(), nullptr);
    if (exact(typed)) return typed;
    if (exact(d)) return d;
    // the degrees a user typed map to this angle; they lie within a few ulps of d
    double up = d, down = d;
    for (int i = 0; i < 8; ++i) {
        up = std::nextafter(up, HUGE_VAL);
        down = std::nextafter(down, -HUGE_VAL);
        if (exact(up)) return up;
        if (exact(down)) return down;
    }
    return d;
}

Writer::Writer() : printer_(nullptr, false, 0) {
    printer_.PushHeader(false, true);
    printer_.OpenElement("gaitlab");
    printer_.PushAttribute("version", kVersion);
}

void Writer::open(const char* name) {
    printer_.OpenElement(name);
}

void Writer::close() {
    printer_.CloseElement();
}

void Writer::attr(const char* name, const std::string& value) {
    printer_.PushAttribute(name, value.c_str());
}

void Writer::attr(const char* name, double value) {
    attr(name, format_number(value));
}

void Writer::attr_int(const char* name, long long value) {
    attr(name, fmt::format("{}", value));
}

void Writer::attr(const char* name, bool value) {
    attr(name, std::string(value ? "true" : "false"));
}

void Writer::attr(const char* name, const Vec3& v) {
    attr(name, fmt::format("{} {} {}", format_number(v.x), format_number(v.y), format_number(v.z)));
}

void Writer::attr(const char* name, const Quat& q) {
    attr(name, fmt::format("{} {} {} {}", format_number(q.w), format_number(q.x),
                           format_number(q.y), format_number(q.z)));
}

void Writer::angle(const char* name, double rad) {
    attr(name, degrees_for(rad));
}

void Writer::text(const std::string& text) {
    printer_.PushText(text.c_str());
}

void Writer::comment(const std::string& text) {
    printer_.PushComment((" " + text + " ").c_str());
}

std::string Writer::text() {
    if (!done_) {
        printer_.CloseElement();
        done_ = true;
    }
    return std::string(printer_.CStr(), static_cast<size_t>(printer_.CStrSize() - 1));
}

}  // namespace gaitlab::xml

namespace gaitlab {

std::string resolve_path(const std::string& from, const std::string& path) {
    const std::filesystem::path p(path);
    if (p.is_absolute()) return p.lexically_normal().string();
    return (std::filesystem::path(from).parent_path() / p).lexically_normal().string();
}

}  // namespace gaitlab
