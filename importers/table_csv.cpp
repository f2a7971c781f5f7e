#include "importers/table_csv.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/common/error.h"
#include "importers/csv_text.h"

namespace roverlab::io {

const std::vector<double>* NumericTable::find(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? nullptr : &columns[static_cast<std::size_t>(it - names.begin())];
}

NumericTable read_numeric_table(const std::string& path, const std::vector<std::string>& numeric,
                                const std::vector<std::string>& numeric_if_present) {
  std::ifstream in = csv::open_text_file(path);
  NumericTable t;
  std::string line;
  int line_number = 0;
  while (csv::next_content_line(in, line, line_number, path)) {
    const auto cells = csv::split(line);
    if (t.names.empty()) {
      for (const auto& c : cells) {
        std::string name = csv::trim(c);
        const auto bracket = name.find(" [");
        if (bracket != std::string::npos) name = name.substr(0, bracket);
        t.names.push_back(name);
      }
      t.columns.resize(t.names.size());
      continue;
    }
    const std::string where = "line " + std::to_string(line_number);
    if (cells.size() != t.names.size()) {
      throw InputError(path, where + ": " + std::to_string(cells.size()) + " cells but the header has " +
                                 std::to_string(t.names.size()) + " (ragged row)");
    }
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const std::string cell = csv::trim(cells[k]);
      const bool must_be_number =
          std::find(numeric.begin(), numeric.end(), t.names[k]) != numeric.end() ||
          std::find(numeric_if_present.begin(), numeric_if_present.end(), t.names[k]) != numeric_if_present.end();
      double v = NAN;
      try {
        v = csv::parse_number(cell).value_or(NAN);
      } catch (const std::invalid_argument&) {
        if (must_be_number) {
          throw InputError(path, where + ", column '" + t.names[k] + "': cannot parse '" + cell + "' as a number");
        }
      }
      t.columns[k].push_back(v);
    }
  }
  if (t.names.empty()) throw InputError(path, "empty CSV file (no header)");
  for (const auto& name : numeric) {
    if (t.find(name) == nullptr) throw InputError(path, "missing column '" + name + "'");
  }
  return t;
}

}  // namespace roverlab::io
