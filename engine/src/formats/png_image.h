// Reading grey levels from PNG files (libpng, a private dependency of the engine).
#pragma once

#include <string>
#include <vector>

namespace gaitlab::detail {

/// A grey-level image: `levels` row by row from the top, each in [0, 1] (0 black, 1 white).
struct GreyImage {
    int width = 0;
    int height = 0;
    std::vector<double> levels;
};

/// Reads `path`; colour images are converted to grey, alpha is ignored, 16-bit images keep their
/// precision. Throws SpecError "cannot read image 'PATH': REASON".
GreyImage read_png_grey(const std::string& path);

}  // namespace gaitlab::detail
