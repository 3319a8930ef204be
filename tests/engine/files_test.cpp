// Files (engine/src/files.cpp, data/files.cpp, csv.cpp, json.cpp): atomic writes, appends that
// report a full disk, CSV quoting and numbers that round-trip, JSON.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "data/csv.h"
#include "data/files.h"
#include "data/json.h"
#include "gaitlab/error.h"
#include "gaitlab/files.h"
#include "temp_dir.h"

using namespace gaitlab;
using namespace gaitlab::data;
using gaitlab::test::TempDir;

TEST_CASE("a full disk is an error naming the file and the reason", "[files]") {
    AppendFile full("/dev/full");
    CHECK_THROWS_AS(full.write("x\n"), IoError);
    CHECK_THROWS_WITH(full.write("x\n"), "cannot write /dev/full: No space left on device");
    TempDir tmp("files_atomic");
    write_file_atomic(tmp / "a.txt", "one");
    write_file_atomic(tmp / "a.txt", "two");
    CHECK(read_file(tmp / "a.txt") == "two");
    // no temporary file is left behind
    CHECK(std::distance(std::filesystem::directory_iterator(tmp.path),
                        std::filesystem::directory_iterator()) == 1);
    CHECK_THROWS_WITH(
        write_file_atomic(tmp / "no/such/dir/a.txt", "x"),
        "cannot write " + (tmp / "no/such/dir/a.txt") + ": No such file or directory");
    CHECK_THROWS_WITH(read_file(tmp / "none"),
                      "cannot read " + (tmp / "none") + ": No such file or directory");
}

TEST_CASE("reads refuse directories, FIFOs, devices and files above the limit", "[files]") {
    TempDir tmp("files_read");
    CHECK_THROWS_WITH(read_file(tmp.str()), "cannot read " + tmp.str() + ": is a directory");
    const std::string fifo = tmp / "fifo";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    // no writer: a blocking open would wait forever
    CHECK_THROWS_WITH(read_file(fifo),
                      "cannot read " + fifo + ": not a regular file (a FIFO, device or socket)");
    const std::string zero = tmp / "zero.lua";
    std::filesystem::create_symlink("/dev/zero", zero);
    CHECK_THROWS_WITH(read_file(zero),
                      "cannot read " + zero + ": not a regular file (a FIFO, device or socket)");
    write_file_atomic(tmp / "big", std::string(2000, 'x'));
    CHECK_THROWS_WITH(read_file(tmp / "big", 1024),
                      "cannot read " + (tmp / "big") + ": larger than the 1 KiB gaitlab reads");
    CHECK(read_file(tmp / "big", 2000).size() == 2000);
    try {
        read_file(tmp / "none");
        FAIL("no error");
    } catch (const ReadError& e) {
        CHECK(e.reason() == "No such file or directory");
    }
    CHECK(describe_size(kMaxInputBytes) == "64 MiB");
    CHECK(describe_size(100) == "100 bytes");
}

TEST_CASE("atomic writes replace regular files only, and keep links", "[files]") {
    TempDir tmp("files_atomic_special");
    // a device, a FIFO or a folder is never replaced by a file
    struct stat before {};
    REQUIRE(::stat("/dev/full", &before) == 0);
    CHECK_THROWS_WITH(write_file_atomic("/dev/full", "x"),
                      "cannot write /dev/full: not a regular file (a FIFO, device or socket)");
    struct stat after {};
    REQUIRE(::stat("/dev/full", &after) == 0);
    CHECK(S_ISCHR(after.st_mode));
    const std::string fifo = tmp / "fifo";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    CHECK_THROWS_WITH(write_file_atomic(fifo, "x"),
                      "cannot write " + fifo + ": not a regular file (a FIFO, device or socket)");
    CHECK_THROWS_WITH(write_file_atomic(tmp.str(), "x"),
                      "cannot write " + tmp.str() + ": is a directory");
    // a link stays a link; its target gets the new content
    write_file_atomic(tmp / "real.txt", "one");
    std::filesystem::create_symlink(tmp / "real.txt", tmp / "link.txt");
    write_file_atomic(tmp / "link.txt", "two");
    CHECK(std::filesystem::is_symlink(tmp.path / "link.txt"));
    CHECK(read_file(tmp / "real.txt") == "two");
}

