// CSV as run folders write it: comma-separated, '\n' line ends, fields quoted only when they
// hold a comma, a quote or a line end (RFC 4180), numbers in the shortest form that reads back
// to the same double.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace gaitlab::formats {

/// Appends `field`, quoted if it needs to be.
void append_field(std::string& out, std::string_view field);
/// Appends `v` in the shortest form that reads back bit for bit ("nan", "inf", "-inf" for the
/// non-finite values).
void append_number(std::string& out, double v);
/// One CSV line without its line end.
std::string csv_line(const std::vector<std::string>& fields);

/// Splits one line (without its line end) into fields, undoing the quoting; false if a quoted
/// field is not closed.
bool split_line(std::string_view line, std::vector<std::string>& fields);

/// Parses a number as append_number writes it (and the usual decimal forms); false if `text`
/// is not one.
bool parse_number(std::string_view text, double& v);

}  // namespace gaitlab::formats
