#include "importers/rover_file.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "importers/named_file.h"

namespace roverlab::io {

using nlohmann::json;

namespace {

double number(const json& j, const char* key, const std::string& path, bool positive = false) {
  if (!j.contains(key) || !j.at(key).is_number()) throw InputError(path, std::string("'") + key + "' must be a number");
  const double v = j.at(key).get<double>();
  if (!std::isfinite(v) || (positive && v <= 0)) throw InputError(path, std::string("'") + key + "' must be finite" + (positive ? " and positive" : ""));
  return v;
}

std::vector<double> numbers(const json& j, const char* key, std::size_t n, const std::string& path) {
  if (!j.contains(key) || !j.at(key).is_array() || j.at(key).size() != n) {
    throw InputError(path, std::string("'") + key + "' must be a list of " + std::to_string(n) + " numbers");
  }
  std::vector<double> out;
  for (const auto& v : j.at(key)) {
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0) {
      throw InputError(path, std::string("'") + key + "' must hold non-negative numbers");
    }
    out.push_back(v.get<double>() + 1e-12);  // seed 000 adds 1e-12 to every covariance
  }
  return out;
}

std::array<double, 2> pair(const json& j, const char* key, const std::string& path) {
  if (!j.contains(key) || !j.at(key).is_array() || j.at(key).size() != 2) {
    throw InputError(path, std::string("'") + key + "' must be [x, z]");
  }
  return {j.at(key)[0].get<double>(), j.at(key)[1].get<double>()};
}

}  // namespace

RoverDescription load_rover(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open rover description");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(path, std::string("rover description is not valid JSON: ") + e.what());
  }
  RoverDescription r;
  r.file = path;
  r.kind = j.value("kind", std::string());
  r.name = j.value("name", std::string());
  r.description = j.value("description", std::string());
  try {
    if (r.kind == "dh") {
      kinematics::RoverModel m;
      m.name = r.name;
      m.description = r.description;
      m.wheel_radius = number(j, "wheel_radius_m", path, true);
      for (const auto& n : j.at("joints")) m.joints.push_back(n.get<std::string>());
      for (const auto& l : j.at("links")) {
        kinematics::DhLink link;
        link.from = l.at("from").get<std::string>();
        link.to = l.at("to").get<std::string>();
        link.theta = number(l, "theta", path);
        link.d = number(l, "d", path);
        link.a = number(l, "a", path);
        link.alpha = number(l, "alpha", path);
        if (l.contains("joint")) {
          link.joint = m.joint_index(l.at("joint").get<std::string>());
          if (link.joint < 0) throw InputError(path, "link " + link.from + " -> " + link.to + ": unknown joint '" + l.at("joint").get<std::string>() + "'");
        }
        m.links.push_back(link);
      }
      std::vector<std::string> drive;
      for (const auto& w : j.at("wheels")) {
        kinematics::WheelChain c;
        c.name = w.at("name").get<std::string>();
        m.wheels.push_back(c);
        drive.push_back(w.at("drive_frame").get<std::string>());
      }
      try {
        m.build_chains(drive);
      } catch (const DataError& e) {
        throw InputError(path, e.what());
      }
      if (j.contains("sensor_noise_covariance")) {
        const json& n = j.at("sensor_noise_covariance");
        const std::size_t nw = m.wheels.size();
        std::size_t nb = 0;
        for (const auto& name : m.joints) nb += name.rfind("bogie", 0) == 0;
        m.noise.steer_angle = numbers(n, "steer_angle_rad2", nw, path);
        m.noise.steer_rate = numbers(n, "steer_rate_rad2_s2", nw, path);
        m.noise.wheel_rate = numbers(n, "wheel_rate_rad2_s2", nw, path);
        m.noise.bogie_angle = numbers(n, "bogie_angle_rad2", nb, path);
        m.noise.bogie_rate = numbers(n, "bogie_rate_rad2_s2", nb, path);
        const auto g = numbers(n, "gyro_rad2_s2", 3, path), a = numbers(n, "accelerometer_m2_s4", 3, path);
        m.noise.gyro = Eigen::Vector3d(g[0], g[1], g[2]);
        m.noise.accelerometer = Eigen::Vector3d(a[0], a[1], a[2]);
      }
      r.dh = std::move(m);
    } else if (r.kind == "skid_steer") {
      estimation::SkidSteerGeometry g;
      g.wheel_radius = number(j, "wheel_radius_m", path, true);
      g.track = number(j, "track_m", path, true);
      g.wheelbase = number(j, "wheelbase_m", path, true);
      r.skid_steer = g;
    } else if (r.kind == "planar_rocker_bogie") {
      PlanarRockerBogie p;
      p.wheel_radius = number(j, "wheel_radius_m", path, true);
      const json& l = j.at("links_m");
      p.rocker_to_wheel1 = pair(l, "rocker_pivot_to_wheel_1", path);
      p.rocker_to_bogie = pair(l, "rocker_pivot_to_bogie_pivot", path);
      p.bogie_to_wheel2 = pair(l, "bogie_pivot_to_wheel_2", path);
      p.bogie_to_wheel3 = pair(l, "bogie_pivot_to_wheel_3", path);
      r.planar = p;
    } else {
      throw InputError(path, "unknown rover kind '" + r.kind + "' (dh, skid_steer, planar_rocker_bogie)");
    }
  } catch (const json::exception& e) {
    throw InputError(path, std::string("rover description: ") + e.what());
  }
  return r;
}

RoverDescription find_rover(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders) {
  return load_rover(find_named_file(name_or_file, folders, "rover"));
}

}  // namespace roverlab::io
