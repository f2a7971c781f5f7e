#pragma once
// Small RAII and helper layer over the HDF5 C API, shared by the RoverLab log
// format and the mapped (MATLAB v7.3) importer. Internal to roverlab_io.

#include <hdf5.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace roverlab::io::h5 {

// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : id_(other.id_) { other.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& other) noexcept;
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  void reset();

 private:
  hid_t id_ = H5I_INVALID_HID;
};

// Turns HDF5's automatic error printing off for this process (errors become
// exceptions with one line of text instead).
void silence_errors();

// The most specific message on HDF5's error stack, e.g. "truncated file: ...",
// or an empty string.
std::string last_error_text();

// True when the file at path has an HDF5 signature (at 0, 512, 1024, ...,
// as in MATLAB v7.3 files whose first 512 bytes are a text header).
bool is_hdf5_file(const std::string& path);

bool has_attribute(hid_t object, const char* name);
std::optional<std::string> read_string_attribute(hid_t object, const char* name);
std::optional<std::int64_t> read_int_attribute(hid_t object, const char* name);
void write_string_attribute(hid_t object, const char* name, const std::string& value);
void write_int_attribute(hid_t object, const char* name, std::int64_t value);
// A text too long for an attribute (a stored result document) as a scalar
// string dataset; read back when it is one of at most `max_bytes`.
void write_text_dataset(hid_t group, const char* name, const std::string& value);
std::optional<std::string> read_text_dataset(hid_t group, const char* name, std::size_t max_bytes);
// Key/value text pairs as one 1-D dataset of a compound {key, value} of UTF-8
// variable-length strings: thousands of pairs in one write (as attributes of
// one object, libhdf5 appends each to its header in time linear in those
// before it). Reading throws std::runtime_error when the dataset is not such a
// table or holds more than `max_pairs`.
using StringPairs = std::vector<std::pair<std::string, std::string>>;
void write_string_pairs(hid_t group, const char* name, const StringPairs& pairs);
StringPairs read_string_pairs(hid_t group, const char* name, std::size_t max_pairs);

// Links of a group, in creation order when the group tracks it, else by name.
std::vector<std::string> link_names(hid_t group);

enum class ObjectKind { none, group, dataset, other };
ObjectKind object_kind(hid_t location, const std::string& path);

// Shape of a dataset (empty for a scalar).
std::vector<hsize_t> dataset_shape(hid_t dataset);

// Whole numeric dataset converted to double (integer or float storage).
// Throws std::runtime_error with the HDF5 message when the read fails.
std::vector<double> read_doubles(hid_t dataset);
// The same into `values` (resized; its memory reused when large enough).
void read_doubles(hid_t dataset, std::vector<double>& values);

}  // namespace roverlab::io::h5
