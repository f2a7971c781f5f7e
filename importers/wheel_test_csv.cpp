#include "importers/wheel_test_csv.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "core/common/error.h"
#include "importers/csv_text.h"

namespace roverlab::io {

namespace fs = std::filesystem;
using terramechanics::WheelTestPoint;

namespace {

bool says_grousers(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text.find("grouser") != std::string::npos || text.find("lugged") != std::string::npos;
}

// A wheel named or described as grousered (its label or the file's name) in
// a file without grouser columns: the study would call grousers not
// applicable; one line says which columns let it fit them (issue 43).
std::string grouser_hint(const std::string& path, const std::vector<WheelTestPoint>& points) {
  std::string named;
  for (const auto& p : points) {
    if (says_grousers(p.wheel_label)) {
      named = "wheel '" + csv::shown(p.wheel_label) + "'";
      break;
    }
  }
  if (named.empty() && says_grousers(fs::path(path).filename().string())) named = "the file's name";
  if (named.empty()) return {};
  return named + " says grousers, but the file has no grouser columns: add grouser_count and grouser_height_m " +
         "(per row) so the study can model them";
}

// The slip column: `slip` (how it is read at a slip angle left to the
// study), or `travel_slip` / `longitudinal_slip`, which state it (issue 43;
// docs/terramechanics.md). Renamed to `slip` in `column`.
void read_slip_column(const std::string& path, std::map<std::string, std::size_t>& column, WheelTestFile& file) {
  for (const char* definition : {"travel", "longitudinal"}) {
    const auto it = column.find(std::string(definition) + "_slip");
    if (it == column.end()) continue;
    if (column.count("slip") || !file.slip_definition.empty()) {
      throw InputError(path, "more than one slip column (slip, travel_slip, longitudinal_slip): keep one");
    }
    file.slip_definition = definition;
    column["slip"] = it->second;
  }
}

// A measured value beyond this (N, N m, m) is no measurement in SI units: 1e300 N would print inf and nan.
constexpr double kMaxMeasured = 1e6;

// The header's columns by name: a UTF-8 byte order mark (Excel's "CSV UTF-8")
// is not part of the first name, and a name given twice is refused (the
// required columns are checked once the slip column is known).
std::map<std::string, std::size_t> header_columns(const std::vector<std::string_view>& cells, const std::string& path) {
  std::map<std::string, std::size_t> column;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    std::string_view cell = cells[k];
    if (k == 0 && cell.substr(0, 3) == "\xEF\xBB\xBF") cell.remove_prefix(3);
    const std::string name = csv::trim(cell);
    if (!column.emplace(name, k).second) {
      throw InputError(path, "the header names column '" + csv::shown(name) + "' twice");
    }
  }
  return column;
}

}  // namespace

