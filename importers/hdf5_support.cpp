#include "importers/hdf5_support.h"

#include <cmath>
#include <cstdio>
#include <new>
#include <stdexcept>

namespace roverlab::io::h5 {

Handle& Handle::operator=(Handle&& other) noexcept {
  if (this != &other) {
    reset();
    id_ = other.id_;
    other.id_ = H5I_INVALID_HID;
  }
  return *this;
}

void Handle::reset() {
  if (id_ < 0) return;
  switch (H5Iget_type(id_)) {
    case H5I_FILE:
      H5Fclose(id_);
      break;
    case H5I_GROUP:
      H5Gclose(id_);
      break;
    case H5I_DATASET:
      H5Dclose(id_);
      break;
    case H5I_DATASPACE:
      H5Sclose(id_);
      break;
    case H5I_DATATYPE:
      H5Tclose(id_);
      break;
    case H5I_ATTR:
      H5Aclose(id_);
      break;
    case H5I_GENPROP_LST:
      H5Pclose(id_);
      break;
    default:
      H5Idec_ref(id_);
      break;
  }
  id_ = H5I_INVALID_HID;
}

void silence_errors() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

namespace {
herr_t keep_innermost(unsigned n, const H5E_error2_t* err, void* data) {
  auto* text = static_cast<std::string*>(data);
  if (n == 0 && err->desc != nullptr) *text = err->desc;  // n = 0: where the error arose
  return 0;
}
}  // namespace

std::string last_error_text() {
  std::string text;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, keep_innermost, &text);
  H5Eclear2(H5E_DEFAULT);
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return text;
}

bool is_hdf5_file(const std::string& path) {
  silence_errors();
  const htri_t r = H5Fis_hdf5(path.c_str());
  H5Eclear2(H5E_DEFAULT);
  return r > 0;
}

bool has_attribute(hid_t object, const char* name) { return H5Aexists(object, name) > 0; }

std::optional<std::string> read_string_attribute(hid_t object, const char* name) {
  if (!has_attribute(object, name)) return std::nullopt;
  Handle attr(H5Aopen(object, name, H5P_DEFAULT));
  if (!attr.valid()) return std::nullopt;
  Handle type(H5Aget_type(attr.get()));
  if (H5Tget_class(type.get()) != H5T_STRING) return std::nullopt;
  Handle space(H5Aget_space(attr.get()));
  if (H5Sget_simple_extent_npoints(space.get()) != 1) return std::nullopt;
  if (H5Tis_variable_str(type.get()) > 0) {
    Handle mem(H5Tcopy(H5T_C_S1));
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
    char* value = nullptr;
    if (H5Aread(attr.get(), mem.get(), &value) < 0) return std::nullopt;
    std::string out = value != nullptr ? value : "";
    H5free_memory(value);
    return out;
  }
  const size_t size = H5Tget_size(type.get());
  if (size == 0 || size > 65536) return std::nullopt;  // more than an attribute stored in its header holds: damaged
  std::string buffer(size + 1, '\0');
  Handle mem(H5Tcopy(H5T_C_S1));
  H5Tset_size(mem.get(), size + 1);
  H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
  if (H5Aread(attr.get(), mem.get(), buffer.data()) < 0) return std::nullopt;
  buffer.resize(buffer.find('\0') == std::string::npos ? size : buffer.find('\0'));
  return buffer;
}

std::optional<std::int64_t> read_int_attribute(hid_t object, const char* name) {
  if (!has_attribute(object, name)) return std::nullopt;
  Handle attr(H5Aopen(object, name, H5P_DEFAULT));
  if (!attr.valid()) return std::nullopt;
  Handle type(H5Aget_type(attr.get()));
  if (H5Tget_class(type.get()) != H5T_INTEGER) return std::nullopt;
  Handle space(H5Aget_space(attr.get()));
  if (H5Sget_simple_extent_npoints(space.get()) != 1) return std::nullopt;
  std::int64_t value = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_INT64, &value) < 0) return std::nullopt;
  return value;
}

