#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "importers/named_file.h"
#include "importers/soil_file.h"
#include "importers/wheel_test_csv.h"
#include "test_support.h"

using namespace roverlab;
using roverlab::test::TempDir;
using roverlab::test::write_text;

namespace {
const std::vector<std::filesystem::path> kSoils{std::string(ROVERLAB_RESOURCES_DIR) + "/soils"};
}

TEST(SoilFile, ShippedSoilsLoadWithSources) {
  const auto names = io::list_named_files(kSoils);
  for (const char* required : {"ding_tyii", "lunar_nominal", "dry_sand", "lete_sand"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
  }
  EXPECT_GE(names.size(), 6u);
  for (const auto& name : names) {
    const auto soil = io::find_soil(name, kSoils);
    EXPECT_EQ(soil.name, name);
    EXPECT_FALSE(soil.source.empty()) << name;
  }
  const auto tyii = io::find_soil("ding_tyii", kSoils);  // seed 003 Table 2.2
  EXPECT_DOUBLE_EQ(tyii.n, 1.1);
  EXPECT_DOUBLE_EQ(tyii.cohesion, 250.0);
  EXPECT_NEAR(tyii.friction_angle, 31.9 * M_PI / 180.0, 1e-15);
  EXPECT_DOUBLE_EQ(tyii.shear_modulus, 0.0114);
  EXPECT_DOUBLE_EQ(tyii.kc, 15600.0);
  EXPECT_DOUBLE_EQ(tyii.kphi, 2407400.0);
}

TEST(SoilFile, LateralShearModulusIsOptional) {
  TempDir dir;
  const std::string body = R"("format": "roverlab-soil", "n": 1.1, "cohesion_Pa": 250, "friction_angle_deg": 31.9,
      "shear_modulus_m": 0.0114, "kc": 15600, "kphi": 2407400, "c1": 0.18, "c2": 0.32)";
  write_text(dir.file("a.json"), "{" + body + "}");
  EXPECT_EQ(io::load_soil(dir.file("a.json")).lateral_shear_modulus, 0.0);  // k_y = K_s (slip_angle_model.h)
  write_text(dir.file("b.json"), "{" + body + R"(, "lateral_shear_modulus_m": 0.02})");
  EXPECT_DOUBLE_EQ(io::load_soil(dir.file("b.json")).lateral_shear_modulus, 0.02);
  write_text(dir.file("c.json"), "{" + body + R"(, "lateral_shear_modulus_m": 20})");  // mm, not m
  EXPECT_THROW(io::load_soil(dir.file("c.json")), InputError);
}