WheelTestFile read_wheel_test_file(const std::string& path) {
  std::ifstream in = csv::open_text_file(path);
  std::map<std::string, std::size_t> column;
  WheelTestFile file;
  auto& points = file.points;
  std::string line;
  int line_number = 0;
  std::size_t columns = 0;
  while (csv::next_content_line(in, line, line_number, path)) {
    const auto cells = csv::split(line);
    const std::string where = "line " + std::to_string(line_number);
    if (column.empty()) {
      column = header_columns(cells, path);
      columns = cells.size();
      read_slip_column(path, column, file);
      for (const char* required : {"radius_m", "width_m", "load_N", "slip"}) {
        if (column.count(required) == 0) {
          throw InputError(path, std::string("missing column '") + required +
                                     "' (a single-wheel file needs radius_m, width_m, load_N, slip)");
        }
      }
      if (column.count("drawbar_pull_N") + column.count("torque_Nm") + column.count("sinkage_m") +
              column.count("lateral_force_N") ==
          0) {
        throw InputError(path, "no measured column (drawbar_pull_N, torque_Nm, sinkage_m or lateral_force_N)");
      }
      continue;
    }
    if (cells.size() != columns) {
      throw InputError(path, where + ": " + std::to_string(cells.size()) + " cells but the header has " +
                                 std::to_string(columns) + " (ragged row)");
    }
    auto number = [&](const char* name) -> std::optional<double> {
      const auto it = column.find(name);
      if (it == column.end()) return std::nullopt;
      const std::string cell = csv::trim(cells[it->second]);
      try {
        const auto v = csv::parse_number(cell);
        if (v && !std::isfinite(*v)) throw std::invalid_argument(cell);
        if (v && std::abs(*v) > kMaxMeasured && std::string_view(name) != "grouser_count") {  // counted below
          throw InputError(path,
                           where + ", column '" + name + "': " + csv::shown(cell) + " is beyond +-1e6 (SI units)");
        }
        return v;
      } catch (const std::invalid_argument&) {
        throw InputError(path, where + ", column '" + name + "': cannot parse '" + cell + "' as a finite number");
      }
    };
    auto required = [&](const char* name) {
      const auto v = number(name);
      if (!v) throw InputError(path, where + ": empty '" + name + "'");
      return *v;
    };
    WheelTestPoint p;
    p.source_line = line_number;
    p.wheel.radius = required("radius_m");
    p.wheel.width = required("width_m");
    p.load = required("load_N");
    p.slip = required("slip");
    if (!(p.wheel.radius > 0.0 && p.wheel.radius < 5.0) || !(p.wheel.width > 0.0 && p.wheel.width < 5.0)) {
      throw InputError(path, where + ": wheel radius and width must be in metres, in (0, 5)");
    }
    if (!(p.load > 0.0)) throw InputError(path, where + ": load_N must be positive");
    if (p.slip < -1.0 || p.slip > 1.0) throw InputError(path, where + ": slip must be a ratio in [-1, 1]");
    const double grousers = number("grouser_count").value_or(0.0);
    if (grousers < 0.0 || grousers > 1000.0 || grousers != std::floor(grousers)) {
      throw InputError(path, where + ": grouser_count must be a whole number in [0, 1000]");
    }
    p.wheel.grouser_count = static_cast<int>(grousers);
    p.wheel.grouser_height = number("grouser_height_m").value_or(0.0);
    if (p.wheel.grouser_height < 0.0 || p.wheel.grouser_height > 0.5 * p.wheel.radius) {
      throw InputError(path, where + ": grouser_height_m must be in metres, between 0 and half the wheel radius");
    }
    if (column.count("wheel")) p.wheel_label = csv::trim(cells[column.at("wheel")]);
    p.drawbar_pull = number("drawbar_pull_N");
    p.torque = number("torque_Nm");
    p.sinkage = number("sinkage_m");
    p.lateral_force = number("lateral_force_N");
    const auto slip_angle_deg = number("slip_angle_deg");
    // Physically impossible in this row: the row is left out, with a warning.
    // Sinkage may exceed the radius (a wheel at a large slip angle digs in),
    // never the diameter.
    std::string impossible;
    if (p.sinkage && (*p.sinkage < 0.0 || *p.sinkage > 2.0 * p.wheel.radius)) {
      impossible = "sinkage_m " + csv::trim(cells[column.at("sinkage_m")]) +
                   " (sinkage_m must be in metres, between 0 and the wheel's diameter)";
    } else if (slip_angle_deg && std::abs(*slip_angle_deg) > 90.0) {
      impossible = "slip_angle_deg " + csv::trim(cells[column.at("slip_angle_deg")]) + " (must be in [-90, 90])";
    }
    if (!impossible.empty()) {
      file.warnings.push_back(where + " left out: " + impossible);
      continue;
    }
    p.slip_angle = slip_angle_deg.value_or(0.0) * M_PI / 180.0;
    points.push_back(p);
  }
  if (points.empty()) {
    throw InputError(path, file.warnings.empty() ? std::string("no data rows")
                                                 : "no usable rows; first left out: " + file.warnings.front());
  }
  if (column.count("grouser_count") == 0 || column.count("grouser_height_m") == 0) {
    if (const std::string hint = grouser_hint(path, points); !hint.empty()) file.warnings.push_back(hint);
  }
  return file;
}

std::vector<WheelTestPoint> read_wheel_test_csv(const std::string& path) { return read_wheel_test_file(path).points; }

}  // namespace roverlab::io