TEST_CASE("writes may create the missing folders above the file, and say which one failed",
          "[files]") {
    TempDir tmp("files_folders");
    write_file_atomic(tmp / "a/b/c/x.txt", "deep", MissingFolders::create);
    CHECK(read_file(tmp / "a/b/c/x.txt") == "deep");
    // existing folders, "." and ".." on the way are fine
    write_file_atomic(tmp / "a/./b/../b/y.txt", "y", MissingFolders::create);
    CHECK(read_file(tmp / "a/b/y.txt") == "y");
    // the default still refuses, naming the file
    CHECK_THROWS_WITH(write_file_atomic(tmp / "none/x.txt", "x"),
                      "cannot write " + (tmp / "none/x.txt") + ": No such file or directory");
    CHECK_FALSE(std::filesystem::exists(tmp.path / "none"));
    // a file where a folder must go: the folder is named, and what is after it is not made
    write_file_atomic(tmp / "plain", "p");
    try {
        write_file_atomic(tmp / "plain/sub/x.txt", "x", MissingFolders::create);
        FAIL("no error");
    } catch (const WriteError& e) {
        CHECK(std::string(e.what()) == "cannot write " + (tmp / "plain/sub/x.txt") +
                                           ": cannot create folder " + (tmp / "plain") +
                                           ": a file of that name is in the way");
        CHECK(e.path() == tmp / "plain/sub/x.txt");
        CHECK(e.folder() == tmp / "plain");
        CHECK(e.reason() == "a file of that name is in the way");
        CHECK(e.part().empty());
    }
    CHECK(read_file(tmp / "plain") == "p");
    // a link to a folder is a folder; a dangling link is in the way
    std::filesystem::create_directory_symlink(tmp.path / "a", tmp.path / "to_a");
    write_file_atomic(tmp / "to_a/new/z.txt", "z", MissingFolders::create);
    CHECK(read_file(tmp / "a/new/z.txt") == "z");
    std::filesystem::create_symlink(tmp.path / "gone", tmp.path / "dangling");
    CHECK_THROWS_WITH(write_file_atomic(tmp / "dangling/z.txt", "z", MissingFolders::create),
                      "cannot write " + (tmp / "dangling/z.txt") + ": cannot create folder " +
                          (tmp / "dangling") + ": a file of that name is in the way");
    CHECK_FALSE(std::filesystem::exists(tmp.path / "gone"));
    // the part of a save is named after the file asked for
    CHECK(std::string(WriteError("s.xml", "is a directory", "", "s.robot.xml").what()) ==
          "cannot write s.xml: its part s.robot.xml: is a directory");
    // a failed write leaves no temporary file, and the message never names one
    std::filesystem::create_directories(tmp.path / "d/x.txt");
    CHECK_THROWS_WITH(write_file_atomic(tmp / "d/x.txt", "x", MissingFolders::create),
                      "cannot write " + (tmp / "d/x.txt") + ": is a directory");
    CHECK(std::distance(std::filesystem::directory_iterator(tmp.path / "d"),
                        std::filesystem::directory_iterator()) == 1);
}

TEST_CASE("numbers are written in their shortest form and read back to the same bits", "[csv]") {
    const double values[] = {0.0,
                             -0.0,
                             0.1,
                             1.0 / 3.0,
                             1e-310,
                             1.7976931348623157e308,
                             static_cast<double>(0.1f),
                             -123456.789,
                             5e-324,
                             std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity()};
    for (double v : values) {
        std::string s;
        append_number(s, v);
        double back = 0;
        REQUIRE(parse_number(s, back));
        CHECK(std::memcmp(&v, &back, sizeof v) == 0);
    }
    std::string s;
    append_number(s, 0.1);
    CHECK(s == "0.1");
    s.clear();
    append_number(s, std::nan(""));
    CHECK(s == "nan");
    double v = 0;
    CHECK(parse_number("nan", v));
    CHECK(std::isnan(v));
    CHECK_FALSE(parse_number("1.5x", v));
    CHECK_FALSE(parse_number("", v));
    CHECK(parse_number("+2", v));
    CHECK(v == 2);
}

TEST_CASE("CSV fields are quoted only when needed and split back", "[csv]") {
    CHECK(csv_line({"a", "b,c", "say \"hi\"", ""}) == "a,\"b,c\",\"say \"\"hi\"\"\",");
    std::vector<std::string> f;
    REQUIRE(split_line("a,\"b,c\",\"say \"\"hi\"\"\",", f));
    CHECK(f == std::vector<std::string>{"a", "b,c", "say \"hi\"", ""});
    CHECK_FALSE(split_line("a,\"open", f));
}

TEST_CASE("JSON round-trips and reports errors with the line", "[json]") {
    Json j = Json::object();
    j.set("name", "a \"quoted\"\nline");
    j.set("seed", std::uint64_t{18446744073709551615ull});
    j.set("dt", 0.001);
    j.set("list", Json::array()).push(1);
    const Json back = Json::parse(j.dump(), "x.json");
    CHECK(back.str_at("name") == "a \"quoted\"\nline");
    CHECK(back.find("seed")->uint() == 18446744073709551615ull);
    CHECK(back.num_at("dt") == 0.001);
    CHECK(back.find("list")->items().size() == 1);
    CHECK(Json::parse("\"\\u00e9\\ud83d\\ude00\"", "s").str() == "\xc3\xa9\xf0\x9f\x98\x80");
    CHECK_THROWS_WITH(Json::parse("{\n\"a\": 1,\n}", "f.json"),
                      "f.json:3: member name (a string) expected");
    CHECK_THROWS_WITH(Json::parse("[1 2]", "f.json"), "f.json:1: ',' or ']' expected in an array");
    CHECK_THROWS_WITH(Json::parse("{} x", "f.json"),
                      "f.json:1: end of file expected after the JSON value");
    CHECK_THROWS_WITH(Json::parse("\"abc", "f.json"), "f.json:1: unterminated string");
    // bytes that are not printable are named, not copied into the message
    CHECK_THROWS_WITH(Json::parse("\x1b[31m", "f.json"),
                      "f.json:1: JSON value expected, got byte 0x1b");
    CHECK_THROWS_WITH(Json::parse("\"\\\x07\"", "f.json"),
                      "f.json:1: unknown escape: '\\' and byte 0x07 in a string");
}