void write_string_attribute(hid_t object, const char* name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.get(), value.empty() ? 1 : value.size());
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  Handle space(H5Screate(H5S_SCALAR));
  Handle attr(H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT));
  const std::string stored = value.empty() ? std::string(1, '\0') : value;
  if (!attr.valid() || H5Awrite(attr.get(), type.get(), stored.data()) < 0) {
    throw std::runtime_error(std::string("cannot write attribute '") + name + "': " + last_error_text());
  }
}

void write_text_dataset(hid_t group, const char* name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.get(), value.empty() ? 1 : value.size());
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  Handle space(H5Screate(H5S_SCALAR));
  Handle set(H5Dcreate2(group, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  const std::string stored = value.empty() ? std::string(1, '\0') : value;
  if (!set.valid() || H5Dwrite(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, stored.data()) < 0) {
    throw std::runtime_error(std::string("cannot write dataset '") + name + "': " + last_error_text());
  }
}

std::optional<std::string> read_text_dataset(hid_t group, const char* name, std::size_t max_bytes) {
  if (object_kind(group, name) != ObjectKind::dataset) return std::nullopt;
  Handle set(H5Dopen2(group, name, H5P_DEFAULT));
  if (!set.valid()) return std::nullopt;
  Handle type(H5Dget_type(set.get()));
  Handle space(H5Dget_space(set.get()));
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0 ||
      H5Sget_simple_extent_npoints(space.get()) != 1) {
    return std::nullopt;
  }
  const size_t size = H5Tget_size(type.get());
  if (size == 0 || size > max_bytes) return std::nullopt;
  std::string buffer(size + 1, '\0');
  Handle mem(H5Tcopy(H5T_C_S1));
  H5Tset_size(mem.get(), size + 1);
  H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
  if (H5Dread(set.get(), mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0) return std::nullopt;
  buffer.resize(buffer.find('\0') == std::string::npos ? size : buffer.find('\0'));
  return buffer;
}

namespace {

struct PairRecord {
  const char* key;
  const char* value;
};

Handle pair_type() {
  Handle text(H5Tcopy(H5T_C_S1));
  H5Tset_size(text.get(), H5T_VARIABLE);
  H5Tset_cset(text.get(), H5T_CSET_UTF8);
  Handle type(H5Tcreate(H5T_COMPOUND, sizeof(PairRecord)));
  H5Tinsert(type.get(), "key", HOFFSET(PairRecord, key), text.get());
  H5Tinsert(type.get(), "value", HOFFSET(PairRecord, value), text.get());
  return type;
}

}  // namespace

void write_string_pairs(hid_t group, const char* name, const StringPairs& pairs) {
  std::vector<PairRecord> records;
  records.reserve(pairs.size());
  for (const auto& [key, value] : pairs) records.push_back({key.c_str(), value.c_str()});
  const hsize_t n = records.size();
  Handle type = pair_type();
  Handle space(H5Screate_simple(1, &n, nullptr));
  Handle set(H5Dcreate2(group, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  if (!set.valid() || (n > 0 && H5Dwrite(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, records.data()) < 0)) {
    throw std::runtime_error(std::string("cannot write dataset '") + name + "': " + last_error_text());
  }
}

StringPairs read_string_pairs(hid_t group, const char* name, std::size_t max_pairs) {
  Handle set(H5Dopen2(group, name, H5P_DEFAULT));
  if (!set.valid()) throw std::runtime_error(std::string("cannot open '") + name + "': " + last_error_text());
  Handle stored(H5Dget_type(set.get()));
  const auto shape = dataset_shape(set.get());
  if (H5Tget_class(stored.get()) != H5T_COMPOUND || H5Tget_nmembers(stored.get()) != 2 ||
      H5Tget_member_index(stored.get(), "key") < 0 || H5Tget_member_index(stored.get(), "value") < 0 ||
      shape.size() != 1) {
    throw std::runtime_error(std::string("'") + name + "' is not a 1-D table of key and value strings");
  }
  if (shape[0] > max_pairs) {
    throw std::runtime_error(std::string("'") + name + "' holds " + std::to_string(shape[0]) + " entries (at most " +
                             std::to_string(max_pairs) + ")");
  }
  std::vector<PairRecord> records(static_cast<std::size_t>(shape[0]), PairRecord{nullptr, nullptr});
  Handle type = pair_type();
  if (!records.empty() && H5Dread(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, records.data()) < 0) {
    throw std::runtime_error(std::string("cannot read '") + name + "': " + last_error_text());
  }
  StringPairs pairs;
  pairs.reserve(records.size());
  for (const auto& r : records) pairs.emplace_back(r.key != nullptr ? r.key : "", r.value != nullptr ? r.value : "");
  if (!records.empty()) {
    Handle space(H5Dget_space(set.get()));
    H5Dvlen_reclaim(type.get(), space.get(), H5P_DEFAULT, records.data());
  }
  return pairs;
}

void write_int_attribute(hid_t object, const char* name, std::int64_t value) {
  Handle space(H5Screate(H5S_SCALAR));
  Handle attr(H5Acreate2(object, name, H5T_STD_I64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT));
  if (!attr.valid() || H5Awrite(attr.get(), H5T_NATIVE_INT64, &value) < 0) {
    throw std::runtime_error(std::string("cannot write attribute '") + name + "': " + last_error_text());
  }
}

namespace {

struct LinkList {
  std::vector<std::string> names;
  std::string not_hard;  // the first soft or external link met
};

herr_t collect_name(hid_t, const char* name, const H5L_info_t* info, void* data) {
  auto* list = static_cast<LinkList*>(data);
  if (info->type != H5L_TYPE_HARD) {
    // A soft link can make a cycle (endless walk), an external one reads
    // another file on the machine: a log holds neither.
    if (list->not_hard.empty()) list->not_hard = name;
    return 0;
  }
  list->names.emplace_back(name);
  return 0;
}

}  // namespace

std::vector<std::string> link_names(hid_t group) {
  LinkList list;
  if (H5Literate(group, H5_INDEX_CRT_ORDER, H5_ITER_INC, nullptr, collect_name, &list) < 0) {
    H5Eclear2(H5E_DEFAULT);
    list = LinkList{};
    if (H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_name, &list) < 0) {
      throw std::runtime_error("cannot list group: " + last_error_text());
    }
  }
  if (!list.not_hard.empty()) {
    throw std::runtime_error("link '" + list.not_hard + "' is a soft or external link (a log holds only its own data)");
  }
  return list.names;
}

ObjectKind object_kind(hid_t location, const std::string& path) {
  if (H5Lexists(location, path.c_str(), H5P_DEFAULT) <= 0) {
    H5Eclear2(H5E_DEFAULT);
    return ObjectKind::none;
  }
  Handle object(H5Oopen(location, path.c_str(), H5P_DEFAULT));
  if (!object.valid()) return ObjectKind::none;
  switch (H5Iget_type(object.get())) {
    case H5I_GROUP:
      return ObjectKind::group;
    case H5I_DATASET:
      return ObjectKind::dataset;
    default:
      return ObjectKind::other;
  }
}

std::vector<hsize_t> dataset_shape(hid_t dataset) {
  Handle space(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) throw std::runtime_error("cannot read dataset shape: " + last_error_text());
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0) H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return dims;
}

namespace {

// What a damaged file can make libhdf5 spend seconds on (found by fuzzing a
// 70 kB log): a dataset in chunks of one value (libhdf5 reads chunk by chunk,
// at a cost per chunk even where none is stored) and a chunk index claiming a
// 4 GB chunk (libhdf5 allocates and reads it). RoverLab writes chunks of up
// to 262144 values, MATLAB hundreds of kB: more chunks than this is a damaged
// file, not a log.
constexpr double kMaxChunks = 1 << 16;

void check_chunks(hid_t dataset, hid_t space) {
  Handle dcpl(H5Dget_create_plist(dataset));
  if (!dcpl.valid() || H5Pget_layout(dcpl.get()) != H5D_CHUNKED) return;
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank <= 0) return;
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank)), chunk(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  if (H5Pget_chunk(dcpl.get(), rank, chunk.data()) != rank) {
    throw std::runtime_error("cannot read the dataset's chunk layout: " + last_error_text());
  }
  double chunks = 1.0;
  for (int k = 0; k < rank; ++k) {
    if (chunk[k] == 0) throw std::runtime_error("dataset has chunks of size 0 (damaged file)");
    chunks *= std::ceil(static_cast<double>(dims[k]) / static_cast<double>(chunk[k]));
  }
  if (chunks > kMaxChunks) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "dataset is stored in %.0f chunks, more than the %.0f a log may have (damaged file)", chunks,
                  kMaxChunks);
    throw std::runtime_error(text);
  }
}

