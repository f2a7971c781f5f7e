#include "importers/rover_file.h"

#include <cmath>

#include "core/common/error.h"
#include "importers/json_resource.h"
#include "importers/named_file.h"

namespace roverlab::io {

namespace {

// The longest link of a rover description, m.
constexpr double kMaxRoverLink = 20.0;

double positive_number(const JsonNode& j, const char* key) {
  const double v = required_number(j, key);
  if (!(v > 0)) j.fail(key, "must be positive");
  if (!(v <= kMaxRoverLink)) j.fail(key, "must be at most 20 (m)");
  return v;
}

std::vector<double> covariances(const JsonNode& j, const char* key, std::size_t n) {
  std::vector<double> out = required_numbers(j, key, n);
  for (double& v : out) {
    if (v < 0) j.fail(key, "must hold non-negative numbers");
    v += 1e-12;  // seed 000 adds 1e-12 to every covariance
  }
  return out;
}

std::array<double, 2> pair(const JsonNode& j, const char* key) {
  const std::vector<double> v = required_numbers(j, key, 2);  // [x, z]
  return {v[0], v[1]};
}

kinematics::DhLink dh_link(const JsonNode& l, const kinematics::RoverModel& m) {
  kinematics::DhLink link;
  link.from = required_string(l, "from");
  link.to = required_string(l, "to");
  // A rover is metres across and angles are radians: a 1e300 m link is a typo.
  link.theta = required_number_in(l, "theta", -2 * M_PI, 2 * M_PI);
  link.d = required_number_in(l, "d", -kMaxRoverLink, kMaxRoverLink);
  link.a = required_number_in(l, "a", -kMaxRoverLink, kMaxRoverLink);
  link.alpha = required_number_in(l, "alpha", -2 * M_PI, 2 * M_PI);
  if (l.has("joint")) {
    const std::string joint = required_string(l, "joint");
    link.joint = m.joint_index(joint);
    if (link.joint < 0) l.fail("joint", "unknown joint '" + joint + "' (link " + link.from + " -> " + link.to + ")");
  }
  return link;
}

void read_sensor_noise(const JsonNode& n, kinematics::RoverModel& m) {
  const std::size_t nw = m.wheels.size();
  std::size_t nb = 0;
  for (const auto& name : m.joints) nb += name.rfind("bogie", 0) == 0;
  m.noise.steer_angle = covariances(n, "steer_angle_rad2", nw);
  m.noise.steer_rate = covariances(n, "steer_rate_rad2_s2", nw);
  m.noise.wheel_rate = covariances(n, "wheel_rate_rad2_s2", nw);
  m.noise.bogie_angle = covariances(n, "bogie_angle_rad2", nb);
  m.noise.bogie_rate = covariances(n, "bogie_rate_rad2_s2", nb);
  const auto g = covariances(n, "gyro_rad2_s2", 3), a = covariances(n, "accelerometer_m2_s4", 3);
  m.noise.gyro = Eigen::Vector3d(g[0], g[1], g[2]);
  m.noise.accelerometer = Eigen::Vector3d(a[0], a[1], a[2]);
}

kinematics::RoverModel dh_rover(const JsonNode& j, const RoverDescription& r) {
  kinematics::RoverModel m;
  m.name = r.name;
  m.description = r.description;
  m.wheel_radius = positive_number(j, "wheel_radius_m");
  for (const auto& n : required_array(j, "joints")) m.joints.push_back(as_string(n));
  for (const auto& l : required_array(j, "links")) m.links.push_back(dh_link(l, m));
  std::vector<std::string> drive;
  for (const auto& w : required_array(j, "wheels")) {
    kinematics::WheelChain c;
    c.name = required_string(w, "name");
    m.wheels.push_back(c);
    drive.push_back(required_string(w, "drive_frame"));
  }
  try {
    m.build_chains(drive);
  } catch (const DataError& e) {
    throw InputError(j.file(), e.what());
  }
  if (j.has("sensor_noise_covariance")) read_sensor_noise(required_object(j, "sensor_noise_covariance"), m);
  return m;
}

estimation::SkidSteerGeometry skid_steer_rover(const JsonNode& j) {
  estimation::SkidSteerGeometry g;
  g.wheel_radius = positive_number(j, "wheel_radius_m");
  g.track = positive_number(j, "track_m");
  g.wheelbase = positive_number(j, "wheelbase_m");
  return g;
}

PlanarRockerBogie planar_rover(const JsonNode& j) {
  PlanarRockerBogie p;
  p.wheel_radius = positive_number(j, "wheel_radius_m");
  const JsonNode l = required_object(j, "links_m");
  p.rocker_to_wheel1 = pair(l, "rocker_pivot_to_wheel_1");
  p.rocker_to_bogie = pair(l, "rocker_pivot_to_bogie_pivot");
  p.bogie_to_wheel2 = pair(l, "bogie_pivot_to_wheel_2");
  p.bogie_to_wheel3 = pair(l, "bogie_pivot_to_wheel_3");
  return p;
}

}  // namespace

RoverDescription load_rover(const std::string& path) {
  const JsonResource file = read_json_resource(path, "rover description");
  const JsonNode j = file.root();
  RoverDescription r;
  r.file = path;
  r.kind = optional_string(j, "kind", "");
  r.name = optional_string(j, "name", "");
  r.description = optional_string(j, "description", "");
  if (r.kind == "dh") {
    r.dh = dh_rover(j, r);
  } else if (r.kind == "skid_steer") {
    r.skid_steer = skid_steer_rover(j);
  } else if (r.kind == "planar_rocker_bogie") {
    r.planar = planar_rover(j);
  } else {
    throw InputError(path, "unknown rover kind '" + r.kind + "' (dh, skid_steer, planar_rocker_bogie)");
  }
  return r;
}

RoverDescription find_rover(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders) {
  return load_rover(find_named_file(name_or_file, folders, "rover"));
}

RoverDescription find_rover_named(const std::string& name, const std::vector<std::filesystem::path>& folders,
                                  const std::string& source) {
  const bool plain = !name.empty() && name.size() <= 128 && name.front() != '.' &&
                     name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.") ==
                         std::string::npos &&
                     std::filesystem::path(name).extension() != ".json";
  if (!plain) {
    throw InputError(source, "rover_id '" + name.substr(0, 128) +
                                 "' is not a rover name (a name from resources/rovers, never a path)");
  }
  for (const auto& folder : folders) {
    if (std::filesystem::exists(folder / (name + ".json"))) return load_rover((folder / (name + ".json")).string());
  }
  return load_rover(find_named_file(name, folders, "rover"));  // the usual "no rover of that name" message
}

}  // namespace roverlab::io
