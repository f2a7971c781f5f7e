#include "importers/csv_text.h"

#include <charconv>
#include <filesystem>
#include <string>

#include <stdexcept>
#include "core/common/error.h"

namespace roverlab::io::csv {

std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  std::string out(s.substr(first, last - first + 1));
  if (out.size() >= 2 && out.front() == '"' && out.back() == '"') out = out.substr(1, out.size() - 2);
  return out;
}

std::ifstream open_text_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "no such file");
  if (fs::is_directory(path, ec)) throw InputError(path, "is a folder, not a log file");
  if (!fs::is_regular_file(path, ec)) throw InputError(path, "not a regular file (a pipe or a device?)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file");
  return in;
}

namespace {

// One line without its '\n', at most kMaxLineBytes long; false at the end.
bool read_line(std::istream& in, std::string& line, int line_number, const std::string& path) {
  line.clear();
  std::streambuf* buffer = in.rdbuf();
  for (;;) {
    const int c = buffer->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return !line.empty();
    }
    if (c == '\n') return true;
    if (c == '\0') {
      throw InputError(path, "line " + std::to_string(line_number) + ": NUL byte: not a text file");
    }
    line.push_back(static_cast<char>(c));
    if (line.size() > kMaxLineBytes) {
      throw InputError(path, "line " + std::to_string(line_number) + " is longer than " +
                                 std::to_string(kMaxLineBytes >> 20) + " MiB: not a text table");
    }
  }
}

// The causes behind a confusing symptom, named: another separator (a European
// spreadsheet's ';', a tab) or quoted cells.
void require_plain_commas(const std::string& line, int line_number, const std::string& path) {
  const std::string where = "line " + std::to_string(line_number) + ": ";
  if (line.find('"') != std::string::npos) {
    throw InputError(path,
                     where + "quoted cells are not read; write cells without quotes (and without commas in them)");
  }
  if (line.find(',') != std::string::npos) return;
  for (const char separator : {';', '\t'}) {
    if (line.find(separator) != std::string::npos) {
      throw InputError(path, where + "cells are separated by " + (separator == ';' ? "';'" : "tabs") +
                                 "; RoverLab reads comma-separated files with '.' as the decimal point");
    }
  }
}

}  // namespace

bool next_content_line(std::istream& in, std::string& line, int& line_number, const std::string& path) {
  while (read_line(in, line, line_number + 1, path)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string stripped = trim(line);
    if (stripped.empty() || stripped.front() == '#') continue;
    require_plain_commas(stripped, line_number, path);
    return true;
  }
  return false;
}

std::string shown(const std::string& cell) {
  constexpr std::size_t kShown = 40;
  if (cell.size() <= kShown) return cell;
  return cell.substr(0, kShown) + "... (" + std::to_string(cell.size()) + " characters)";
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    cells.push_back(line.substr(begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin));
    if (comma == std::string_view::npos) return cells;
    begin = comma + 1;
  }
}

std::optional<double> parse_number(const std::string& cell) {
  if (cell.empty()) return std::nullopt;
  const char* first = cell.data();
  const char* last = cell.data() + cell.size();
  if (*first == '+') ++first;
  double value = 0.0;
  const auto [ptr, err] = std::from_chars(first, last, value);
  if (err != std::errc() || ptr != last) throw std::invalid_argument(cell);
  return value;
}

}  // namespace roverlab::io::csv