// Throws when the dataset's layout says the file is damaged: more storage
// than the whole file, or too many chunks.
void check_storage(hid_t dataset, hid_t space) {
  Handle file(H5Iget_file_id(dataset));
  hsize_t file_size = 0;
  if (!file.valid() || H5Fget_filesize(file.get(), &file_size) < 0) return;
  const hsize_t stored = H5Dget_storage_size(dataset);
  if (stored > file_size) {
    throw std::runtime_error("dataset claims " + std::to_string(stored) + " bytes of storage, more than the file's " +
                             std::to_string(file_size) + " (damaged file)");
  }
  check_chunks(dataset, space);
}

}  // namespace

std::vector<double> read_doubles(hid_t dataset) {
  std::vector<double> values;
  read_doubles(dataset, values);
  return values;
}

void read_doubles(hid_t dataset, std::vector<double>& values) {
  Handle type(H5Dget_type(dataset));
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls != H5T_FLOAT && cls != H5T_INTEGER) {
    throw std::runtime_error("dataset is not numeric");
  }
  // A damaged type can claim values 0 bytes wide, which would let any declared count pass the check below.
  const std::size_t width = H5Tget_size(type.get());
  if (width == 0 || width > 16) {
    throw std::runtime_error("dataset's values are " + std::to_string(width) + " bytes wide (damaged file)");
  }
  Handle space(H5Dget_space(dataset));
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0) throw std::runtime_error("cannot read dataset size: " + last_error_text());
  // A declared size is believed only as far as the file could store it:
  // uncompressed, every value is in the file; compressed, deflate stores at
  // most about 1000 values in the space of one.
  hsize_t file_size = 0;
  {
    Handle file(H5Iget_file_id(dataset));
    if (file.get() < 0 || H5Fget_filesize(file.get(), &file_size) < 0) file_size = 0;
  }
  Handle create(H5Dget_create_plist(dataset));
  const int filters = create.get() >= 0 ? H5Pget_nfilters(create.get()) : 0;
  const double stored = static_cast<double>(n) * static_cast<double>(width);
  const double room = (filters > 0 ? 1000.0 : 1.0) * static_cast<double>(file_size) + 4096.0;
  if (file_size > 0 && stored > room) {
    throw std::runtime_error("declares " + std::to_string(n) + " values, more than the file (" +
                             std::to_string(file_size) + " bytes) can hold");
  }
  check_storage(dataset, space.get());
  try {
    values.resize(static_cast<std::size_t>(n));
  } catch (const std::bad_alloc&) {
    throw std::runtime_error("declares " + std::to_string(n) + " values, more than memory holds");
  }
  if (n > 0 && H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
    const std::string why = last_error_text();
    throw std::runtime_error("cannot read dataset" + (why.empty() ? "" : ": " + why));
  }
}

}  // namespace roverlab::io::h5
