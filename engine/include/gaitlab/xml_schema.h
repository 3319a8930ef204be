// The attributes of every element of gaitlab's XML files, as their readers accept them: the
// readers take their allow-lists from this table, so it is the one list of what a file can say.
// The Lua API mirrors it key for key (docs/lua-api.md, "XML attributes and Lua keys"); its test
// walks this table, so an attribute added here without a Lua key fails it.
#pragma once

#include <string>
#include <vector>

namespace gaitlab {

/// One element of one file kind and the attributes its reader accepts.
struct XmlElementSchema {
    std::string file;     ///< "robot", "environment", "simulation" or "actuation"
    std::string element;  ///< the element's name ("chain", "box", "record", ...)
    std::vector<std::string> attributes;
};

/// Every element of the four file kinds, in file order. A <sensor> lists the attributes of
/// every kind (each kind takes some of them); a <controller> lists the attributes that say
/// which controller it is, its other attributes being the controller's parameters.
const std::vector<XmlElementSchema>& xml_schema();

}  // namespace gaitlab
