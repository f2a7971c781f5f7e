// `roverlab soil plate` as a user runs it (issue 44): CSV plate tests of two
// sizes give a soil file that `--soil` reads; a robot-arm ROS bag gives the
// plate's depth from the arm's joint angles, held equal to an independent
// forward-kinematics script (tests/importers/arm_fk.py).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <rosbag/bag.h>
#include <sensor_msgs/JointState.h>

#include <nlohmann/json.hpp>

#include "core/kinematics/arm.h"
#include "core/terramechanics/plate_test.h"
#include "importers/arm_file.h"
#include "importers/soil_file.h"
#include "test_support.h"

using namespace roverlab;
using namespace roverlab::test;
using nlohmann::json;

namespace {

const std::string kExe = ROVERLAB_EXE;
constexpr double kKc = 15600, kKphi = 2.4e6, kN = 1.1;

CommandResult run_roverlab(const std::string& args) { return run_command(quote(kExe) + " " + args); }

// A plate of diameter D pushed from 1 cm above the soil to 5 cm in and back to 2 cm.
void write_plate_csv(const std::string& path, double diameter, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 2.0);
  const terramechanics::Plate plate{true, diameter, diameter};
  std::ofstream out(path);
  out.precision(17);
  out << "# plate_diameter_m: " << diameter << "\ndepth_m,force_N\n";
  for (int i = 0; i <= 300; ++i) {
    const double z = -0.01 + 2e-4 * i;
    out << z << ',' << plate.area() * terramechanics::bekker_pressure(kKc, kKphi, kN, plate.b(), z) + noise(rng)
        << '\n';
  }
  const double pu = terramechanics::bekker_pressure(kKc, kKphi, kN, plate.b(), 0.05);
  for (int i = 1; i <= 150; ++i) {
    const double z = 0.05 - 2e-4 * i;
    out << z << ',' << plate.area() * std::max(0.0, pu - 20 * pu / 0.05 * (0.05 - z)) + noise(rng) << '\n';
  }
}

const json* fit_of(const json& doc, const std::string& model) {
  for (const auto& f : doc.at("fits")) {
    if (f.at("model") == model) return &f;
  }
  return nullptr;
}

double parameter(const json& fit, const std::string& name, const char* what = "value") {
  for (const auto& p : fit.at("parameters")) {
    if (p.at("name") == name) return p.at(what).get<double>();
  }
  ADD_FAILURE() << "no parameter " << name;
  return NAN;
}

}  // namespace

