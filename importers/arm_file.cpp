#include "importers/arm_file.h"

#include <cmath>
#include <set>

#include "importers/json_resource.h"
#include "importers/named_file.h"

namespace roverlab::io {

namespace {

// A lab arm is a metre or two across: a 1e3 m link is a typo.
constexpr double kMaxArmLink = 5.0;

kinematics::ArmLink arm_link(const JsonNode& l) {
  kinematics::ArmLink link;
  link.joint = required_string(l, "joint");
  link.theta = required_number_in(l, "theta", -2 * M_PI, 2 * M_PI);
  link.d = required_number_in(l, "d", -kMaxArmLink, kMaxArmLink);
  link.a = required_number_in(l, "a", -kMaxArmLink, kMaxArmLink);
  link.alpha = required_number_in(l, "alpha", -2 * M_PI, 2 * M_PI);
  return link;
}

}  // namespace

kinematics::ArmModel load_arm(const std::string& path) {
  const JsonResource file = read_json_resource(path, "arm file");
  const JsonNode j = file.root();
  require_format(j, "roverlab-arm", "arm");
  if (j.has("version") && optional_number(j, "version", 1) != 1) {
    j.fail("version", "unsupported arm file version (this RoverLab reads version 1)");
  }
  kinematics::ArmModel arm;
  arm.name = required_string(j, "name");
  arm.description = optional_string(j, "description", "");
  std::set<std::string> seen;
  const std::vector<JsonNode> links = required_array(j, "links");
  if (links.empty() || links.size() > 12) j.fail("links", "must hold 1 to 12 links");
  for (const auto& l : links) {
    arm.links.push_back(arm_link(l));
    if (!seen.insert(arm.links.back().joint).second) l.fail("joint", "joint '" + arm.links.back().joint + "' twice");
  }
  if (j.has("tool_m")) {
    const std::vector<double> tool = required_numbers(j, "tool_m", 3);
    for (double v : tool) {
      if (!(std::abs(v) <= kMaxArmLink)) j.fail("tool_m", "must be within 5 m of the flange");
    }
    arm.tool = Eigen::Vector3d(tool[0], tool[1], tool[2]);
  }
  return arm;
}

kinematics::ArmModel find_arm(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders) {
  return load_arm(find_named_file(name_or_file, folders, "arm"));
}

}  // namespace roverlab::io