namespace {

// whether `s` is well-formed UTF-8 (RFC 3629), as a JSON file must be
bool valid_utf8(const std::string& s) {
    for (size_t i = 0; i < s.size();) {
        const auto c = static_cast<unsigned char>(s[i]);
        size_t n = c < 0x80                 ? 1
                   : c >= 0xC2 && c <= 0xDF ? 2
                   : c >= 0xE0 && c <= 0xEF ? 3
                   : c >= 0xF0 && c <= 0xF4 ? 4
                                            : 0;
        if (n == 0 || i + n > s.size()) return false;
        std::uint32_t cp = n == 1 ? c : n == 2 ? c & 0x1F : n == 3 ? c & 0x0F : c & 0x07;
        for (size_t k = 1; k < n; ++k) {
            const auto b = static_cast<unsigned char>(s[i + k]);
            if ((b & 0xC0) != 0x80) return false;
            cp = (cp << 6) | (b & 0x3F);
        }
        const std::uint32_t least[] = {0, 0, 0x80, 0x800, 0x10000};
        if (cp < least[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp < 0xE000)) return false;
        i += n;
    }
    return true;
}

}  // namespace

TEST_CASE("JSON strings are valid UTF-8 whatever bytes they hold", "[json]") {
    // names come from scripts and may be any bytes: lone continuation bytes, cut sequences,
    // overlong forms, surrogates, code points past U+10FFFF, control characters
    const std::string bytes[] = {"\xff\xfe",
                                 "a\x80z",
                                 "cut \xc3",
                                 "over\xc0\xaf",
                                 "sur\xed\xa0\x80",
                                 "big\xf4\x90\x80\x80",
                                 "ctl\x01\x1f\x7f",
                                 "ok \xc3\xa9\xf0\x9f\x98\x80",
                                 std::string("nul\0in", 6)};
    for (const std::string& b : bytes) {
        INFO(b);
        Json j = Json::object();
        j.set("name", b);
        j.set(b, 1);  // as a member name too
        const std::string text = j.dump();
        CHECK(valid_utf8(text));
        const Json back = Json::parse(text, "x.json");
        const std::string name = back.str_at("name");
        CHECK(valid_utf8(name));
        // valid UTF-8 comes back as it was; each bad byte as U+FFFD
        if (valid_utf8(b)) CHECK(name == b);
        CHECK(back.members()[1].first == name);
    }
    CHECK(Json::parse(Json("\xff"
                           "a")
                          .dump(),
                      "x")
              .str() ==
          "\xef\xbf\xbd"
          "a");
    CHECK(Json::parse(Json("\xe2\x82").dump(), "x").str() == "\xef\xbf\xbd\xef\xbf\xbd");
    // lone or mismatched surrogate escapes read as U+FFFD too, never as broken UTF-8
    CHECK(Json::parse("\"\\ud800x\"", "s").str() == "\xef\xbf\xbdx");
    CHECK(Json::parse("\"\\udc00\"", "s").str() == "\xef\xbf\xbd");
    CHECK(Json::parse("\"\\ud800\\u0041\"", "s").str() ==
          "\xef\xbf\xbd"
          "A");
}

TEST_CASE("JSON values know their line, and numbers out of range are not integers", "[json]") {
    const Json j = Json::parse("{\n  \"a\": 1,\n\n  \"b\": [\n 2, \"x\"]\n}", "f.json");
    CHECK(j.line() == 1);
    CHECK(j.find("a")->line() == 2);
    CHECK(j.find("b")->line() == 4);
    CHECK(j.find("b")->items()[1].line() == 5);
    const Json n = Json::parse("[1e300, -1e300, 0.5, 1e3, 18446744073709551616]", "n.json");
    CHECK(n.items()[0].integer(-7) == -7);
    CHECK(n.items()[1].integer(-7) == -7);
    CHECK(n.items()[2].integer(-7) == -7);
    CHECK(n.items()[3].integer(-7) == 1000);
    CHECK(n.items()[4].uint(3) == 3);
    // an object with a great many members parses in linear time
    std::string big = "{";
    for (int i = 0; i < 200000; ++i)
        big += (i > 0 ? ",\"" : "\"") + std::to_string(i) + "\":1";
    big += "}";
    CHECK(Json::parse(big, "big.json").members().size() == 200000);
}
