#include "importers/plate_test_csv.h"

#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>

#include "core/common/error.h"
#include "importers/csv_text.h"

namespace roverlab::io {

namespace {

// "# plate_diameter_m: 0.1" (or "= 0.1") -> {"plate_diameter_m", "0.1"}.
std::optional<std::pair<std::string, std::string>> header_entry(const std::string& line) {
  if (line.empty() || line[0] != '#') return std::nullopt;
  const auto sep = line.find_first_of(":=");
  if (sep == std::string::npos) return std::nullopt;
  return std::pair{csv::trim(std::string_view(line).substr(1, sep - 1)),
                   csv::trim(std::string_view(line).substr(sep + 1))};
}

double plate_size(const std::string& path, const std::string& key, const std::string& text) {
  try {
    const auto v = csv::parse_number(text);
    if (v && std::isfinite(*v) && *v > 0 && *v <= 10.0) return *v;
  } catch (const std::invalid_argument&) {
  }
  throw InputError(path, key + ": '" + csv::shown(text) + "' is not a size in m from 0 to 10");
}

// The plate from the header entries; InputError when it is not given.
terramechanics::Plate plate_of(const std::string& path, const std::map<std::string, std::string>& header) {
  terramechanics::Plate plate;
  const auto get = [&](const char* key) -> std::optional<double> {
    const auto it = header.find(key);
    if (it == header.end()) return std::nullopt;
    return plate_size(path, key, it->second);
  };
  const auto diameter = get("plate_diameter_m"), width = get("plate_width_m"), length = get("plate_length_m");
  if (diameter && (width || length)) throw InputError(path, "give either plate_diameter_m or plate_width_m, not both");
  if (diameter) return terramechanics::Plate{true, *diameter, *diameter};
  if (!width || !length) {
    throw InputError(path,
                     "no plate size: a header line '# plate_diameter_m: D' or '# plate_width_m: W' with "
                     "'# plate_length_m: L'");
  }
  plate.circular = false;
  plate.width = std::min(*width, *length);
  plate.length = std::max(*width, *length);
  return plate;
}

}  // namespace

terramechanics::PlateRecord read_plate_test_csv(const std::string& path) {
  std::ifstream in = csv::open_text_file(path);
  std::map<std::string, std::string> header;
  std::map<std::string, std::size_t> column;
  std::size_t columns = 0;
  terramechanics::PlateRecord r;
  r.name = path;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.size() > csv::kMaxLineBytes)
      throw InputError(path, "line " + std::to_string(line_number) + " is too long");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (const auto entry = header_entry(line)) header[entry->first] = entry->second;
    if (csv::trim(line).empty() || line[0] == '#') continue;
    const auto cells = csv::split(line);
    const std::string where = "line " + std::to_string(line_number);
    if (column.empty()) {
      for (std::size_t k = 0; k < cells.size(); ++k) column[csv::trim(cells[k])] = k;
      columns = cells.size();
      for (const char* required : {"depth_m", "force_N"}) {
        if (column.count(required) == 0) {
          throw InputError(path,
                           std::string("missing column '") + required + "' (a plate test needs depth_m, force_N)");
        }
      }
      continue;
    }
    if (cells.size() != columns) {
      throw InputError(path, where + ": " + std::to_string(cells.size()) + " cells but the header has " +
                                 std::to_string(columns) + " (ragged row)");
    }
    for (const char* name : {"depth_m", "force_N"}) {
      const std::string cell = csv::trim(cells[column[name]]);
      std::optional<double> v;
      try {
        v = csv::parse_number(cell);
      } catch (const std::invalid_argument&) {
      }
      if (!v || !std::isfinite(*v)) {
        throw InputError(path,
                         where + ", column '" + name + "': cannot parse '" + csv::shown(cell) + "' as a finite number");
      }
      (name[0] == 'd' ? r.depth : r.force).push_back(*v);
    }
  }
  if (column.empty()) throw InputError(path, "no header row (depth_m, force_N)");
  r.plate = plate_of(path, header);
  return r;
}

}  // namespace roverlab::io
