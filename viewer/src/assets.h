// The page and its libraries (three.js, uPlot), embedded in the program at build time from
// viewer/web/ and its node_modules (viewer/embed_web.cmake): the viewer works offline and
// nothing is installed beside the program.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace gaitlab::viewer {

struct Asset {
    std::string path;  ///< as served, without the leading '/': "index.html", "lib/three.core.js"
    const char* data;
    std::size_t size;
    const char* type;  ///< its media type (text: served as UTF-8)
};

/// Every embedded file.
const std::vector<Asset>& assets();

}  // namespace gaitlab::viewer
