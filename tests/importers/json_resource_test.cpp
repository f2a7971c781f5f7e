// The JSON resource helper: every error names the file and the field.
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "core/common/error.h"
#include "importers/json_resource.h"
#include "importers/rover_file.h"
#include "importers/scenario_file.h"
#include "importers/soil_file.h"
#include "test_support.h"

using namespace roverlab;
using roverlab::test::TempDir;
using roverlab::test::write_text;

namespace {

// The InputError `read` throws: its file must be `path`; returns the problem.
std::string problem_of(const std::string& path, const std::function<void()>& read) {
  try {
    read();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    return e.problem();
  }
  ADD_FAILURE() << "no error for " << path;
  return "";
}

}  // namespace

TEST(JsonResource, ReadsTypedFields) {
  TempDir dir;
  write_text(dir.file("r.json"),
             R"({"format": "roverlab-x", "n": 2.5, "s": "text", "o": {"v": [1, 2, 3]}, "a": [{"x": 1}, {"x": 2}]})");
  const io::JsonResource file = io::read_json_resource(dir.file("r.json"), "resource");
  const io::JsonNode root = file.root();
  io::require_format(root, "roverlab-x", "thing");
  EXPECT_DOUBLE_EQ(io::required_number(root, "n"), 2.5);
  EXPECT_DOUBLE_EQ(io::optional_number(root, "absent", 7.0), 7.0);
  EXPECT_EQ(io::required_string(root, "s"), "text");
  EXPECT_EQ(io::optional_string(root, "absent", "fallback"), "fallback");
  EXPECT_EQ(io::required_numbers(io::required_object(root, "o"), "v", 3), (std::vector<double>{1, 2, 3}));
  const auto a = io::required_array(root, "a");
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[1].where(), "a[1]");
  EXPECT_DOUBLE_EQ(io::required_number(a[1], "x"), 2.0);
}

TEST(JsonResource, ErrorsNameTheFileAndTheField) {
  TempDir dir;
  const std::string path = dir.file("r.json");
  write_text(path, R"({"n": "2.5", "o": {"v": [1, "two"]}, "a": [{"x": 1}, {"y": 2}], "k": 5})");
  const io::JsonResource file = io::read_json_resource(path, "resource");
  const io::JsonNode root = file.root();
  EXPECT_EQ(problem_of(path, [&] { io::required_number(root, "missing"); }),
            "field 'missing': missing, expected a number");
  EXPECT_EQ(problem_of(path, [&] { io::required_number(root, "n"); }), "field 'n': expected a number, got a string");
  EXPECT_EQ(problem_of(path, [&] { io::optional_string(root, "k", ""); }),
            "field 'k': expected a string, got a number");
  EXPECT_EQ(problem_of(path, [&] { io::required_numbers(io::required_object(root, "o"), "v", 2); }),
            "field 'o.v[1]': expected a number, got a string");
  EXPECT_EQ(problem_of(path, [&] { io::required_numbers(io::required_object(root, "o"), "v", 3); }),
            "field 'o.v': expected 3 numbers, got 2");
  EXPECT_EQ(problem_of(path, [&] { io::required_number(io::required_array(root, "a")[1], "x"); }),
            "field 'a[1].x': missing, expected a number");
  EXPECT_EQ(problem_of(path, [&] { io::required_number_in(root, "k", 0, 1); }), "field 'k': 5 is outside [0, 1]");
  EXPECT_EQ(problem_of(path, [&] { io::require_format(root, "roverlab-x", "thing"); }),
            "not a RoverLab thing ('format' must be \"roverlab-x\")");
}

TEST(JsonResource, UnreadableFilesNameTheFile) {
  TempDir dir;
  EXPECT_EQ(problem_of(dir.file("none.json"), [&] { io::read_json_resource(dir.file("none.json"), "soil file"); }),
            "cannot open soil file");
  write_text(dir.file("bad.json"), "{ not json");
  EXPECT_EQ(problem_of(dir.file("bad.json"), [&] { io::read_json_resource(dir.file("bad.json"), "soil file"); })
                .rfind("soil file is not valid JSON: ", 0),
            0u);
  // Found by fuzzing (tests/fuzz/corpus/json_resources/number_overflow.json): nlohmann's
  // out_of_range for a number beyond a double escaped as an internal failure.
  write_text(dir.file("huge.json"), "{\"format\": \"roverlab-soil\", \"version\": 22E22222}");
  EXPECT_EQ(problem_of(dir.file("huge.json"), [&] { io::read_json_resource(dir.file("huge.json"), "soil file"); })
                .rfind("soil file is not valid JSON: ", 0),
            0u);
  write_text(dir.file("list.json"), "[1, 2]");
  EXPECT_NE(
      problem_of(dir.file("list.json"), [&] { io::read_json_resource(dir.file("list.json"), "rover description"); })
          .find("expected a JSON object"),
      std::string::npos);
}

