// What gaitlab writes for a person to read: its messages (errors, warnings, notes) quote
// strings that come from users (names, paths, values from scripts and files), and those may
// hold any bytes. Written as they are, an escape character would drive the terminal (colours,
// a cleared screen, a changed title, in some terminals typed input). Every message reaches the
// terminal through these functions, which write such bytes as \xNN; what a script prints
// itself (print, io.write) and the data files (CSV, JSON, with their own escaping) do not.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace gaitlab {

/// `text` with every byte that a terminal would act on or could not show written as the four
/// characters \xNN (two lowercase hex digits): the C0 control characters but line end and tab
/// (NUL as \x00, ESC as \x1b), DEL, the C1 control characters U+0080 to U+009F (each byte of
/// their UTF-8 form: \xc2\x9b), and each byte that is not part of valid UTF-8 (a lone or cut
/// sequence, an overlong form, a surrogate, a code point past U+10FFFF). Valid UTF-8 that can
/// be shown ("N·m", "μ") stays as it is, and so does the rest of the text: a message that is
/// already terminal text comes back unchanged.
std::string terminal_text(std::string_view text);

/// terminal_text(`text`) with line ends and tabs written as \x0a and \x09 too: a value shown
/// on a line of its own or in a column (a run folder's series names in a listing).
std::string terminal_line(std::string_view text);

/// Writes terminal_text(`text`) to `stream` (stderr for messages).
void write_message(std::FILE* stream, std::string_view text);

/// Writes "gaitlab: `message`" and a line end to stderr as write_message writes: the form of
/// gaitlab's errors, warnings and notes on the command line.
void report_line(std::string_view message);

/// std::fprintf(`stream`, `format`, ...) written as write_message writes: gaitlab's own
/// messages on stderr (and those it prints on stdout, such as a failed point's error).
[[gnu::format(printf, 2, 3)]] void print_message(std::FILE* stream, const char* format, ...);

}  // namespace gaitlab
