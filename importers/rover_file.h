#pragma once
// Rover descriptions as data (resources/rovers/*.json): DH tables of
// six-wheel rocker-bogie rovers (kind "dh", seed 000), four-wheel skid-steer
// geometry (kind "skid_steer", seed 002) and planar rocker-bogie link vectors
// (kind "planar_rocker_bogie", seed 003).

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/kinematics/rover_model.h"
#include "core/models/skid_steer_odometry.h"

namespace roverlab::io {

struct PlanarRockerBogie {
  double wheel_radius = 0.075;
  std::array<double, 2> rocker_to_wheel1{}, rocker_to_bogie{}, bogie_to_wheel2{}, bogie_to_wheel3{};  // x, z in m
};

struct RoverDescription {
  std::string kind, name, description, file;
  std::optional<kinematics::RoverModel> dh;
  std::optional<estimation::SkidSteerGeometry> skid_steer;
  std::optional<PlanarRockerBogie> planar;
};

// Throws InputError naming the file: not JSON, unknown kind, missing or
// non-finite numbers, unknown joint names, broken link chains.
RoverDescription load_rover(const std::string& path);

// NAME (resources/rovers/NAME.json) or FILE.
RoverDescription find_rover(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders);

// NAME only, as a log's rover_id gives it: a value inside a data file never
// opens a file by path. Throws InputError(`source`, ...) for anything that is
// not a plain name (a path, a .json file, empty).
RoverDescription find_rover_named(const std::string& name, const std::vector<std::filesystem::path>& folders,
                                  const std::string& source);

}  // namespace roverlab::io
