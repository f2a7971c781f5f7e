#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "core/common/error.h"
#include "core/kinematics/arm.h"
#include "importers/arm_file.h"

namespace fs = std::filesystem;
using namespace roverlab;

namespace {

const std::string kArms = std::string(ROVERLAB_RESOURCES_DIR) + "/arms";

// Heights from tests/importers/arm_fk.py, an independent DH implementation in Python.
std::vector<double> python_heights(const std::string& arm_file, const std::vector<std::vector<double>>& angles) {
  const fs::path dir = fs::temp_directory_path() / ("roverlab_arm_fk_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  {
    std::ofstream in(dir / "angles.txt");
    in.precision(17);
    for (const auto& q : angles) {
      for (double v : q) in << v << ' ';
      in << '\n';
    }
  }
  const std::string command = "python3 " + std::string(ROVERLAB_TEST_SOURCE_DIR) + "/importers/arm_fk.py '" + arm_file +
                              "' < " + (dir / "angles.txt").string() + " > " + (dir / "z.txt").string();
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream out(dir / "z.txt");
  std::vector<double> z;
  for (double v; out >> v;) z.push_back(v);
  fs::remove_all(dir);
  return z;
}

void expect_equal_to_python(const std::string& arm_file) {
  const kinematics::ArmModel arm = io::load_arm(arm_file);
  std::mt19937 rng(44);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::vector<std::vector<double>> angles(200, std::vector<double>(arm.links.size()));
  for (auto& q : angles) {
    for (double& v : q) v = angle(rng);
  }
  const std::vector<double> z = python_heights(arm_file, angles);
  ASSERT_EQ(z.size(), angles.size());
  double worst = 0;
  for (std::size_t i = 0; i < angles.size(); ++i)
    worst = std::max(worst, std::abs(kinematics::arm_tool_height(arm, angles[i]) - z[i]));
  std::printf("%s: largest difference from the Python script %.3g m over %zu poses\n", arm_file.c_str(), worst,
              angles.size());
  EXPECT_LT(worst, 1e-9);
}

}  // namespace

TEST(ArmFile, ShippedArmsLoadAndTheirToolHeightEqualsAnIndependentScript) {
  int arms = 0;
  for (const auto& entry : fs::directory_iterator(kArms)) {
    if (entry.path().extension() != ".json") continue;
    ++arms;
    expect_equal_to_python(entry.path().string());
  }
  EXPECT_GE(arms, 1);
}

TEST(ArmFile, AToolOffsetIsCarriedToTheHeight) {
  const fs::path file = fs::temp_directory_path() / ("roverlab_arm_tool_" + std::to_string(::getpid()) + ".json");
  std::ifstream in(kArms + "/ur5e.json");
  std::stringstream text;
  text << in.rdbuf();
  std::string json = text.str();
  const auto at = json.find("\"tool_m\"");
  ASSERT_NE(at, std::string::npos);
  json = json.substr(0, at) + "\"tool_m\": [0.01, -0.02, 0.15]\n}\n";
  std::ofstream(file) << json;
  expect_equal_to_python(file.string());
  // UR's zero pose: the arm stretched out horizontally, wrist 2 pointing down: the flange at d1 - d5.
  const kinematics::ArmModel ur5e = io::load_arm(kArms + "/ur5e.json");
  EXPECT_NEAR(kinematics::arm_tool_height(ur5e, {0, 0, 0, 0, 0, 0}), 0.1625 - 0.0997, 1e-12);
  fs::remove(file);
}

TEST(ArmFile, BadArmFilesNameTheFileAndTheField) {
  const fs::path file = fs::temp_directory_path() / ("roverlab_arm_bad_" + std::to_string(::getpid()) + ".json");
  const auto message = [&](const std::string& json) {
    std::ofstream(file) << json;
    try {
      io::load_arm(file.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string head = R"({"format": "roverlab-arm", "name": "x", "links": [)";
  EXPECT_NE(message(head + R"({"joint": "j1", "theta": 0, "d": 1e300, "a": 0, "alpha": 0}]})").find("links[0].d"),
            std::string::npos);
  EXPECT_NE(message(head + R"({"joint": "j1", "theta": 0, "d": 0, "a": 0, "alpha": 0},
                                {"joint": "j1", "theta": 0, "d": 0, "a": 0, "alpha": 0}]})")
                .find("twice"),
            std::string::npos);
  EXPECT_NE(message(R"({"format": "roverlab-soil", "name": "x", "links": []})").find("arm"), std::string::npos);
  EXPECT_NE(message(head + "]}").find(file.filename().string()), std::string::npos);
  fs::remove(file);
}
