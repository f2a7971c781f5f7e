#pragma once
// Line-level CSV helpers shared by the CSV readers (no quoting of commas).

#include <istream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace roverlab::io::csv {

// Cell without surrounding blanks and without one pair of double quotes.
std::string trim(std::string_view s);

// Reads the next line that is neither blank nor a '#' comment, without its
// trailing CR; counts every line read in line_number. False at the end.
bool next_content_line(std::istream& in, std::string& line, int& line_number);

// Cells of one line, split at every comma.
std::vector<std::string_view> split(std::string_view line);

// The number in a trimmed cell: nullopt for an empty cell; throws
// std::invalid_argument when the cell is not a number.
std::optional<double> parse_number(const std::string& cell);

}  // namespace roverlab::io::csv
