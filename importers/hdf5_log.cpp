#include "importers/hdf5_log.h"

#include <algorithm>
#include <filesystem>
#include <initializer_list>

#include "core/common/error.h"
#include "core/log/units.h"
#include "importers/atomic_file.h"
#include "importers/hdf5_support.h"

namespace roverlab::io {

namespace fs = std::filesystem;
using h5::Handle;

namespace {

// Chunks of at most 2 MiB of doubles, split evenly so that the last chunk is
// not mostly empty (HDF5 allocates whole chunks). Chunks above the 1 MiB chunk
// cache are read straight into the caller's buffer.
constexpr hsize_t kMaxChunkSamples = 262144;
// Datasets of at most this many samples (8 kB) are compact, stored in their
// object header: a chunked one costs a chunk index each.
constexpr hsize_t kMaxCompactSamples = 1024;

// The metadata as attributes of /metadata up to this many entries, else as
// the one table /metadata/extra (docs/log-format.md).
constexpr std::size_t kMaxMetadataAttributes = 64;
constexpr std::size_t kMaxMetadataEntries = std::size_t{1} << 20;
constexpr const char* kMetadataTable = "extra";

Handle make_group(hid_t parent, const std::string& name) {
  Handle gcpl(H5Pcreate(H5P_GROUP_CREATE));
  H5Pset_link_creation_order(gcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
  Handle group(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT));
  if (!group.valid()) {
    throw std::runtime_error("cannot create group '" + name + "': " + h5::last_error_text());
  }
  return group;
}

Handle open_or_make_group(hid_t parent, const std::string& name) {
  if (h5::object_kind(parent, name) == h5::ObjectKind::group) {
    return Handle(H5Gopen2(parent, name.c_str(), H5P_DEFAULT));
  }
  return make_group(parent, name);
}

void write_vector(hid_t parent, const std::string& name, const std::vector<double>& values, const std::string& unit,
                  const std::string& description) {
  const hsize_t n = values.size();
  Handle space(H5Screate_simple(1, &n, nullptr));
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
  if (n > 0 && n <= kMaxCompactSamples) {
    H5Pset_layout(dcpl.get(), H5D_COMPACT);  // in the object header: no chunk index to create (65,535 topics)
  } else if (n > 0) {
    const hsize_t chunks = (n + kMaxChunkSamples - 1) / kMaxChunkSamples;
    const hsize_t chunk = (n + chunks - 1) / chunks;
    H5Pset_chunk(dcpl.get(), 1, &chunk);
  }
  Handle dataset(H5Dcreate2(parent, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT));
  if (!dataset.valid() ||
      (n > 0 && H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)) {
    throw std::runtime_error("cannot write dataset '" + name + "': " + h5::last_error_text());
  }
  h5::write_string_attribute(dataset.get(), "unit", unit);
  if (!description.empty()) h5::write_string_attribute(dataset.get(), "description", description);
}

// One stream under `streams`: nested names ("truth/imu") become nested
// groups; only the last is a stream.
void write_stream(hid_t streams, const log::Stream& stream) {
  Handle group;
  hid_t parent = streams;
  std::size_t begin = 0;
  const std::string& name = stream.name();
  while (true) {
    const std::size_t slash = name.find('/', begin);
    const std::string segment = name.substr(begin, slash - begin);
    Handle next = slash == std::string::npos ? make_group(parent, segment) : open_or_make_group(parent, segment);
    group = std::move(next);
    parent = group.get();
    if (slash == std::string::npos) break;
    begin = slash + 1;
  }
  h5::write_string_attribute(group.get(), "roverlab_kind", "stream");
  write_vector(group.get(), "time", stream.time(), "s", "");
  Handle channels = make_group(group.get(), "channels");
  for (const auto& c : stream.channels()) {
    write_vector(channels.get(), c.name, c.values, c.unit, c.description);
  }
}

// The file of a log with `metadata` and the streams of `parts`, one after
// another (a log and the streams added to it, without copying either).
void write_file(const log::LogMetadata& meta, std::initializer_list<const log::Log*> parts, const std::string& path) {
  h5::silence_errors();
  Handle fcpl(H5Pcreate(H5P_FILE_CREATE));
  H5Pset_link_creation_order(fcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.get(), H5P_DEFAULT));
  if (!file.valid()) throw std::runtime_error("cannot create file: " + h5::last_error_text());

