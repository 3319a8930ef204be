// Reading and writing gaitlab's XML files: the shared mechanics of every format. A reader walks
// elements through Element, which knows its file, line and path, checks that every attribute
// and child it is given is known (suggesting the closest valid name otherwise) and parses
// numbers with their units; errors are FormatError "FILE:LINE: PATH: what was expected". A
// writer builds elements with Writer and writes the text atomically.
#pragma once

#include <tinyxml2.h>

#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gaitlab/types.h"
#include "gaitlab/xml.h"
#include "gaitlab/xml_schema.h"

namespace gaitlab::xml {

/// The version of the formats this build reads and writes.
inline constexpr int kVersion = 1;

class Element;

/// A parsed file: the document and the one element under <gaitlab version="1">, which must be
/// called `kind` ("robot", "actuation", ...).
class Document {
  public:
    /// Parses `text`; `file` names it in messages. Throws FormatError.
    Document(std::string_view text, std::string file, const char* kind);
    /// A foreign format (URDF): `text` whose root element must be `root`, no gaitlab wrapper.
    static std::unique_ptr<Document> foreign(std::string_view text, std::string file,
                                             const char* root);
    Document(const Document&) = delete;
    Document& operator=(const Document&) = delete;

    Element root() const;
    const std::string& file() const { return file_; }

  private:
    Document(std::string_view text, std::string file);
    std::unique_ptr<tinyxml2::XMLDocument> doc_;
    std::string file_;
    const tinyxml2::XMLElement* root_ = nullptr;
};

/// Reads `path` whole; throws FormatError naming the path if it cannot.
std::string read_text(const std::string& path);

/// One element being read. Every attribute read through it counts as known; finish() (or the
/// destructor's caller, via check()) rejects the others.
class Element {
  public:
    Element(const Document& doc, const tinyxml2::XMLElement* e, std::string path);

    const std::string& path() const { return path_; }
    int line() const { return e_->GetLineNum(); }
    const char* name() const { return e_->Name(); }
    const std::string& file() const { return doc_->file(); }

    /// Throws FormatError at this element: "FILE:LINE: PATH: message".
    [[noreturn]] void fail(const std::string& message) const;

    /// Runs `check` (a spec check) and reports its SpecError at this element.
    template <class F>
    void check(F&& check) const {
        try {
            check();
        } catch (const SpecError& e) {
            fail(e.what());
        }
    }

    /// Rejects attributes outside `allowed`, naming the closest valid one.
    void allow(std::initializer_list<const char*> allowed) const;
    void allow(const std::vector<const char*>& allowed) const;
    bool has(const char* attr) const;

    std::string string(const char* attr, const std::string& fallback) const;
    std::string required_string(const char* attr) const;
    double number(const char* attr, double fallback) const;
    double required_number(const char* attr) const;
    long long integer(const char* attr, long long fallback) const;
    bool boolean(const char* attr, bool fallback) const;
    /// "x y z".
    Vec3 vec3(const char* attr, const Vec3& fallback) const;
    /// Exactly `n` numbers separated by spaces.
    std::vector<double> numbers(const char* attr, size_t n,
                                const std::vector<double>& fallback) const;
    /// "w x y z", normalised check within 1e-6.
    Quat quat(const char* attr, const Quat& fallback) const;
    /// An angle written in degrees, returned in radians.
    double angle(const char* attr, double fallback_rad) const;

    /// The child elements, each of which must be named in `allowed`.
    std::vector<Element> children(std::initializer_list<const char*> allowed) const;
    /// The element's text content ("" if none).
    std::string text() const;
    /// The first child element called `name`, if any (the others are not checked).
    std::optional<Element> child(const char* name) const;
    /// The attribute names present, in file order.
    std::vector<std::string> attribute_names() const;

  private:
    const char* raw(const char* attr) const;
    double parse_number(const char* attr, const char* text) const;

    const Document* doc_;
    const tinyxml2::XMLElement* e_;
    std::string path_;
};

/// Builds a file's text: <?xml ...?><gaitlab version="1"> ... </gaitlab>.
class Writer {
  public:
    Writer();
    /// Opens an element; attributes follow until the next open/close.
    void open(const char* name);
    void close();
    void attr(const char* name, const std::string& value);
    void attr(const char* name, const char* value) { attr(name, std::string(value)); }
    /// A number in its shortest form that reads back to the same double.
    void attr(const char* name, double value);
    void attr_int(const char* name, long long value);
    void attr(const char* name, bool value);
    void attr(const char* name, const Vec3& v);
    void attr(const char* name, const Quat& q);
    /// An angle given in radians, written in degrees that read back to the same radians.
    void angle(const char* name, double rad);
    void comment(const std::string& text);
    /// Text content of the element opened last (after its attributes).
    void text(const std::string& text);
    /// The finished text.
    std::string text();

  private:
    tinyxml2::XMLPrinter printer_;
    bool done_ = false;
};

/// The shortest decimal form of `v` that parses back to exactly `v`.
std::string format_number(double v);
/// Degrees for `rad` that deg_to_rad turns back into exactly `rad` when such a value exists
/// near rad_to_deg(rad) (always the case for angles that were typed in degrees).
double degrees_for(double rad);
/// Degrees near rad_to_deg(rad) for which `exact` holds, preferring the shortest decimal a
/// person would type; rad_to_deg(rad) if none does.
double degrees_for(double rad, const std::function<bool(double)>& exact);

/// The attributes each reader allows (xml_schema.cpp): the one list gaitlab::xml_schema()
/// exports.
namespace attrs {
extern const std::vector<const char*> robot, chain, module, body, joint, sensor_joint, sensor_imu,
    sensor_contact, sensor_range, sensor_position;
extern const std::vector<const char*> environment, floor, box, heightfield_source, place;
extern const std::vector<const char*> simulation, simulation_environment, simulation_robot, record;
extern const std::vector<const char*> actuation, group, controller;
}  // namespace attrs

/// The environment's library objects (wall, ramp, ..., heightfield) and their attributes, from
/// the field lists their reader and writer walk (environment_xml.cpp).
std::vector<XmlElementSchema> environment_object_schema();

}  // namespace gaitlab::xml