TEST(SoilFile, BadSoilFilesNameTheFileAndTheProblem) {
  TempDir dir;
  write_text(dir.file("a.json"), R"({"format": "roverlab-soil", "n": 1.1})");
  try {
    io::load_soil(dir.file("a.json"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'cohesion_Pa'"), std::string::npos) << e.what();
  }
  write_text(dir.file("b.json"),
             R"({"format": "roverlab-soil", "n": 1.1, "cohesion_Pa": 250, "friction_angle_deg": 0.55,
                 "shear_modulus_m": 11.4, "kc": 1, "kphi": 1, "c1": 0.18, "c2": 0.32})");
  EXPECT_THROW(io::load_soil(dir.file("b.json")), InputError);  // K in mm instead of m: out of range
  EXPECT_THROW(io::find_soil("martian_regolith_x", kSoils), InputError);
}

TEST(WheelTestCsv, ReadsTheDing2011File) {
  const auto points = io::read_wheel_test_csv(std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv");
  ASSERT_EQ(points.size(), 12u);
  EXPECT_EQ(points[0].wheel_label, "smooth");
  EXPECT_DOUBLE_EQ(points[0].wheel.radius, 0.15735);
  EXPECT_DOUBLE_EQ(points[0].load, 80.0);
  EXPECT_DOUBLE_EQ(*points[1].drawbar_pull, 11.0);
  EXPECT_EQ(points[6].wheel.grouser_count, 30);
  EXPECT_DOUBLE_EQ(points[6].wheel.grouser_height, 0.010);
  EXPECT_FALSE(points[11].torque.has_value());  // empty cell: not readable from the source figure
  EXPECT_FALSE(points[11].sinkage.has_value());
  EXPECT_DOUBLE_EQ(*points[11].drawbar_pull, 24.5);
}

TEST(WheelTestCsv, SlipAngleColumnsAndImpossibleRowsLeftOutWithAWarning) {
  TempDir dir;
  const std::string path = dir.file("steer.csv");
  write_text(path,
             "radius_m,width_m,load_N,slip,slip_angle_deg,sinkage_m,lateral_force_N\n"
             "0.1,0.1,80,0.2,30,0.15,-21.5\n"   // sinkage beyond the radius, within the diameter: kept
             "0.1,0.1,80,0.2,-10,0.01,\n"       // lateral force unmeasured
             "0.1,0.1,80,0.2,45,0.25,-30\n"     // sinkage beyond the diameter: left out
             "0.1,0.1,80,0.2,120,0.02,-30\n"    // slip angle beyond 90 deg: left out
             "0.1,0.1,80,0.2,60,-0.01,-30\n");  // negative sinkage: left out
  const io::WheelTestFile file = io::read_wheel_test_file(path);
  ASSERT_EQ(file.points.size(), 2u);
  EXPECT_NEAR(file.points[0].slip_angle, 30.0 * M_PI / 180.0, 1e-15);
  EXPECT_DOUBLE_EQ(*file.points[0].lateral_force, -21.5);
  EXPECT_DOUBLE_EQ(*file.points[0].sinkage, 0.15);
  EXPECT_NEAR(file.points[1].slip_angle, -10.0 * M_PI / 180.0, 1e-15);
  EXPECT_FALSE(file.points[1].lateral_force.has_value());
  ASSERT_EQ(file.warnings.size(), 3u);
  EXPECT_NE(file.warnings[0].find("line 4"), std::string::npos) << file.warnings[0];
  EXPECT_NE(file.warnings[0].find("sinkage_m 0.25"), std::string::npos) << file.warnings[0];
  EXPECT_NE(file.warnings[1].find("line 5"), std::string::npos) << file.warnings[1];
  EXPECT_NE(file.warnings[1].find("slip_angle_deg 120"), std::string::npos) << file.warnings[1];
  EXPECT_NE(file.warnings[2].find("line 6"), std::string::npos) << file.warnings[2];
  EXPECT_EQ(io::read_wheel_test_csv(path).size(), 2u);
  // Without the columns the slip angle is 0 and no lateral force is measured.
  const auto ding = io::read_wheel_test_csv(std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv");
  for (const auto& p : ding) {
    EXPECT_EQ(p.slip_angle, 0.0);
    EXPECT_FALSE(p.lateral_force.has_value());
  }
  // A file of lateral forces alone is a measured file.
  write_text(dir.file("lateral.csv"),
             "radius_m,width_m,load_N,slip,slip_angle_deg,lateral_force_N\n0.1,0.1,80,0.2,20,-9\n");
  EXPECT_EQ(io::read_wheel_test_csv(dir.file("lateral.csv")).size(), 1u);
}

TEST(WheelTestCsv, BadFilesNameLineAndProblem) {
  TempDir dir;
  const std::string head = "radius_m,width_m,load_N,slip,sinkage_m\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"width_m,load_N,slip,sinkage_m\n0.1,80,0.1,0.01\n", "missing column 'radius_m'"},
      {"radius_m,width_m,load_N,slip\n0.1,0.1,80,0.1\n", "no measured column"},
      {head + "0.1,0.1,80,0.1,0.01\n0.1,0.1,80,abc,0.01\n", "line 3, column 'slip'"},
      {head + "0.1,0.1,80,0.1\n", "ragged row"},
      {head + "157,0.1,80,0.1,0.01\n", "in metres"},
      {head + "0.1,0.1,80,30,0.01\n", "slip must be a ratio"},
      {head + "0.1,0.1,80,0.1,5\n", "sinkage_m must be in metres"},  // the only row, left out: no usable rows
      {"radius_m,width_m,load_N,slip,slip_angle_deg,lateral_force_N\n0.1,0.1,80,0.1,1e3,-2\n", "line 2 left out"},
      {head + "0.1,0.1,nan,0.1,0.01\n", "finite number"},
      {head, "no data rows"},
      // Found by fuzzing (tests/fuzz/corpus/wheel_test_csv/grouser_count_2e51.csv): cast to int unchecked.
      {"radius_m,width_m,load_N,slip,sinkage_m,grouser_count\n0.1,0.1,80,0.1,0.01,2.2e51\n", "grouser_count must be"},
      {"radius_m,width_m,load_N,slip,sinkage_m,grouser_count\n0.1,0.1,80,0.1,0.01,2.5\n", "grouser_count must be"},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string path = dir.file("p" + std::to_string(k) + ".csv");
    write_text(path, cases[k].first);
    try {
      io::read_wheel_test_csv(path);
      ADD_FAILURE() << "accepted case " << k;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(cases[k].second), std::string::npos) << "case " << k << ": " << e.what();
      EXPECT_EQ(e.file(), path);
    }
  }
}

// Issue 43: a wheel named grousered (its label, or the file's name) without
// grouser columns gets one warning line naming the columns; a smooth wheel,
// or a file with the columns, gets none.
TEST(WheelTestCsv, AGrouseredWheelWithoutGrouserColumnsGetsAHintNamingThem) {
  TempDir dir;
  const std::string rows = "0.0625,0.06,20,0.2,3.1\n0.0625,0.06,20,0.4,5.2\n";
  write_text(dir.file("a.csv"),
             "wheel,radius_m,width_m,load_N,slip,drawbar_pull_N\n"
             "Grousered,0.0625,0.06,20,0.2,3.1\n");
  write_text(dir.file("wheel_grousers.csv"), "radius_m,width_m,load_N,slip,drawbar_pull_N\n" + rows);
  write_text(dir.file("smooth.csv"),
             "wheel,radius_m,width_m,load_N,slip,drawbar_pull_N\nsmooth,0.0625,0.06,20,0.2,3\n");
  write_text(dir.file("grousered_with_columns.csv"),
             "radius_m,width_m,load_N,slip,drawbar_pull_N,grouser_count,grouser_height_m\n"
             "0.0625,0.06,20,0.2,3.1,12,0.005\n");
  for (const char* name : {"a.csv", "wheel_grousers.csv"}) {
    const io::WheelTestFile file = io::read_wheel_test_file(dir.file(name));
    ASSERT_EQ(file.warnings.size(), 1u) << name;
    EXPECT_NE(file.warnings[0].find("grouser_count"), std::string::npos) << file.warnings[0];
    EXPECT_NE(file.warnings[0].find("grouser_height_m"), std::string::npos) << file.warnings[0];
    EXPECT_EQ(file.warnings[0].find('\n'), std::string::npos) << file.warnings[0];
  }
  EXPECT_NE(io::read_wheel_test_file(dir.file("a.csv")).warnings[0].find("wheel 'Grousered'"), std::string::npos);
  EXPECT_TRUE(io::read_wheel_test_file(dir.file("smooth.csv")).warnings.empty());
  EXPECT_TRUE(io::read_wheel_test_file(dir.file("grousered_with_columns.csv")).warnings.empty());
}

// Issue 43: a file states its slip definition by its slip column's name
// (travel_slip or longitudinal_slip); two files with the same header are
// read the same way, and a file with two slip columns is refused.
TEST(WheelTestCsv, TheSlipColumnsNameStatesItsDefinition) {
  TempDir dir;
  const std::string row = "0.0625,0.06,20,0.3,45,3.1\n";
  write_text(dir.file("a.csv"), "radius_m,width_m,load_N,travel_slip,slip_angle_deg,drawbar_pull_N\n" + row);
  write_text(dir.file("b.csv"), "radius_m,width_m,load_N,travel_slip,slip_angle_deg,drawbar_pull_N\n" + row);
  write_text(dir.file("c.csv"), "radius_m,width_m,load_N,longitudinal_slip,slip_angle_deg,drawbar_pull_N\n" + row);
  write_text(dir.file("d.csv"), "radius_m,width_m,load_N,slip,slip_angle_deg,drawbar_pull_N\n" + row);
  write_text(dir.file("e.csv"), "radius_m,width_m,load_N,slip,travel_slip,drawbar_pull_N\n0.0625,0.06,20,0.3,0.3,3\n");
  const auto a = io::read_wheel_test_file(dir.file("a.csv"));
  EXPECT_EQ(a.slip_definition, "travel");
  EXPECT_EQ(io::read_wheel_test_file(dir.file("b.csv")).slip_definition, a.slip_definition);
  ASSERT_EQ(a.points.size(), 1u);
  EXPECT_DOUBLE_EQ(a.points[0].slip, 0.3);
  EXPECT_EQ(io::read_wheel_test_file(dir.file("c.csv")).slip_definition, "longitudinal");
  EXPECT_EQ(io::read_wheel_test_file(dir.file("d.csv")).slip_definition, "");
  try {
    io::read_wheel_test_file(dir.file("e.csv"));
    FAIL() << "two slip columns were read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("e.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("more than one slip column"), std::string::npos) << e.what();
  }
}