  h5::write_string_attribute(file.get(), "format", kLogFormatName);
  h5::write_int_attribute(file.get(), "format_version", kLogFormatVersion);
  h5::write_string_attribute(file.get(), "rover_id", meta.rover_id);
  h5::write_string_attribute(file.get(), "source_file", meta.source_file);
  h5::write_string_attribute(file.get(), "description", meta.description);
  Handle metadata = make_group(file.get(), "metadata");
  if (meta.extra.size() > kMaxMetadataEntries) {
    throw std::runtime_error(std::to_string(meta.extra.size()) + " metadata entries (at most " +
                             std::to_string(kMaxMetadataEntries) + ")");
  }
  if (meta.extra.size() <= kMaxMetadataAttributes) {
    for (const auto& [key, value] : meta.extra) h5::write_string_attribute(metadata.get(), key.c_str(), value);
  } else {
    // One entry per topic of a large bag: one table, written at once.
    h5::write_string_pairs(metadata.get(), kMetadataTable, h5::StringPairs(meta.extra.begin(), meta.extra.end()));
  }

  if (!meta.results.empty()) {
    Handle results = make_group(file.get(), "results");
    for (const auto& [name, text] : meta.results) h5::write_text_dataset(results.get(), name.c_str(), text);
  }
  Handle streams = make_group(file.get(), "streams");
  for (const log::Log* part : parts) {
    for (const auto& stream : part->streams()) write_stream(streams.get(), stream);
  }
  if (H5Fflush(file.get(), H5F_SCOPE_GLOBAL) < 0) {
    throw std::runtime_error("cannot flush file: " + h5::last_error_text());
  }
}

// Writes atomically; a failure is an InputError naming the path.
void write_parts(const log::LogMetadata& meta, std::initializer_list<const log::Log*> parts, const std::string& path) {
  write_atomically(path, [&](const std::string& temporary) {
    try {
      write_file(meta, parts, temporary);
    } catch (const InputError&) {
      throw;
    } catch (const std::runtime_error& e) {
      throw InputError(path, std::string("cannot write HDF5 log: ") + e.what());
    }
  });
}

}  // namespace

struct Hdf5LogReader::File {
  Handle file;
  Handle streams;
  // Dataset access without a chunk cache: a dataset is read chunk by chunk
  // straight into the caller's buffer (through the default 1 MiB cache a
  // chunk below that size was copied, its buffer allocated first).
  Handle uncached;
};

namespace {

// Streams nest (estimate/ins/pose): deeper than this is a hard-link cycle.
constexpr int kMaxStreamDepth = 16;
constexpr std::size_t kMaxStoredResultBytes = std::size_t{64} << 20;  // a result document larger is damage

// Collects the streams under `group` (relative names joined with '/').
void collect_streams(hid_t group, const std::string& prefix, std::vector<std::string>& names, int depth = 0) {
  if (depth > kMaxStreamDepth) {
    throw std::runtime_error("streams nested deeper than " + std::to_string(kMaxStreamDepth) + " levels at '" + prefix +
                             "' (a link cycle?)");
  }
  for (const auto& child : h5::link_names(group)) {
    if (h5::object_kind(group, child) != h5::ObjectKind::group) continue;
    Handle sub(H5Gopen2(group, child.c_str(), H5P_DEFAULT));
    const std::string name = prefix.empty() ? child : prefix + "/" + child;
    const auto kind = h5::read_string_attribute(sub.get(), "roverlab_kind");
    if (kind == std::string("stream")) {
      names.push_back(name);
    } else if (kind) {
      // A stream of a kind this RoverLab does not know would be dropped without a word.
      throw std::runtime_error("group '" + name + "' has roverlab_kind '" + *kind + "' (this RoverLab reads 'stream')");
    }
    if (child != "channels") collect_streams(sub.get(), name, names, depth + 1);
  }
}

}  // namespace

