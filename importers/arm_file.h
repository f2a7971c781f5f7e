#pragma once
// Manipulator descriptions as data (resources/arms/*.json, format in
// docs/plate-tests.md): a classic DH table, one revolute joint per link, and
// the tool point in the flange frame.

#include <filesystem>
#include <string>
#include <vector>

#include "core/kinematics/arm.h"

namespace roverlab::io {

// Throws InputError naming the file and the field: not JSON, wrong format,
// missing or non-finite numbers, a link longer than 5 m, a joint named twice.
kinematics::ArmModel load_arm(const std::string& path);

// NAME (resources/arms/NAME.json) or FILE.
kinematics::ArmModel find_arm(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders);

}  // namespace roverlab::io
