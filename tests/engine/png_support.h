// PNG files for the engine tests that read images, written with libpng's simplified API.
#pragma once

#include <png.h>
#include <unistd.h>
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace gaitlab::test {

/// A temporary PNG file, removed when the object goes: `pixels` row by row from the top, one
/// value per pixel (grey, grey16) or three (rgb).
struct TempPng {
    enum class Format { grey, grey16, rgb };
    std::string path;

    TempPng(int width, int height, const std::vector<unsigned short>& pixels,
            Format format = Format::grey) {
        char name[] = "/tmp/gaitlab_png_test_XXXXXX";
        const int fd = mkstemp(name);
        REQUIRE(fd >= 0);
        close(fd);
        std::remove(name);
        path = std::string(name) + ".png";
        png_image image;
        std::memset(&image, 0, sizeof image);
        image.version = PNG_IMAGE_VERSION;
        image.width = static_cast<png_uint_32>(width);
        image.height = static_cast<png_uint_32>(height);
        int ok = 0;
        if (format == Format::grey16) {
            image.format = PNG_FORMAT_LINEAR_Y;
            ok = png_image_write_to_file(&image, path.c_str(), 0, pixels.data(), 0, nullptr);
        } else {
            image.format = format == Format::rgb ? PNG_FORMAT_RGB : PNG_FORMAT_GRAY;
            std::vector<png_byte> bytes(pixels.begin(), pixels.end());
            ok = png_image_write_to_file(&image, path.c_str(), 0, bytes.data(), 0, nullptr);
        }
        REQUIRE(ok != 0);
    }
    ~TempPng() { std::remove(path.c_str()); }
    TempPng(const TempPng&) = delete;
    TempPng& operator=(const TempPng&) = delete;
};

}  // namespace gaitlab::test