Hdf5LogReader::Hdf5LogReader(const std::string& path) : path_(path), file_(new File) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "no such file");
  if (fs::is_directory(path, ec)) throw InputError(path, "is a folder, not a log file");
  if (!h5::is_hdf5_file(path)) throw InputError(path, "not an HDF5 file");
  file_->uncached = Handle(H5Pcreate(H5P_DATASET_ACCESS));
  H5Pset_chunk_cache(file_->uncached.get(), 0, 0, 1.0);
  file_->file = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file_->file.valid()) {
    const std::string why = h5::last_error_text();
    throw InputError(path, "corrupt or truncated HDF5 file" + (why.empty() ? "" : " (" + why + ")"));
  }
  const hid_t f = file_->file.get();
  if (h5::read_string_attribute(f, "format") != std::string(kLogFormatName)) {
    throw InputError(path, "HDF5 file is not a RoverLab log (no format attribute '" + std::string(kLogFormatName) +
                               "'); for other HDF5 or MATLAB files pass --mapping NAME|FILE");
  }
  const auto version = h5::read_int_attribute(f, "format_version");
  if (!version || *version < 1) throw InputError(path, "RoverLab log without a valid format_version");
  if (*version > kLogFormatVersion) {
    throw InputError(path, "log format version " + std::to_string(*version) + " is newer than this RoverLab reads (" +
                               std::to_string(kLogFormatVersion) + ")");
  }
  format_version_ = static_cast<int>(*version);
  metadata_.rover_id = h5::read_string_attribute(f, "rover_id").value_or("");
  metadata_.source_file = h5::read_string_attribute(f, "source_file").value_or("");
  metadata_.description = h5::read_string_attribute(f, "description").value_or("");
  if (h5::object_kind(f, "metadata") == h5::ObjectKind::group) {
    Handle group(H5Gopen2(f, "metadata", H5P_DEFAULT));
    const int n = H5Aget_num_attrs(group.get());
    for (int k = 0; k < n; ++k) {
      Handle attr(H5Aopen_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, static_cast<hsize_t>(k), H5P_DEFAULT,
                                 H5P_DEFAULT));
      const ssize_t len = H5Aget_name(attr.get(), 0, nullptr);
      if (len <= 0) continue;
      std::string key(static_cast<std::size_t>(len) + 1, '\0');
      H5Aget_name(attr.get(), key.size(), key.data());
      key.resize(static_cast<std::size_t>(len));
      metadata_.extra[key] = h5::read_string_attribute(group.get(), key.c_str()).value_or("");
    }
    if (h5::object_kind(group.get(), kMetadataTable) == h5::ObjectKind::dataset) {
      try {
        for (auto& [key, value] : h5::read_string_pairs(group.get(), kMetadataTable, kMaxMetadataEntries)) {
          if (!metadata_.extra.emplace(key, std::move(value)).second) {
            throw std::runtime_error("metadata key '" + key + "' is given twice");
          }
        }
      } catch (const std::runtime_error& e) {
        throw InputError(path, std::string("corrupt RoverLab log: /metadata/") + kMetadataTable + ": " + e.what());
      }
    }
  }
  if (h5::object_kind(f, "results") == h5::ObjectKind::group) {
    Handle group(H5Gopen2(f, "results", H5P_DEFAULT));
    for (const auto& name : h5::link_names(group.get())) {
      // A damaged or oversized result is not reused: the analysis runs again.
      if (auto text = h5::read_text_dataset(group.get(), name.c_str(), kMaxStoredResultBytes))
        metadata_.results[name] = std::move(*text);
    }
  }
  if (h5::object_kind(f, "streams") != h5::ObjectKind::group) {
    throw InputError(path, "RoverLab log without a 'streams' group");
  }
  file_->streams = Handle(H5Gopen2(f, "streams", H5P_DEFAULT));
  std::vector<std::string> names;
  try {
    collect_streams(file_->streams.get(), "", names);
    for (const auto& name : names) {
      StreamInfo info;
      info.name = name;
      Handle group(H5Gopen2(file_->streams.get(), name.c_str(), H5P_DEFAULT));
      if (h5::object_kind(group.get(), "time") != h5::ObjectKind::dataset) {
        throw InputError(path, "stream '" + name + "' has no 'time' dataset");
      }
      Handle time(H5Dopen2(group.get(), "time", H5P_DEFAULT));
      const auto shape = h5::dataset_shape(time.get());
      if (shape.size() != 1) throw InputError(path, "stream '" + name + "': time is not 1-D");
      info.size = shape[0];
      if (h5::object_kind(group.get(), "channels") == h5::ObjectKind::group) {
        Handle channels(H5Gopen2(group.get(), "channels", H5P_DEFAULT));
        for (const auto& cname : h5::link_names(channels.get())) {
          if (h5::object_kind(channels.get(), cname) != h5::ObjectKind::dataset) continue;
          Handle ds(H5Dopen2(channels.get(), cname.c_str(), H5P_DEFAULT));
          const auto unit = h5::read_string_attribute(ds.get(), "unit");
          // RoverLab writes a unit for every channel ("1" when dimensionless): without
          // one, a channel could be used as anything (an angular rate, a distance).
          if (!unit) throw InputError(path, "stream '" + name + "', channel '" + cname + "' has no unit attribute");
          const auto channel_shape = h5::dataset_shape(ds.get());
          if (channel_shape.size() != 1) {
            throw InputError(path, "stream '" + name + "', channel '" + cname + "': expected a 1-D dataset, found " +
                                       std::to_string(channel_shape.size()) + "-D");
          }
          info.channels.push_back(
              ChannelInfo{cname, *unit, h5::read_string_attribute(ds.get(), "description").value_or("")});
        }
      }
      catalog_.push_back(std::move(info));
    }
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const InputError*>(&e) != nullptr) throw;
    throw InputError(path, std::string("corrupt RoverLab log: ") + e.what());
  }
}

