#pragma once
// Line-level CSV helpers shared by the CSV readers (no quoting of commas).

#include <cstddef>
#include <fstream>
#include <istream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace roverlab::io::csv {

// Cell without surrounding blanks and without one pair of double quotes.
std::string trim(std::string_view s);

// Longest line a text table may have: a longer one (a binary file, /dev/zero
// behind a .csv name) is refused instead of filling memory.
inline constexpr std::size_t kMaxLineBytes = std::size_t{16} << 20;

// Opens `path` for reading as text: InputError naming it when it does not
// exist, is a folder, or is not a regular file (a pipe or a device never ends).
std::ifstream open_text_file(const std::string& path);

// Reads the next line that is neither blank nor a '#' comment, without its
// trailing CR; counts every line read in line_number. False at the end.
// Throws InputError naming `path` for a NUL byte, a line over kMaxLineBytes,
// quoted cells, or cells separated by something other than commas.
bool next_content_line(std::istream& in, std::string& line, int& line_number, const std::string& path);

// A cell as an error message shows it: at most 40 characters (a
// multi-megabyte cell is not echoed whole).
std::string shown(const std::string& cell);

// Cells of one line, split at every comma.
std::vector<std::string_view> split(std::string_view line);

// The number in a trimmed cell: nullopt for an empty cell; throws
// std::invalid_argument when the cell is not a number.
std::optional<double> parse_number(const std::string& cell);

}  // namespace roverlab::io::csv
