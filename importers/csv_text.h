#pragma once
// Line-level CSV helpers shared by the CSV readers (no quoting of commas).

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace roverlab::io::csv {

// Cell without surrounding blanks and without one pair of double quotes.
std::string trim(std::string_view s);

// Cells of one line, split at every comma.
std::vector<std::string_view> split(std::string_view line);

// The number in a trimmed cell: nullopt for an empty cell; throws
// std::invalid_argument when the cell is not a number.
std::optional<double> parse_number(const std::string& cell);

}  // namespace roverlab::io::csv