Hdf5LogReader::~Hdf5LogReader() = default;

namespace {

// Reads a dataset and converts it from its "unit" attribute (default_unit
// when absent) to SI.
void read_si(const std::string& path, hid_t dataset, const std::string& what, const std::string& default_unit,
             std::vector<double>& values, const std::string& expected_si = {}) {
  try {
    h5::read_doubles(dataset, values);
  } catch (const std::runtime_error& e) {
    throw InputError(path, what + ": " + e.what() + " (truncated or corrupt file?)");
  }
  const std::string unit = h5::read_string_attribute(dataset, "unit").value_or(default_unit);
  log::UnitConversion si;
  try {
    si = log::unit_to_si(unit);
  } catch (const DataError& e) {
    throw InputError(path, what + ": " + e.what());
  }
  if (!expected_si.empty() && si.si_unit != expected_si) {
    throw InputError(path, what + ": unit '" + unit + "' is not a unit of " +
                               (expected_si == "s" ? std::string("time") : expected_si));
  }
  if (si.factor != 1.0 || si.offset != 0.0) {
    for (double& v : values) v = v * si.factor + si.offset;
  }
}

}  // namespace

void Hdf5LogReader::read_time_into(const std::string& stream, std::vector<double>& values) const {
  Handle group(H5Gopen2(file_->streams.get(), stream.c_str(), H5P_DEFAULT));
  if (!group.valid()) throw InputError(path_, "no stream '" + stream + "'");
  Handle ds(H5Dopen2(group.get(), "time", file_->uncached.get()));
  if (!ds.valid()) throw InputError(path_, "stream '" + stream + "' has no time");
  read_si(path_, ds.get(), "stream '" + stream + "', time", "s", values, "s");
}