TEST(JsonResource, ResourceReadersNameTheField) {
  TempDir dir;
  const std::string soil = dir.file("soil.json");
  write_text(soil, R"({"format": "roverlab-soil", "n": 1.1, "cohesion_Pa": "250"})");
  EXPECT_EQ(problem_of(soil, [&] { io::load_soil(soil); }), "field 'cohesion_Pa': expected a number, got a string");

  const std::string rover = dir.file("rover.json");
  write_text(rover, R"({"kind": "planar_rocker_bogie", "wheel_radius_m": 0.075,
                        "links_m": {"rocker_pivot_to_wheel_1": [0.1]}})");
  EXPECT_EQ(problem_of(rover, [&] { io::load_rover(rover); }),
            "field 'links_m.rocker_pivot_to_wheel_1': expected 2 numbers, got 1");
  write_text(rover, R"({"kind": "skid_steer", "wheel_radius_m": 0.1, "track_m": -1, "wheelbase_m": 0.3})");
  EXPECT_EQ(problem_of(rover, [&] { io::load_rover(rover); }), "field 'track_m': must be positive");

  const std::string scenario = dir.file("scenario.json");
  write_text(scenario, R"({"format": "roverlab-scenario", "kind": "rocker-bogie", "rover": "r", "path": "flat",
                           "soil": "s", "duration_s": 10, "effects": {"slip": "high"}})");
  EXPECT_EQ(problem_of(scenario, [&] { io::load_scenario(scenario); }),
            "field 'effects.slip': expected a number, got a string");
  write_text(scenario, R"({"format": "roverlab-scenario", "kind": "rocker-bogie", "rover": "r", "path": "flat",
                           "soil": "s"})");
  EXPECT_EQ(problem_of(scenario, [&] { io::load_scenario(scenario); }),
            "field 'duration_s': missing, expected a number");
}

// Physically absurd values are refused with the field and its range
// (shared/robustness/findings.md F19, F21).
TEST(JsonResource, AbsurdValuesAreRefusedWithTheirRange) {
  TempDir dir;
  const std::string scenario = dir.file("scenario.json");
  const std::string head = R"({"format": "roverlab-scenario", "kind": "rocker-bogie", "rover": "r", "path": "flat",
                               "soil": "s", "duration_s": 10, )";
  write_text(scenario, head + R"("desired_speed_mps": 1000})");
  EXPECT_EQ(problem_of(scenario, [&] { io::load_scenario(scenario); }),
            "field 'desired_speed_mps': must be at most 2 (m/s)");
  write_text(scenario, head + R"("start_x_m": 1e12})");
  EXPECT_EQ(problem_of(scenario, [&] { io::load_scenario(scenario); }), "field 'start_x_m': must be within +-1000 (m)");
  const std::string rover = dir.file("rover.json");
  write_text(rover, R"({"kind": "skid_steer", "wheel_radius_m": 1e300, "track_m": 0.7, "wheelbase_m": 0.5})");
  EXPECT_EQ(problem_of(rover, [&] { io::load_rover(rover); }), "field 'wheel_radius_m': must be at most 20 (m)");
  // The ExoMars BB2 with one DH link 1e300 m long.
  std::string bb2 = test::read_text(std::string(ROVERLAB_RESOURCES_DIR) + "/rovers/exomars_bb2.json");
  const auto at = bb2.find("\"a\":");
  ASSERT_NE(at, std::string::npos);
  bb2.replace(at, bb2.find_first_of(",}", at) - at, "\"a\": 1e300");
  write_text(rover, bb2);
  const std::string problem = problem_of(rover, [&] { io::load_rover(rover); });
  EXPECT_NE(problem.find(".a'"), std::string::npos) << problem;
}
