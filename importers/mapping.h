#pragma once
// Mapping files (resources/mappings/*.json): how the numeric variables of a
// MATLAB v7.3 (or any HDF5) file become RoverLab streams and channels, with
// unit conversion and scale (a sign flip is scale -1). Format in
// docs/log-format.md.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace roverlab::io {

struct ChannelMapping {
  std::string name;                      // RoverLab channel name
  std::string variable;                  // variable (dataset path) in the file
  std::optional<std::size_t> component;  // column of a 2-D variable, 0-based
  std::string unit = "1";                // unit of the stored values
  double scale = 1.0;                    // applied after unit conversion; -1 flips the sign
  std::string description;
};

struct StreamMapping {
  std::string name;
  std::string time_variable;
  std::string time_unit = "s";
  std::vector<ChannelMapping> channels;
};

struct Mapping {
  std::string name;
  std::string description;
  std::string rover_id;
  // "first_sample": times are shifted so that the earliest sample of any
  // stream is t = 0 (the shift is kept in metadata as time_origin);
  // "none": times are kept as stored.
  std::string time_origin = "first_sample";
  std::vector<StreamMapping> streams;
  std::string source;  // the mapping file it came from
};

// Parses and checks a mapping file. Throws InputError naming the file.
Mapping load_mapping(const std::string& path);

// NAME (looked up as NAME.json in each of `folders`, in order) or a FILE path.
// Throws InputError when neither exists.
std::string find_mapping(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders);

// Names of the mappings found in `folders`.
std::vector<std::string> list_mappings(const std::vector<std::filesystem::path>& folders);

}  // namespace roverlab::io