void Hdf5LogReader::read_channel_into(const std::string& stream, const std::string& channel,
                                      std::vector<double>& values) const {
  const std::string where = stream + "/channels/" + channel;
  if (h5::object_kind(file_->streams.get(), where) != h5::ObjectKind::dataset) {
    throw InputError(path_, "no channel '" + channel + "' in stream '" + stream + "'");
  }
  Handle ds(H5Dopen2(file_->streams.get(), where.c_str(), file_->uncached.get()));
  read_si(path_, ds.get(), "stream '" + stream + "', channel '" + channel + "'", "1", values);
}

std::vector<double> Hdf5LogReader::read_time(const std::string& stream) const {
  std::vector<double> values;
  read_time_into(stream, values);
  return values;
}

std::vector<double> Hdf5LogReader::read_channel(const std::string& stream, const std::string& channel) const {
  std::vector<double> values;
  read_channel_into(stream, channel, values);
  return values;
}

log::Stream Hdf5LogReader::read_stream(const std::string& stream) const {
  const auto info =
      std::find_if(catalog_.begin(), catalog_.end(), [&](const StreamInfo& s) { return s.name == stream; });
  if (info == catalog_.end()) throw InputError(path_, "no stream '" + stream + "'");
  return read_stream(*info);
}

log::Stream Hdf5LogReader::read_stream(const StreamInfo& info) const {
  try {
    log::Stream out(info.name, read_time(info.name));
    for (const auto& c : info.channels) {
      out.add_channel(c.name, log::unit_to_si(c.unit).si_unit, read_channel(info.name, c.name), c.description);
    }
    return out;
  } catch (const DataError& e) {
    throw InputError(path_, e.what());
  }
}

void Hdf5LogReader::read_all_discarding() const {
  std::vector<double> buffer;
  for (const auto& info : catalog_) {
    read_time_into(info.name, buffer);
    for (const auto& c : info.channels) {
      (void)log::unit_to_si(c.unit);  // as read_stream: an unknown unit is a DataError there too
      read_channel_into(info.name, c.name, buffer);
    }
  }
}

log::Log Hdf5LogReader::read_all() const {
  log::Log out;
  out.metadata = metadata_;
  for (const auto& info : catalog_) {  // by its entry, not by name: no search per stream (65,535 streams)
    try {
      out.add_stream(read_stream(info));
    } catch (const DataError& e) {
      throw InputError(path_, e.what());
    }
  }
  return out;
}

bool is_roverlab_hdf5(const std::string& path) {
  if (!h5::is_hdf5_file(path)) return false;
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file.valid()) {
    H5Eclear2(H5E_DEFAULT);
    return false;
  }
  return h5::read_string_attribute(file.get(), "format") == std::string(kLogFormatName);
}

log::Log read_hdf5_log(const std::string& path) { return Hdf5LogReader(path).read_all(); }

void write_hdf5_log(const log::Log& log, const std::string& path) { write_parts(log.metadata, {&log}, path); }

void write_hdf5_log(const log::Log& base, const log::Log& added, const std::string& path) {
  for (const auto& s : added.streams()) {
    if (base.find_stream(s.name()) != nullptr) throw DataError("stream '" + s.name() + "' appears twice");
  }
  log::LogMetadata meta = base.metadata;
  for (const auto& [key, value] : added.metadata.extra) meta.extra[key] = value;
  for (const auto& [key, value] : added.metadata.results) meta.results[key] = value;
  write_parts(meta, {&base, &added}, path);
}

}  // namespace roverlab::io
