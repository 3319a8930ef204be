// Files (engine/src/formats/: files.cpp, run_files.cpp, csv.cpp, json.cpp): atomic writes, appends
// that report a full disk, CSV quoting and numbers that round-trip, JSON.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "formats/csv.h"
#include "formats/json.h"
#include "formats/run_files.h"
#include "gaitlab/error.h"
#include "gaitlab/files.h"
#include "temp_dir.h"

using namespace gaitlab;
using namespace gaitlab::formats;
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

TEST_CASE("atomic writes of names as long as the file system allows", "[files]") {
    // the temporary name beside the file was the name plus ".tmp-PID-N": a name of 240 bytes or
    // more could not be written at all ("File name too long")
    TempDir tmp("files_atomic_long");
    for (const size_t length : {240, 250, 255}) {
        const std::string path = tmp / std::string(length, 'n');
        write_file_atomic(path, "long " + std::to_string(length));
        CHECK(read_file(path) == "long " + std::to_string(length));
        write_file_atomic(path, "again");
        CHECK(read_file(path) == "again");
    }
    // nothing else is left in the folder
    CHECK(std::distance(std::filesystem::directory_iterator(tmp.path),
                        std::filesystem::directory_iterator()) == 3);
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

namespace {

// the parse error `text` gives, as a user sees it
std::string json_error(const std::string& text) {
    try {
        const JsonDocument doc(text, "f.json");
    } catch (const FormatError& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST_CASE("JSON round-trips and reports errors with the line", "[json]") {
    nlohmann::ordered_json j;
    j["name"] = "a \"quoted\"\nline";
    j["seed"] = std::uint64_t{18446744073709551615ull};
    j["dt"] = 0.001;
    j["flush"] = 2.0;
    j["list"] = {1, "two"};
    j["nested"] = {{"a", nlohmann::ordered_json::array()}, {"b", nlohmann::ordered_json::object()}};
    const std::string text = dump_json(j);
    // two-space indent, arrays of scalars on one line, members in order, doubles written short
    CHECK(text ==
          "{\n"
          "  \"name\": \"a \\\"quoted\\\"\\nline\",\n"
          "  \"seed\": 18446744073709551615,\n"
          "  \"dt\": 0.001,\n"
          "  \"flush\": 2,\n"
          "  \"list\": [1, \"two\"],\n"
          "  \"nested\": {\n"
          "    \"a\": [],\n"
          "    \"b\": {}\n"
          "  }\n"
          "}\n");
    const JsonDocument back(text, "x.json");
    CHECK(str_at(back.root(), "name") == "a \"quoted\"\nline");
    CHECK(as_uint(*find(back.root(), "seed")) == 18446744073709551615ull);
    CHECK(find(back.root(), "dt")->get<double>() == 0.001);
    CHECK(find(back.root(), "flush")->get<double>() == 2.0);
    CHECK(find(back.root(), "list")->size() == 2);
    CHECK(find(back.root(), "missing") == nullptr);
    CHECK(find(*find(back.root(), "list"), "x") == nullptr);  // not an object
    CHECK(as_string(JsonDocument("\"\\u00e9\\ud83d\\ude00\"", "s").root()) ==
          "\xc3\xa9\xf0\x9f\x98\x80");
    // the first of two members of the same name counts
    CHECK(find(JsonDocument("{\"a\": 1, \"a\": [2, {\"a\": 3}], \"b\": 4}", "d").root(), "a")
              ->get<int>() == 1);
    CHECK(json_error("{\n\"a\": 1,\n}") == "f.json:3: member name (a string) expected");
    CHECK(json_error("[1 2]") == "f.json:1: ',' or ']' expected in an array");
    CHECK(json_error("{\"a\": 1\n\n \"b\": 2}") == "f.json:3: ',' or '}' expected in an object");
    CHECK(json_error("{\"a\" 1}") == "f.json:1: ':' expected after a member name");
    CHECK(json_error("{} x") == "f.json:1: end of file expected after the JSON value");
    CHECK(json_error("\"abc") == "f.json:1: unterminated string");
    CHECK(json_error("\"abc\\") == "f.json:1: unterminated string");
    CHECK(json_error("") == "f.json:1: JSON value expected, got the end of the file");
    CHECK(json_error("{\"a\":\n\n") == "f.json:3: JSON value expected, got the end of the file");
    CHECK(json_error("[tru]") == "f.json:1: JSON value expected, got 't'");
    CHECK(json_error("\n\n\"\\q\"") == "f.json:3: unknown escape '\\q' in a string");
    CHECK(json_error("\"\\u12g4\"") == "f.json:1: four hex digits expected after \\u");
    // bytes that are not printable are named, not copied into the message
    CHECK(json_error("\x1b[31m") == "f.json:1: JSON value expected, got byte 0x1b");
    CHECK(json_error("\n\xcc") == "f.json:2: JSON value expected, got byte 0xcc");
    CHECK(json_error("\"\\\x07\"") == "f.json:1: unknown escape: '\\' and byte 0x07 in a string");
    // where nlohmann-json says more, its words are kept
    CHECK(json_error("[1,\n-x]") == "f.json:2: invalid number; expected digit after '-'");
    CHECK(json_error("[1e999]") == "f.json:1: number overflow parsing '1e999'");
    CHECK(json_error("\"a\nb\"") ==
          "f.json:1: invalid string: control character U+000A (LF) must be escaped to "
          "\\u000A or \\n");
    CHECK(json_error("[\"\xff\"]") == "f.json:1: invalid string: ill-formed UTF-8 byte");
    // deep nesting is refused before it costs anything
    CHECK(json_error(std::string(100000, '[')) == "f.json:1: JSON nested too deeply");
    CHECK(json_error("{\"a\": 1, \"a\": " + std::string(100, '[')) ==
          "f.json:1: JSON nested too deeply");
}

TEST_CASE("JSON doubles read back to the same bits", "[json]") {
    // replay rebuilds the simulation from run.json's numbers: every double must come back exact
    std::vector<double> values = {0.0,
                                  -0.0,
                                  0.001,
                                  1.0 / 3,
                                  2.0,
                                  1e16,
                                  123456789012345678.0,
                                  9007199254740993.0,
                                  std::numeric_limits<double>::min(),
                                  std::numeric_limits<double>::denorm_min(),
                                  std::numeric_limits<double>::max(),
                                  -std::numeric_limits<double>::max()};
    std::uint64_t bits = 0x9e3779b97f4a7c15ull;
    for (int i = 0; i < 2000; ++i) {
        bits ^= bits << 13;
        bits ^= bits >> 7;
        bits ^= bits << 17;
        double d = 0;
        std::memcpy(&d, &bits, sizeof d);
        if (std::isfinite(d)) values.push_back(d);
    }
    nlohmann::ordered_json j = nlohmann::ordered_json::array();
    for (double d : values)
        j.push_back(d);
    j.push_back(std::nan(""));
    j.push_back(std::numeric_limits<double>::infinity());
    const JsonDocument back(dump_json(j), "n.json");
    REQUIRE(back.root().size() == values.size() + 2);
    for (size_t i = 0; i < values.size(); ++i) {
        const double d = back.root()[i].get<double>();
        INFO(values[i]);
        CHECK(std::memcmp(&d, &values[i], sizeof d) == 0);
    }
    // JSON has no NaN or infinity: null
    CHECK(back.root()[values.size()].is_null());
    CHECK(back.root()[values.size() + 1].is_null());
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
        nlohmann::ordered_json j;
        j["name"] = b;
        j["list"] = {b};
        j[b] = 1;  // as a member name too
        const std::string text = dump_json(j);
        CHECK(valid_utf8(text));
        const JsonDocument back(text, "x.json");
        const std::string name = str_at(back.root(), "name");
        CHECK(valid_utf8(name));
        // valid UTF-8 comes back as it was; bad bytes as U+FFFD
        if (valid_utf8(b)) CHECK(name == b);
        CHECK(as_string(back.root()["list"][0]) == name);
        CHECK(find(back.root(), name) != nullptr);
    }
    const auto round_trip = [](const std::string& s) {
        return as_string(JsonDocument(dump_json(nlohmann::ordered_json(s)), "x").root());
    };
    CHECK(round_trip("\xff"
                     "a") ==
          "\xef\xbf\xbd"
          "a");
    // a sequence cut short is one U+FFFD (Unicode's "maximal subpart" practice)
    CHECK(round_trip("\xe2\x82") == "\xef\xbf\xbd");
    CHECK(round_trip("\xe2\x82z") ==
          "\xef\xbf\xbd"
          "z");
    // lone or mismatched surrogate escapes are refused, naming the line
    CHECK(json_error("\n\"\\ud800x\"") ==
          "f.json:2: invalid string: surrogate U+D800..U+DBFF must be followed by U+DC00..U+DFFF");
    CHECK(json_error("\"\\udc00\"") ==
          "f.json:1: invalid string: surrogate U+DC00..U+DFFF must follow U+D800..U+DBFF");
}

TEST_CASE("JSON values know their line, and numbers out of range are not integers", "[json]") {
    const JsonDocument j(
        "{\n  \"a\": 1,\n\n  \"b\": [\n 2, \"x\",\n [3,\n{\"c\":\n\n 4.5}]],\n"
        "\"d\": true,\"e\"\n:\nnull}",
        "f.json");
    const nlohmann::json& r = j.root();
    CHECK(j.line(r) == 1);
    CHECK(j.line(r["a"]) == 2);
    CHECK(j.line(r["b"]) == 4);
    CHECK(j.line(r["b"][0]) == 5);
    CHECK(j.line(r["b"][1]) == 5);
    CHECK(j.line(r["b"][2]) == 6);
    CHECK(j.line(r["b"][2][0]) == 6);
    CHECK(j.line(r["b"][2][1]) == 7);
    CHECK(j.line(r["b"][2][1]["c"]) == 9);
    CHECK(j.line(r["d"]) == 10);
    CHECK(j.line(r["e"]) == 12);
    const nlohmann::json elsewhere = 1;
    CHECK(j.line(elsewhere) == 0);
    const JsonDocument n("[1e300, -1e300, 0.5, 1e3, 18446744073709551616, -3, \"4\"]", "n.json");
    CHECK_FALSE(as_integer(n.root()[0]));
    CHECK_FALSE(as_integer(n.root()[1]));
    CHECK_FALSE(as_integer(n.root()[2]));
    CHECK(as_integer(n.root()[3]) == 1000);
    CHECK(as_uint(n.root()[4], 3) == 3);
    CHECK(as_integer(n.root()[5]) == -3);
    CHECK(as_uint(n.root()[5], 3) == 3);
    CHECK_FALSE(as_integer(n.root()[6]));
    // an object with a great many members parses in about linear time
    std::string big = "{";
    for (int i = 0; i < 200000; ++i)
        big += (i > 0 ? ",\"" : "\"") + std::to_string(i) + "\":1";
    big += "}";
    const JsonDocument many(big, "big.json");
    CHECK(many.root().size() == 200000);
    CHECK(many.line(many.root()["199999"]) == 1);
}

TEST_CASE("content hashes are FNV-1a 64", "[files]") {
    // the published test vectors of FNV-1a 64
    CHECK(content_hash("") == "fnv1a64:cbf29ce484222325");
    CHECK(content_hash("a") == "fnv1a64:af63dc4c8601ec8c");
    CHECK(content_hash("foobar") == "fnv1a64:85944171f73967e8");
    CHECK(content_hash(std::string("a\0b", 3)) != content_hash("a"));
}
