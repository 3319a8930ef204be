#include "formats/png_image.h"

#include <png.h>

#include <cctype>
#include <cstring>

#include "gaitlab/error.h"
#include "gaitlab/files.h"

namespace gaitlab::detail {

namespace {

constexpr int kMaxSide = 4096;

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
    throw SpecError("cannot read image '" + path + "': " + reason);
}

}  // namespace

GreyImage read_png_grey(const std::string& path) {
    // the one bounded reader: a directory, a FIFO, a device or a huge file is refused up front
    std::string bytes;
    try {
        bytes = read_file(path);
    } catch (const ReadError& e) {
        std::string why = e.reason();
        if (!why.empty())
            why[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(why[0])));
        fail(path, why);
    }

    // libpng's simplified API reports errors through image.message instead of longjmp, so no
    // C++ frame is ever skipped
    png_image image;
    std::memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) {
        fail(path, std::string("not a readable PNG file (libpng: ") + image.message + ")");
    }
    if (image.width < 2 || image.height < 2 || image.width > kMaxSide || image.height > kMaxSide) {
        png_image_free(&image);
        fail(path, "it is " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                       " pixels (expected 2 to " + std::to_string(kMaxSide) + " on each side)");
    }
    // 16-bit files keep their precision; 8-bit grey files are read unchanged
    const bool wide = (image.format & PNG_FORMAT_FLAG_LINEAR) != 0;
    image.format = wide ? PNG_FORMAT_LINEAR_Y : PNG_FORMAT_GRAY;
    const size_t n = static_cast<size_t>(image.width) * image.height;
    GreyImage out;
    out.width = static_cast<int>(image.width);
    out.height = static_cast<int>(image.height);
    out.levels.resize(n);
    bool ok = false;
    if (wide) {
        std::vector<png_uint_16> pixels(n);
        ok = png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr) != 0;
        for (size_t k = 0; ok && k < n; ++k)
            out.levels[k] = pixels[k] / 65535.0;
    } else {
        std::vector<png_byte> pixels(n);
        ok = png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr) != 0;
        for (size_t k = 0; ok && k < n; ++k)
            out.levels[k] = pixels[k] / 255.0;
    }
    if (!ok) {
        const std::string message = image.message;
        png_image_free(&image);
        fail(path, "corrupt PNG data (libpng: " + message + ")");
    }
    return out;
}

}  // namespace gaitlab::detail
