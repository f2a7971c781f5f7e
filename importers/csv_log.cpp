#include "importers/csv_log.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/common/error.h"
#include "core/log/units.h"
#include "importers/atomic_file.h"
#include "importers/csv_text.h"

namespace roverlab::io {

namespace fs = std::filesystem;

namespace {

struct Column {
  std::string name;
  log::UnitConversion si;
  std::vector<double> values;
};

// "name [unit]" -> name, unit ("1" when absent).
std::pair<std::string, std::string> parse_header_cell(const std::string& cell) {
  const auto open = cell.rfind('[');
  if (open == std::string::npos || cell.back() != ']') return {cell, "1"};
  return {csv::trim(std::string_view(cell).substr(0, open)),
          csv::trim(std::string_view(cell).substr(open + 1, cell.size() - open - 2))};
}

}  // namespace

log::Log read_csv_log(const std::string& path, const CsvOptions& options) {
  std::ifstream in = csv::open_text_file(path);

  std::vector<Column> columns;
  std::size_t time_column = 0;
  std::string line;
  int line_number = 0;
  while (csv::next_content_line(in, line, line_number, path)) {
    const auto cells = csv::split(line);
    const std::string where = "line " + std::to_string(line_number);
    if (columns.empty()) {  // header
      for (std::size_t k = 0; k < cells.size(); ++k) {
        auto [name, unit] = parse_header_cell(csv::trim(cells[k]));
        if (name.empty()) throw InputError(path, where + ": empty header cell in column " + std::to_string(k + 1));
        Column c;
        c.name = name;
        try {
          c.si = log::unit_to_si(unit);
        } catch (const DataError& e) {
          throw InputError(path, where + ", column '" + name + "': " + e.what());
        }
        columns.push_back(std::move(c));
      }
      for (std::size_t k = 0; k < columns.size(); ++k) {
        if (columns[k].name == "time" || columns[k].name == "t") {
          time_column = k;
          break;
        }
      }
      // No time column, but a single-wheel test's columns: named for what it is.
      const auto has = [&](const char* n) {
        return std::any_of(columns.begin(), columns.end(), [&](const Column& c) { return c.name == n; });
      };
      if (columns[time_column].name != "time" && columns[time_column].name != "t" && has("load_N") && has("slip")) {
        throw InputError(path,
                         "a single-wheel test table (load_N, slip, ...), not a log with a time column: "
                         "`roverlab discrepancy single-wheel` and `terramechanics fit` read it");
      }
      if (columns[time_column].si.si_unit == "1" && cells[time_column].find('[') == std::string_view::npos) {
        throw InputError(path, where + ": time column '" + columns[time_column].name +
                                   "' has no unit; write its header as '" + columns[time_column].name + " [s]'");
      }
      if (columns[time_column].si.si_unit != "s") {
        throw InputError(path, where + ": time column '" + columns[time_column].name + "' has unit '" +
                                   columns[time_column].si.si_unit + "', not a unit of time");
      }
      continue;
    }
    if (cells.size() != columns.size()) {
      throw InputError(path, where + ": " + std::to_string(cells.size()) + " cells but the header has " +
                                 std::to_string(columns.size()) + " (ragged row)");
    }
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const std::string cell = csv::trim(cells[k]);
      double value = std::numeric_limits<double>::quiet_NaN();
      try {
        value = csv::parse_number(cell).value_or(value);
      } catch (const std::invalid_argument&) {
        throw InputError(
            path, where + ", column '" + columns[k].name + "': cannot parse '" + csv::shown(cell) + "' as a number");
      }
      Column& c = columns[k];
      value = value * c.si.factor + c.si.offset;
      if (k == time_column) {
        if (!std::isfinite(value)) {
          throw InputError(path, where + ": time is " + (cell.empty() ? "empty" : "'" + csv::shown(cell) + "'") +
                                     "; it must be a finite number");
        }
        if (!c.values.empty() && !(value > c.values.back())) {
          std::ostringstream msg;
          msg.precision(12);
          msg << where << ": time " << value << " s is not after the previous " << c.values.back()
              << " s (time must increase strictly)";
          throw InputError(path, msg.str());
        }
      }
      c.values.push_back(value);
    }
  }
  if (in.bad()) throw InputError(path, "read error");
  if (columns.empty()) throw InputError(path, "empty CSV file (no header)");

  std::string name = options.stream_name;
  if (name.empty()) {
    name = fs::path(path).stem().string();
    for (char& ch : name) {
      if (ch == '/' || ch == ' ') ch = '_';
    }
  }
  log::Log out;
  out.metadata.source_file = fs::path(path).filename().string();
  try {
    log::Stream stream(name, std::move(columns[time_column].values));
    for (std::size_t k = 0; k < columns.size(); ++k) {
      if (k == time_column) continue;
      stream.add_channel(columns[k].name, columns[k].si.si_unit, std::move(columns[k].values));
    }
    out.add_stream(std::move(stream));
  } catch (const DataError& e) {
    throw InputError(path, e.what());
  }
  return out;
}

namespace {
void append_number(std::string& out, double v) {
  if (std::isnan(v)) return;  // empty cell: missing sample
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  out.append(buffer, result.ptr);
}
}  // namespace

void write_csv_stream(const log::Stream& stream, const std::string& path) {
  std::string text = "time [s]";
  for (const auto& c : stream.channels()) text += "," + c.name + " [" + c.unit + "]";
  text += "\n";
  for (std::size_t i = 0; i < stream.size(); ++i) {
    append_number(text, stream.time()[i]);
    for (const auto& c : stream.channels()) {
      text += ',';
      append_number(text, c.values[i]);
    }
    text += '\n';
  }
  write_text_atomically(path, text);
}

}  // namespace roverlab::io
