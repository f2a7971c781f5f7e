#include "importers/matlab_importer.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include "core/common/error.h"
#include "core/log/units.h"
#include "importers/hdf5_support.h"

namespace roverlab::io {

namespace fs = std::filesystem;
using h5::Handle;

MatFileVersion matlab_file_version(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[128] = {};
  in.read(header, sizeof header);
  const std::string text(header, static_cast<std::size_t>(in.gcount()));
  if (text.rfind("MATLAB 7.3 MAT-file", 0) == 0) return MatFileVersion::v7_3;
  if (text.rfind("MATLAB", 0) == 0 && text.find("MAT-file") != std::string::npos) {
    return MatFileVersion::older;
  }
  return MatFileVersion::not_matlab;
}

namespace {

// A mapping as the user named it: its file when one was given, else its name.
std::string mapping_label(const Mapping& mapping) {
  const bool named_by_its_file = mapping.source.empty() || fs::path(mapping.source).stem() == mapping.name;
  return named_by_its_file ? "'" + mapping.name + "'" : mapping.source;
}

struct Variable {
  std::vector<double> values;
  std::vector<hsize_t> shape;
};

Variable read_variable(const std::string& path, hid_t file, const std::string& mapping_name,
                       const std::string& variable) {
  const h5::ObjectKind kind = h5::object_kind(file, variable);
  if (kind == h5::ObjectKind::group) {
    throw InputError(path, "mapping " + mapping_name + " names variable '" + variable +
                               "', which is a struct or cell array in the file, not a numeric array");
  }
  if (kind != h5::ObjectKind::dataset) {
    throw InputError(path, "mapping " + mapping_name + " names variable '" + variable + "', which the file lacks");
  }
  Handle ds(H5Dopen2(file, variable.c_str(), H5P_DEFAULT));
  Variable v;
  try {
    v.shape = h5::dataset_shape(ds.get());
    v.values = h5::read_doubles(ds.get());
  } catch (const std::runtime_error& e) {
    throw InputError(path, "variable '" + variable + "': " + e.what());
  }
  return v;
}

// The samples of one channel: a vector variable as it is, or one component
// (column) of a 2-D variable whose other axis has `samples` entries.
std::vector<double> select(const std::string& path, const Variable& v, const std::string& variable,
                           std::optional<std::size_t> component, std::size_t samples) {
  std::size_t non_singleton = 0;
  for (hsize_t d : v.shape) non_singleton += d > 1 ? 1 : 0;
  if (non_singleton <= 1) {
    if (component && *component != 0) {
      throw InputError(
          path, "variable '" + variable + "' is a vector; component " + std::to_string(*component) + " does not exist");
    }
    return v.values;
  }
  if (v.shape.size() != 2) {
    throw InputError(path, "variable '" + variable + "' has " + std::to_string(v.shape.size()) +
                               " dimensions; only vectors and 2-D arrays can be mapped");
  }
  if (!component) {
    throw InputError(path, "variable '" + variable + "' is 2-D: the mapping must name a 'component'");
  }
  // HDF5 row-major [rows, cols]; the sample axis is the one as long as the time base.
  const std::size_t rows = v.shape[0], cols = v.shape[1];
  std::vector<double> out;
  if (rows == samples && *component < cols) {
    out.resize(rows);
    for (std::size_t r = 0; r < rows; ++r) out[r] = v.values[r * cols + *component];
  } else if (cols == samples && *component < rows) {
    out.assign(v.values.begin() + static_cast<std::ptrdiff_t>(*component * cols),
               v.values.begin() + static_cast<std::ptrdiff_t>((*component + 1) * cols));
  } else {
    throw InputError(path, "variable '" + variable + "' is " + std::to_string(rows) + " x " + std::to_string(cols) +
                               ": no axis of " + std::to_string(samples) + " samples with component " +
                               std::to_string(*component));
  }
  return out;
}

}  // namespace

log::Log read_mapped_hdf5(const std::string& path, const Mapping& mapping) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "no such file");
  if (fs::is_directory(path, ec)) throw InputError(path, "is a folder, not a log file");
  const MatFileVersion mat = matlab_file_version(path);
  if (!h5::is_hdf5_file(path)) {
    if (mat == MatFileVersion::older) {
      throw InputError(path,
                       "MAT-file older than v7.3 (not HDF5-based); re-save it in MATLAB "
                       "with save(FILE, '-v7.3')");
    }
    if (mat == MatFileVersion::v7_3) {
      throw InputError(path, "MATLAB v7.3 header but no readable HDF5 content (truncated?)");
    }
    throw InputError(path, "not an HDF5 or MATLAB v7.3 file");
  }
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file.valid()) {
    const std::string why = h5::last_error_text();
    throw InputError(path, "corrupt or truncated HDF5 file" + (why.empty() ? "" : " (" + why + ")"));
  }

  // Times first, to find the common origin.
  std::vector<std::vector<double>> times;
  double origin = std::numeric_limits<double>::infinity();
  for (const auto& s : mapping.streams) {
    Variable t = read_variable(path, file.get(), mapping.name, s.time_variable);
    std::vector<double> seconds = select(path, t, s.time_variable, std::nullopt, t.values.size());
    const log::UnitConversion si = log::unit_to_si(s.time_unit);
    for (double& v : seconds) v = v * si.factor + si.offset;
    if (!seconds.empty() && std::isfinite(seconds.front())) origin = std::min(origin, seconds.front());
    times.push_back(std::move(seconds));
  }
  if (mapping.time_origin != "first_sample" || !std::isfinite(origin)) origin = 0.0;

  log::Log out;
  out.metadata.rover_id = mapping.rover_id;
  out.metadata.source_file = fs::path(path).filename().string();
  out.metadata.description = mapping.description;
  out.metadata.extra["mapping"] = mapping.name;
  if (origin != 0.0) {
    char text[64];
    std::snprintf(text, sizeof text, "%.9f", origin);
    out.metadata.extra["time_origin"] = text;
  }
  std::map<std::string, Variable> cache;  // a variable feeding several channels is read once
  for (std::size_t k = 0; k < mapping.streams.size(); ++k) {
    const StreamMapping& sm = mapping.streams[k];
    std::vector<double> t = std::move(times[k]);
    for (double& v : t) v -= origin;
    try {
      log::Stream stream(sm.name, std::move(t));
      for (const auto& cm : sm.channels) {
        auto it = cache.find(cm.variable);
        if (it == cache.end()) {
          it = cache.emplace(cm.variable, read_variable(path, file.get(), mapping_label(mapping), cm.variable)).first;
        }
        std::vector<double> values = select(path, it->second, cm.variable, cm.component, stream.size());
        const log::UnitConversion si = log::unit_to_si(cm.unit);
        for (double& v : values) v = (v * si.factor + si.offset) * cm.scale + 0.0;  // + 0.0: no -0 from flips
        stream.add_channel(cm.name, si.si_unit, std::move(values), cm.description);
      }
      out.add_stream(std::move(stream));
    } catch (const DataError& e) {
      throw InputError(path, std::string(e.what()) + " (mapping " + mapping_label(mapping) + ")");
    }
  }
  return out;
}

}  // namespace roverlab::io