TEST(SoilPlateCli, TwoPlateSizesGiveASoilFileThatSoilOptionsRead) {
  TempDir dir;
  write_plate_csv(dir.file("small.csv"), 0.1, 1);
  write_plate_csv(dir.file("large.csv"), 0.2, 2);
  const std::string soil = dir.file("plate_sand.json");
  const CommandResult r = run_roverlab("soil plate " + quote(dir.file("small.csv")) + " " +
                                       quote(dir.file("large.csv")) + " -o " + quote(soil) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = json::parse(r.out);
  const json& bekker = *fit_of(doc, "bekker");
  EXPECT_TRUE(bekker.at("sizes_separated").get<bool>());
  for (const auto& [name, truth] : {std::pair{"kc", kKc}, std::pair{"kphi", kKphi}, std::pair{"n", kN}}) {
    EXPECT_NEAR(parameter(bekker, name), truth, 3.0 * parameter(bekker, name, "sigma")) << name;
  }
  ASSERT_NE(fit_of(doc, "reece"), nullptr);
  ASSERT_NE(fit_of(doc, "rft"), nullptr);
  EXPECT_EQ(doc.at("files")[0].at("segments")[1].at("kind"), "loading");
  EXPECT_EQ(doc.at("files")[0].at("segments")[2].at("kind"), "unloading");
  // The soil file: the fitted Bekker moduli, its provenance, and every command's --soil reads it.
  const terramechanics::Soil s = io::load_soil(soil);
  EXPECT_DOUBLE_EQ(s.kphi, parameter(bekker, "kphi"));
  EXPECT_EQ(s.name, "plate_sand");
  const json written = json::parse(read_text(soil));
  EXPECT_EQ(written.at("plate_test").at("analysis").at("files")[1].at("sha256").get<std::string>().size(), 64U);
  const CommandResult t =
      run_roverlab("terramechanics --soil " + quote(soil) + " --radius 0.15 --width 0.1 --load 100 --slip 0.2");
  EXPECT_EQ(t.exit_code, 0) << t.err;
}

TEST(SoilPlateCli, BadInputIsOneLineNamingTheFileOrOption) {
  TempDir dir;
  write_text(dir.file("nosize.csv"), "depth_m,force_N\n0,0\n0.01,1\n");
  const CommandResult r = run_roverlab("soil plate " + quote(dir.file("nosize.csv")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("nosize.csv"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("plate_diameter_m"), std::string::npos) << r.err;
  write_text(
      dir.file("air.csv"), "# plate_diameter_m: 0.1\ndepth_m,force_N\n" + [] {
        std::string rows;
        for (int i = 0; i < 50; ++i) rows += std::to_string(0.001 * i) + "," + (i % 2 ? "0.1" : "-0.1") + "\n";
        return rows;
      }());
  const CommandResult air = run_roverlab("soil plate " + quote(dir.file("air.csv")));
  EXPECT_EQ(air.exit_code, 3);
  EXPECT_NE(air.err.find("air.csv"), std::string::npos) << air.err;
  EXPECT_NE(air.err.find("no contact"), std::string::npos) << air.err;
  const CommandResult log = run_roverlab("soil plate " + quote(dir.file("air.bag")) + " --depth a/b");
  EXPECT_EQ(log.exit_code, 2);
  EXPECT_NE(log.err.find("--force"), std::string::npos) << log.err;
}

// A UR5e pushing a 10 cm plate: /data WrenchStamped (z pointing into the
// soil, so --invert-force) and /joint_states at the same times.
TEST(SoilPlateCli, ARobotArmBagGivesTheDepthOfAnIndependentForwardKinematicsScript) {
  TempDir dir;
  const std::string bag_path = dir.file("plate.bag");
  const kinematics::ArmModel arm = io::load_arm(std::string(ROVERLAB_RESOURCES_DIR) + "/arms/ur5e.json");
  const std::vector<std::string> names = arm.joints();
  const terramechanics::Plate plate{true, 0.1, 0.1};
  std::vector<std::vector<double>> angles;
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    const ros::Time start(1700000000, 0);
    double h0 = NAN, deepest = 0;
    for (int i = 0; i < 600; ++i) {
      const double s = i < 400 ? 0.3 * i / 400.0 : 0.3 - 0.1 * (i - 400) / 200.0;  // down, then back up
      const std::vector<double> q{0.0, -1.2 + 0.6 * s, 1.5 - 0.3 * s, -1.87 - 0.3 * s, -1.5708, 0.3};
      angles.push_back(q);
      const double h = kinematics::arm_tool_height(arm, q);
      if (std::isnan(h0)) h0 = h;
      const double z = h0 - h - 0.01;  // the soil 1 cm below the start
      deepest = std::max(deepest, z);
      double p = terramechanics::bekker_pressure(kKc, kKphi, kN, plate.b(), z);
      if (z < deepest) {
        const double pu = terramechanics::bekker_pressure(kKc, kKphi, kN, plate.b(), deepest);
        p = std::max(0.0, pu - 20 * pu / deepest * (deepest - z));
      }
      const ros::Time t = start + ros::Duration(0.01 * i);
      sensor_msgs::JointState js;
      js.header.stamp = t;
      js.name = names;
      js.position = q;
      bag.write("/joint_states", t, js);
      geometry_msgs::WrenchStamped w;
      w.header.stamp = t;
      w.wrench.force.z = -plate.area() * p + 0.5 * std::sin(1.7 * i);
      bag.write("/data", t, w);
    }
  }
  const std::string samples = dir.file("samples.csv");
  const CommandResult r = run_roverlab("soil plate " + quote(bag_path) +
                                       " -m ros_plate_arm --force forces/force_z --invert-force --arm ur5e "
                                       "--joints joints --plate-diameter 0.1 --samples " +
                                       quote(samples) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = json::parse(r.out);
  const json& bekker = *fit_of(doc, "bekker");
  EXPECT_FALSE(bekker.at("sizes_separated").get<bool>());
  EXPECT_NEAR(parameter(bekker, "n"), kN, 0.02);
  EXPECT_NEAR(bekker.at("contact_depths_m")[0].get<double>(), 0.01, 2e-4);
  // The depth the command used, against the Python script on the bag's joint angles.
  {
    std::ofstream in(dir.file("angles.txt"));
    in.precision(17);
    for (const auto& q : angles) {
      for (double v : q) in << v << ' ';
      in << '\n';
    }
  }
  ASSERT_EQ(std::system(("python3 " + quote(std::string(ROVERLAB_TEST_SOURCE_DIR) + "/importers/arm_fk.py") + " " +
                         quote(std::string(ROVERLAB_RESOURCES_DIR) + "/arms/ur5e.json") + " < " +
                         quote(dir.file("angles.txt")) + " > " + quote(dir.file("z.txt")))
                            .c_str()),
            0);
  std::ifstream zs(dir.file("z.txt"));
  std::vector<double> height;
  for (double v; zs >> v;) height.push_back(v);
  std::ifstream table(samples);
  std::string line;
  std::getline(table, line);
  std::size_t row = 0;
  double worst = 0;
  while (std::getline(table, line)) {
    std::stringstream cells(line);
    std::string record, sample, depth;
    std::getline(cells, record, ',');
    std::getline(cells, sample, ',');
    std::getline(cells, depth, ',');
    ASSERT_LT(row, height.size());
    worst = std::max(worst, std::abs(std::stod(depth) - (height[0] - height[row])));
    ++row;
  }
  EXPECT_EQ(row, angles.size());
  std::printf("largest depth difference from the Python forward kinematics: %.3g m over %zu samples\n", worst, row);
  EXPECT_LT(worst, 1e-9);
}

// A linear stage instead of an arm, read without a mapping: its height on
// /stage/pose (z up, so --invert-depth), the force on /data.
TEST(SoilPlateCli, ALinearStagesHeightIsTheDepthOfAnUnmappedBag) {
  TempDir dir;
  const std::string bag_path = dir.file("stage.bag");
  const terramechanics::Plate plate{true, 0.2, 0.2};
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    const ros::Time start(1700000000, 0);
    for (int i = 0; i < 400; ++i) {
      const double height = 0.30 - 1.5e-4 * i;  // the soil at 0.29 m
      const ros::Time t = start + ros::Duration(0.01 * i);
      geometry_msgs::PoseStamped p;
      p.header.stamp = t;
      p.pose.position.z = height;
      bag.write("/stage/pose", t, p);
      geometry_msgs::WrenchStamped w;
      w.header.stamp = t;
      w.wrench.force.z = plate.area() * terramechanics::bekker_pressure(kKc, kKphi, kN, plate.b(), 0.29 - height) +
                         0.3 * std::cos(2.3 * i);
      bag.write("/data", t, w);
    }
  }
  const CommandResult r = run_roverlab(
      "soil plate " + quote(bag_path) +
      " --force data/wrench.force.z --depth stage/pose/pose.position.z --invert-depth --plate-diameter 0.2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = json::parse(r.out);
  const json& bekker = *fit_of(doc, "bekker");
  EXPECT_NEAR(parameter(bekker, "n"), kN, 0.01);
  EXPECT_NEAR(parameter(bekker, "k_eq"), kKc / 0.1 + kKphi, 0.02 * (kKc / 0.1 + kKphi));
  // Depth is minus the height: the soil surface at -0.29 m.
  EXPECT_NEAR(bekker.at("contact_depths_m")[0].get<double>(), -0.29, 2e-4);
  const CommandResult bad = run_roverlab("soil plate " + quote(bag_path) +
                                         " --force data/wrench.force.q --depth stage/pose/pose.position.z "
                                         "--plate-diameter 0.2");
  EXPECT_EQ(bad.exit_code, 3);
  EXPECT_NE(bad.err.find("stage.bag"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("wrench.force.q"), std::string::npos) << bad.err;
}
