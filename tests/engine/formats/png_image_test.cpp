// Tests for engine/src/formats/png_image.cpp: grey levels from PNG files, and clear errors for
// files that are not readable PNG images.
#include "formats/png_image.h"

#include <catch2/catch.hpp>

#include <fstream>

#include "engine/png_support.h"
#include "gaitlab/error.h"

using namespace gaitlab;
using Catch::Matchers::Equals;
using Catch::Matchers::StartsWith;
using detail::read_png_grey;
using test::TempPng;

TEST_CASE("8-bit grey images give their levels row by row from the top") {
    const TempPng png(3, 2, {0, 128, 255, 255, 0, 51});
    const detail::GreyImage image = read_png_grey(png.path);
    REQUIRE(image.width == 3);
    REQUIRE(image.height == 2);
    const std::vector<double> expected{0, 128 / 255.0, 1, 1, 0, 0.2};
    REQUIRE(image.levels.size() == expected.size());
    for (size_t k = 0; k < expected.size(); ++k)
        CHECK(image.levels[k] == Approx(expected[k]).epsilon(1e-12));
}

TEST_CASE("16-bit images keep their precision") {
    const TempPng png(2, 2, {0, 1, 65535, 32768}, TempPng::Format::grey16);
    const detail::GreyImage image = read_png_grey(png.path);
    CHECK(image.levels[0] == 0);
    CHECK(image.levels[1] == Approx(1.0 / 65535).epsilon(1e-9));
    CHECK(image.levels[2] == 1);
    CHECK(image.levels[3] == Approx(32768.0 / 65535).epsilon(1e-12));
}

TEST_CASE("colour images count as grey") {
    // black, white and a mid grey given as RGB, and pure green, which is brighter than blue
    const TempPng png(2, 2, {0, 0, 0, 255, 255, 255, 0, 255, 0, 0, 0, 255}, TempPng::Format::rgb);
    const detail::GreyImage image = read_png_grey(png.path);
    CHECK(image.levels[0] == 0);
    CHECK(image.levels[1] == 1);
    CHECK(image.levels[2] > image.levels[3]);
}

TEST_CASE("files that are not readable PNG images are errors naming them") {
    SECTION("missing") {
        REQUIRE_THROWS_AS(read_png_grey("/tmp/gaitlab_no_such_dir/x.png"), SpecError);
        REQUIRE_THROWS_WITH(read_png_grey("/tmp/gaitlab_no_such_dir/x.png"),
                            Equals("cannot read image '/tmp/gaitlab_no_such_dir/x.png': no such "
                                   "file or directory"));
    }
    SECTION("a directory") {
        REQUIRE_THROWS_WITH(read_png_grey("/tmp"),
                            Equals("cannot read image '/tmp': is a directory"));
    }
    SECTION("not a PNG, or a truncated one") {
        const TempPng good(8, 8, std::vector<unsigned short>(64, 100));
        std::ifstream in(good.path, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), {});
        const std::string path = good.path + ".bad";
        for (const std::string& content :
             {std::string("hello"), bytes.substr(0, 40), bytes.substr(0, bytes.size() - 20)}) {
            std::ofstream(path, std::ios::binary) << content;
            REQUIRE_THROWS_AS(read_png_grey(path), SpecError);
            REQUIRE_THROWS_WITH(read_png_grey(path),
                                StartsWith("cannot read image '" + path + "': "));
        }
        std::remove(path.c_str());
    }
    SECTION("too small for a grid") {
        const TempPng tiny(1, 1, {3});
        REQUIRE_THROWS_WITH(read_png_grey(tiny.path),
                            Equals("cannot read image '" + tiny.path +
                                   "': it is 1 x 1 pixels (expected 2 to 4096 on each side)"));
    }
}
