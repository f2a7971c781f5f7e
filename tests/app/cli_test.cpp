// The roverlab command line, run as a user runs it: exit codes, one-line
// errors naming the file, no partial output, and the convert round trip.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/common/error.h"
#include "core/terramechanics/traction_surface.h"
#include "importers/hdf5_log.h"
#include "importers/log_file.h"
#include "importers/mapping.h"
#include "importers/raw_hdf5.h"
#include "test_support.h"

using namespace roverlab;
using namespace roverlab::test;
namespace fs = std::filesystem;

namespace {

const std::string kExe = ROVERLAB_EXE;
const std::string kPathfinder = std::string(ROVERLAB_TEST_DATA) + "/test17run.mat";

CommandResult run_roverlab(const std::string& args) { return run_command(quote(kExe) + " " + args); }

std::size_t count_lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

// Runs `info` and `convert` on a bad input: both must exit 3 with one line on
// stderr naming the file and containing `problem`, and convert must leave no
// output (nor temporary) file.
void expect_bad_input(const std::string& input, const std::string& problem, const std::string& extra_args = "") {
  SCOPED_TRACE(input);
  const CommandResult info = run_roverlab("info " + quote(input) + " " + extra_args);
  EXPECT_EQ(info.exit_code, 3) << info.err;
  EXPECT_EQ(count_lines(info.err), 1u) << info.err;
  EXPECT_NE(info.err.find(input), std::string::npos) << info.err;
  EXPECT_NE(info.err.find(problem), std::string::npos) << info.err;

  TempDir out;
  const CommandResult convert =
      run_roverlab("convert " + quote(input) + " " + quote(out.file("out.h5")) + " " + extra_args);
  EXPECT_EQ(convert.exit_code, 3) << convert.err;
  EXPECT_EQ(count_lines(convert.err), 1u) << convert.err;
  EXPECT_NE(convert.err.find(problem), std::string::npos) << convert.err;
  EXPECT_EQ(files_in(out.path()), 0u) << "convert left a file behind";
}

// A RoverLab HDF5 log written by hand: one stream "imu" with the given time
// base and one channel "x" of the given unit (none when `unit` is empty).
void write_raw_log(const std::string& path, const std::vector<double>& time, const std::vector<double>& x,
                   const std::string& unit = "1") {
  RawHdf5 f(path);
  f.roverlab_header(1);
  f.roverlab_stream("imu");
  H5Dclose(f.dataset("streams/imu/time", time));
  hid_t d = f.dataset("streams/imu/channels/x", x);
  if (!unit.empty()) RawHdf5::string_attribute(d, "unit", unit);
  H5Dclose(d);
}

void write_log_with_time(const std::string& path, const std::vector<double>& time) {
  write_raw_log(path, time, std::vector<double>(time.size(), 1.0));
}

}  // namespace

TEST(Cli, InfoListsPathfinderStreamsWithUnitsRatesAndDurations) {
  const CommandResult r = run_roverlab("info " + quote(kPathfinder) + " --mapping wvu_pathfinder");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("stream imu: 17611 samples, 250.0 Hz"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("stream wheels: 705 samples, 10.0 Hz"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[m/s^2]"), std::string::npos);
  EXPECT_NE(r.out.find("[rad/s]"), std::string::npos);

  const CommandResult j = run_roverlab("info " + quote(kPathfinder) + " -m wvu_pathfinder --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto doc = nlohmann::json::parse(j.out);
  const auto& streams = doc.at("streams");
  auto find = [&](const std::string& name) {
    return *std::find_if(streams.begin(), streams.end(), [&](const auto& s) { return s.at("name") == name; });
  };
  EXPECT_EQ(find("imu").at("samples"), 17611);
  EXPECT_NEAR(find("imu").at("rate_hz").get<double>(), 250.0, 1.0);
  EXPECT_NEAR(find("imu").at("duration_s").get<double>(), 70.44, 0.01);
  EXPECT_EQ(find("wheels").at("samples"), 705);
  EXPECT_NEAR(find("wheels").at("rate_hz").get<double>(), 10.0, 0.05);
  EXPECT_EQ(find("imu").at("channels").at(0).at("unit"), "m/s^2");
}

TEST(Cli, ConvertThenInfoShowsTheSameStreamsAndIdenticalValues) {
  TempDir dir;
  const std::string out = dir.file("test17run.h5");
  const CommandResult c =
      run_roverlab("convert " + quote(kPathfinder) + " " + quote(out) + " --mapping wvu_pathfinder");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_EQ(files_in(dir.path()), 1u);

  const CommandResult a = run_roverlab("info " + quote(kPathfinder) + " -m wvu_pathfinder --json");
  const CommandResult b = run_roverlab("info " + quote(out) + " --json");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  EXPECT_EQ(ja.at("streams"), jb.at("streams"));  // names, counts, rates, units, min, max
  EXPECT_EQ(ja.at("metadata"), jb.at("metadata"));

  // And every value bit for bit.
  io::LoadOptions options;
  options.mapping = io::load_mapping(std::string(ROVERLAB_RESOURCES_DIR) + "/mappings/wvu_pathfinder.json");
  const log::Log original = io::load_log(kPathfinder, options).log;
  const log::Log converted = io::load_log(out).log;
  ASSERT_EQ(original.streams().size(), converted.streams().size());
  for (std::size_t s = 0; s < original.streams().size(); ++s) {
    const auto& so = original.streams()[s];
    const auto& sc = converted.streams()[s];
    EXPECT_EQ(so.name(), sc.name());
    EXPECT_EQ(so.time(), sc.time());
    ASSERT_EQ(so.channels().size(), sc.channels().size());
    for (std::size_t k = 0; k < so.channels().size(); ++k) {
      EXPECT_EQ(so.channels()[k].values, sc.channels()[k].values) << so.channels()[k].name;
      EXPECT_EQ(so.channels()[k].unit, sc.channels()[k].unit);
    }
  }
}

TEST(Cli, ConvertToCsvAndBack) {
  TempDir dir;
  write_text(dir.file("in.csv"), "time [s],pitch [deg]\n0,0\n1,90\n");
  ASSERT_EQ(run_roverlab("convert " + quote(dir.file("in.csv")) + " " + quote(dir.file("a.h5"))).exit_code, 0);
  const CommandResult r = run_roverlab("convert " + quote(dir.file("a.h5")) + " " + quote(dir.file("b.csv")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_text(dir.file("b.csv")), "time [s],pitch [rad]\n0,0\n1,1.5707963267948966\n");
}

TEST(Cli, UsageErrorsExitTwoAndHelpExitsZero) {
  EXPECT_EQ(run_roverlab("").exit_code, 2);
  EXPECT_EQ(run_roverlab("frobnicate").exit_code, 2);
  EXPECT_EQ(run_roverlab("info").exit_code, 2);
  EXPECT_EQ(run_roverlab("info x.h5 --no-such-option").exit_code, 2);
  EXPECT_EQ(run_roverlab("estimate ins-slip " + quote(kPathfinder) + " -m wvu_pathfinder --no-slip-band 0.5").exit_code,
            2);
  EXPECT_EQ(run_roverlab("convert " + quote(kPathfinder) + " out.txt -m wvu_pathfinder").exit_code, 2);
  for (const std::string cmd : {"", "info ", "convert ", "mappings "}) {
    const CommandResult r = run_roverlab(cmd + "--help");
    EXPECT_EQ(r.exit_code, 0) << cmd;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << cmd;
  }
  const CommandResult m = run_roverlab("mappings");
  EXPECT_EQ(m.exit_code, 0);
  EXPECT_NE(m.out.find("wvu_pathfinder"), std::string::npos);
}

// --- bad input: one test per case of the foundation issue -----------------

TEST(CliBadInput, MissingFile) {
  TempDir dir;
  expect_bad_input(dir.file("nope.h5"), "no such file");
}

TEST(CliBadInput, NotAnHdf5File) {
  TempDir dir;
  write_text(dir.file("log.h5"), "this is not HDF5\n");
  expect_bad_input(dir.file("log.h5"), "not an HDF5 file");
}

TEST(CliBadInput, TruncatedHdf5File) {
  TempDir dir;
  const std::string good = dir.file("good.h5");
  ASSERT_EQ(run_roverlab("convert " + quote(kPathfinder) + " " + quote(good) + " -m wvu_pathfinder").exit_code, 0);
  const auto size = fs::file_size(good);
  const std::string cut = dir.file("cut.h5");
  fs::copy_file(good, cut);
  fs::resize_file(cut, size / 2);
  expect_bad_input(cut, "truncated");
}

TEST(CliBadInput, TruncatedMatFile) {
  TempDir dir;
  const std::string cut = dir.file("cut.mat");
  fs::copy_file(kPathfinder, cut);
  fs::resize_file(cut, fs::file_size(kPathfinder) / 3);
  expect_bad_input(cut, "truncated", "-m wvu_pathfinder");
}

TEST(CliBadInput, MatFileOlderThanV73) {
  TempDir dir;
  std::string header(116, ' ');
  header.replace(0, 63, "MATLAB 5.0 MAT-file, Platform: GLNXA64, Created on: Mon Jan  1");
  write_text(dir.file("old.mat"), header + std::string(12, '\0') + "IM" + std::string(200, 'x'));
  expect_bad_input(dir.file("old.mat"), "older than v7.3", "-m wvu_pathfinder");
  expect_bad_input(dir.file("old.mat"), "older than v7.3");
}

TEST(CliBadInput, MatFileWithoutMapping) {
  const CommandResult r = run_roverlab("info " + quote(kPathfinder));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("--mapping"), std::string::npos) << r.err;
}

TEST(CliBadInput, MappingNamesAVariableTheFileLacks) {
  TempDir dir;
  std::string mapping = read_text(std::string(ROVERLAB_RESOURCES_DIR) + "/mappings/wvu_pathfinder.json");
  mapping.replace(mapping.find("\"Gz\""), 4, "\"GyroZ\"");
  write_text(dir.file("m.json"), mapping);
  expect_bad_input(kPathfinder, "'GyroZ'", "--mapping " + quote(dir.file("m.json")));
}

TEST(CliBadInput, UnknownMapping) {
  const CommandResult r = run_roverlab("info " + quote(kPathfinder) + " -m no_such_rover");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("no_such_rover"), std::string::npos);
  EXPECT_EQ(count_lines(r.err), 1u);
}

TEST(CliBadInput, ChannelLengthDiffersFromTimeBase) {
  TempDir dir;
  std::string mapping = read_text(std::string(ROVERLAB_RESOURCES_DIR) + "/mappings/wvu_pathfinder.json");
  // Put a 705-sample wheel variable into the 17611-sample IMU stream.
  mapping.replace(mapping.find("\"Gz\""), 4, "\"frontRightPos\"");
  write_text(dir.file("m.json"), mapping);
  expect_bad_input(kPathfinder, "705 samples but the time base has 17611", "--mapping " + quote(dir.file("m.json")));
  // The same in a RoverLab HDF5 log.
  write_raw_log(dir.file("short.h5"), {0.0, 1.0, 2.0}, {1.0, 2.0});
  expect_bad_input(dir.file("short.h5"), "2 samples but the time base has 3");
}

TEST(CliBadInput, NaNTime) {
  TempDir dir;
  write_text(dir.file("nan.csv"), "time [s],x [m]\n0,1\nnan,2\n2,3\n");
  expect_bad_input(dir.file("nan.csv"), "line 3: time is 'nan'");
  write_log_with_time(dir.file("nan.h5"), {0.0, std::nan(""), 2.0});
  expect_bad_input(dir.file("nan.h5"), "time is not finite at sample 1");
}

TEST(CliBadInput, NonIncreasingTime) {
  TempDir dir;
  write_text(dir.file("back.csv"), "time [s],x [m]\n0,1\n1,2\n1,3\n");
  expect_bad_input(dir.file("back.csv"), "line 4: time 1 s is not after");
  write_log_with_time(dir.file("back.h5"), {0.0, 1.0, 0.5});
  expect_bad_input(dir.file("back.h5"), "not strictly increasing at sample 2");
}

TEST(CliBadInput, CsvRaggedRow) {
  TempDir dir;
  write_text(dir.file("ragged.csv"), "time [s],x [m],y [m]\n0,1,2\n1,2\n");
  expect_bad_input(dir.file("ragged.csv"), "line 3: 2 cells but the header has 3");
}

TEST(CliBadInput, CsvUnparsableNumber) {
  TempDir dir;
  write_text(dir.file("bad.csv"), "time [s],x [m]\n0,1\n1,1.2.3\n");
  expect_bad_input(dir.file("bad.csv"), "line 3, column 'x': cannot parse '1.2.3'");
}

TEST(CliBadInput, UnknownUnitString) {
  TempDir dir;
  write_text(dir.file("units.csv"), "time [s],x [furlong]\n0,1\n");
  expect_bad_input(dir.file("units.csv"), "unknown unit 'furlong'");
  write_raw_log(dir.file("units.h5"), {0.0, 1.0}, {1.0, 2.0}, "cubits");
  expect_bad_input(dir.file("units.h5"), "unknown unit 'cubits'");
}

TEST(CliBadInput, UnwritableOutputIsBadInputNotACrash) {
  TempDir dir;
  const CommandResult r = run_roverlab("convert " + quote(kPathfinder) + " " +
                                       quote(dir.file("no/such/folder/out.h5")) + " -m wvu_pathfinder");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
}

// --- terramechanics and discrepancy ----------------------------------------

TEST(CliTerramechanics, EvaluatePrintsOneRowPerLoadAndSlip) {
  const CommandResult r =
      run_roverlab("terramechanics --soil ding_tyii --radius 0.075 --width 0.07 --load 10,50 --slip -0.5,0,0.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("load_N,slip,drawbar_pull_N,resistive_torque_Nm,sinkage_m,entry_angle_rad", 0), 0u);
  EXPECT_EQ(count_lines(r.out), 7u);
  const CommandResult j = run_roverlab(
      "terramechanics --soil ding_tyii --radius 0.075 --width 0.07 --load 50 --slip 0.2 --format json "
      "--integration riemann --model wong+slip-sinkage --slip-sinkage-n1 0.3");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc.at("rows").size(), 1u);
  EXPECT_GT(doc.at("rows")[0].at("drawbar_pull_N").get<double>(), 0.0);  // past the zero crossing at s = 0.2
  // A load the soil cannot carry is reported, not extrapolated.
  const CommandResult u =
      run_roverlab("terramechanics --soil lunar_nominal --radius 0.075 --width 0.07 --load 600 --slip 0.5");
  EXPECT_EQ(u.exit_code, 0);
  EXPECT_NE(u.out.find(",,,,unsupported_load"), std::string::npos) << u.out;
}

TEST(CliTerramechanics, UsageAndInputErrors) {
  EXPECT_EQ(run_roverlab("terramechanics --radius 0.075 --width 0.07 --load 1 --slip 0").exit_code, 2);
  EXPECT_EQ(run_roverlab("terramechanics --soil ding_tyii --radius -1 --width 0.07 --load 1 --slip 0").exit_code, 2);
  EXPECT_EQ(
      run_roverlab("terramechanics --soil ding_tyii --radius 0.075 --width 0.07 --load 1 --slip 0 --model wong+magic")
          .exit_code,
      2);
  const CommandResult r = run_roverlab("terramechanics --soil nowhere --radius 0.075 --width 0.07 --load 1 --slip 0");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("no soil of that name"), std::string::npos) << r.err;
  EXPECT_EQ(run_roverlab("terramechanics --help").exit_code, 0);
  EXPECT_EQ(run_roverlab("terramechanics fit --help").exit_code, 0);
  EXPECT_EQ(run_roverlab("discrepancy single-wheel --help").exit_code, 0);
}

// Issue 33 item 4: --model wong+shear-peak with its two parameters gives the
// value of tests/data/single_wheel/shear_peak_reference.py (80 N, s = 0.3,
// K_r = 0.6, K_w = 8 mm: DP 32.3899829 N); K_r outside (0, 1] is refused.
TEST(CliTerramechanics, ShearPeakTakesItsResidualRatioAndPeakDisplacement) {
  const std::string wheel =
      "terramechanics --soil ding_tyii --radius 0.15735 --width 0.165 --load 80 --slip 0.3 --integration riemann "
      "--format json --model wong+shear-peak --shear-peak-displacement 0.008 --shear-residual-ratio ";
  const CommandResult r = run_roverlab(wheel + "0.6");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out).at("rows")[0].at("drawbar_pull_N").get<double>(), 32.3899829, 1e-6);
  const CommandResult bad = run_roverlab(wheel + "1.5");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--shear-residual-ratio"), std::string::npos) << bad.err;
}

TEST(CliTerramechanics, SlipAngleAddsTheLateralForce) {
  const std::string wheel = "terramechanics --soil ding_tyii --radius 0.075 --width 0.07 --load 50 --slip 0.2";
  const CommandResult r = run_roverlab(wheel + " --slip-angle -20,0,20");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("load_N,slip,slip_angle_deg,drawbar_pull_N,lateral_force_N,resistive_torque_Nm,sinkage_m", 0),
            0u)
      << r.out;
  EXPECT_EQ(count_lines(r.out), 4u);
  const CommandResult j = run_roverlab(wheel + " --slip-angle 0,30 --format json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto doc = nlohmann::json::parse(j.out);
  ASSERT_EQ(doc.at("rows").size(), 2u);
  EXPECT_EQ(doc.at("rows")[0].at("lateral_force_N").get<double>(), 0.0);
  EXPECT_LT(doc.at("rows")[1].at("lateral_force_N").get<double>(), -5.0);  // resists +y motion
  EXPECT_LT(doc.at("rows")[1].at("drawbar_pull_N").get<double>(), doc.at("rows")[0].at("drawbar_pull_N").get<double>());
  // Beta = 0 is the Wong-Reece row.
  const CommandResult plain = run_roverlab(wheel + " --format json");
  const auto plain_doc = nlohmann::json::parse(plain.out);
  EXPECT_NEAR(plain_doc.at("rows")[0].at("drawbar_pull_N").get<double>(),
              doc.at("rows")[0].at("drawbar_pull_N").get<double>(), 1e-6);
  // Bad values: one line naming the option, exit 2.
  for (const char* bad : {"nan", "95", "-90.5", "abc"}) {
    const CommandResult e = run_roverlab(wheel + " --slip-angle " + std::string(bad));
    EXPECT_EQ(e.exit_code, 2) << bad;
    // One error line naming the option (CLI11 adds its "Run with --help" hint).
    EXPECT_EQ(e.err.rfind("roverlab: --slip-angle: '" + std::string(bad) + "'", 0), 0u) << e.err;
  }
  const CommandResult bekker = run_roverlab(wheel + " --slip-angle 10 --model bekker");
  EXPECT_EQ(bekker.exit_code, 2);
  EXPECT_NE(bekker.err.find("--slip-angle"), std::string::npos) << bekker.err;
  EXPECT_EQ(run_roverlab(wheel + " --slip-angle 10 --lateral-shear sideways").exit_code, 2);
}

// Issue 33 item 2: F_y(W, s, beta) as one Eq. 2.28 surface per slip angle,
// fitted the way the DP surfaces are.
TEST(CliTerramechanics, SurfaceAtSlipAnglesFitsTheLateralForce) {
  const std::string grid =
      "terramechanics surface --soil ding_tyii --radius 0.075 --width 0.07 --load-max 200 "
      "--order 4 --grid 30 --json";
  const CommandResult r = run_roverlab(grid + " --slip-angle 0,20");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc.at("slip_angles").size(), 2u);
  const auto& zero = doc.at("slip_angles")[0];
  const auto& twenty = doc.at("slip_angles")[1];
  // At beta = 0: no lateral force, and the DP surface of the straight wheel.
  EXPECT_EQ(zero.at("lateral_force").at("max_abs_error").get<double>(), 0.0);
  for (const auto& c : zero.at("lateral_force").at("coefficients")) EXPECT_EQ(c.get<double>(), 0.0);
  const auto straight = nlohmann::json::parse(run_roverlab(grid).out);
  const auto& a = straight.at("drawbar_pull").at("coefficients");
  const auto& b = zero.at("drawbar_pull").at("coefficients");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i].get<double>(), b[i].get<double>(), 1e-6);
  // At 20 deg the F_y surface fits its grid to a small fraction of F_y and
  // gives the model's value: F_y(100 N, s = 0.5) from the coefficients.
  const auto& fy = twenty.at("lateral_force");
  EXPECT_LT(fy.at("mean_abs_error").get<double>(), 0.2);
  double value = 0.0;
  const auto coefficients = fy.at("coefficients").get<std::vector<double>>();
  for (std::size_t i = 0; i < coefficients.size(); ++i) {
    const auto [k, l] = roverlab::terramechanics::PolynomialSurface::exponents(i);
    value += coefficients[i] * std::pow(0.5, k) * std::pow(100.0, l);
  }
  const auto row = nlohmann::json::parse(
      run_roverlab("terramechanics --soil ding_tyii --radius 0.075 --width 0.07 --load 100 --slip 0.5 "
                   "--slip-angle 20 --format json")
          .out);
  const double model = row.at("rows")[0].at("lateral_force_N").get<double>();
  EXPECT_LT(model, -10.0);
  EXPECT_NEAR(value, model, 0.5);
  EXPECT_EQ(run_roverlab(grid + " --slip-angle 10 --model bekker").exit_code, 2);
}

TEST(CliTerramechanics, FitRecoversTheSurfaceOfItsOwnGrid) {
  TempDir dir;
  const std::string points = dir.file("grid.csv");
  const CommandResult g = run_roverlab(
      "terramechanics --soil dry_sand --radius 0.075 --width 0.07 --load 10,30,50,70,90,110 "
      "--slip 0,0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.9,1");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  write_text(points, g.out);
  const CommandResult f = run_roverlab("terramechanics fit " + quote(points) + " --json --grid 5");
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const auto doc = nlohmann::json::parse(f.out);
  const auto& dp = doc.at("drawbar_pull_N");
  EXPECT_EQ(dp.at("points"), 66);
  EXPECT_LT(dp.at("rmse").get<double>(), 0.5);
  EXPECT_GE(dp.at("order").get<int>(), 3);
  EXPECT_EQ(dp.at("occupancy").at("counts").size(), 25u);
  EXPECT_DOUBLE_EQ(dp.at("occupancy").at("coverage").get<double>(), 1.0);
  EXPECT_TRUE(doc.contains("resistive_torque_Nm"));
}

// Issue 33 item 2: points at slip angles (the slip-angle rows of
// `terramechanics --slip-angle`) are fitted per slip angle, F_y included.
TEST(CliTerramechanics, FitAtSlipAnglesFitsEachAngleAndTheLateralForce) {
  TempDir dir;
  const std::string points = dir.file("steer.csv");
  const CommandResult g = run_roverlab(
      "terramechanics --soil dry_sand --radius 0.075 --width 0.07 --load 10,30,50,70,90,110 "
      "--slip 0,0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.9 --slip-angle 0,30");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  write_text(points, g.out);
  const CommandResult f = run_roverlab("terramechanics fit " + quote(points) + " --json --order 4");
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const auto doc = nlohmann::json::parse(f.out);
  ASSERT_EQ(doc.at("slip_angles").size(), 2u);
  const auto& zero = doc.at("slip_angles")[0];
  const auto& thirty = doc.at("slip_angles")[1];
  EXPECT_EQ(zero.at("slip_angle_deg"), 0.0);
  EXPECT_EQ(zero.at("drawbar_pull_N").at("points"), 60);
  EXPECT_EQ(zero.at("lateral_force_N").at("max_abs_error").get<double>(), 0.0);
  EXPECT_EQ(thirty.at("lateral_force_N").at("points"), 60);
  EXPECT_LT(thirty.at("lateral_force_N").at("rmse").get<double>(), 0.5);
  EXPECT_NE(thirty.at("lateral_force_N").at("coefficients")[0].get<double>(), 0.0);
  // Without the column the document is as before (one surface per quantity).
  const CommandResult plain =
      run_roverlab("terramechanics --soil dry_sand --radius 0.075 --width 0.07 --load 10,50,90 --slip 0,0.3,0.6,0.9");
  write_text(dir.file("plain.csv"), plain.out);
  const auto p =
      nlohmann::json::parse(run_roverlab("terramechanics fit " + quote(dir.file("plain.csv")) + " --json").out);
  EXPECT_FALSE(p.contains("slip_angles"));
  EXPECT_TRUE(p.contains("drawbar_pull_N"));
}

TEST(CliDiscrepancy, SingleWheelOnTheDing2011File) {
  const std::string file = std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv";
  const CommandResult r = run_roverlab("discrepancy single-wheel " + quote(file) + " --soil ding_tyii --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc.at("points"), 12);
  EXPECT_EQ(doc.at("measurements"), 34);  // two cells of the file are empty
  const auto& base = doc.at("baseline").at("residuals");
  // Measured sinkage grows with slip much faster than the static model's.
  EXPECT_LT(base.at("sinkage").at("slope_vs_slip").get<double>(), -0.01);
  EXPECT_LT(base.at("sinkage").at("t_slip").get<double>(), -3.0);
  EXPECT_EQ(doc.at("candidates").size(), 12u);  // the lateral two and RFT's two not applicable here
  EXPECT_EQ(doc.at("baseline_model"), "Wong-Reece");
  EXPECT_FALSE(doc.at("verdict").get<std::string>().empty());
  const CommandResult text = run_roverlab("discrepancy single-wheel " + quote(file) + " --soil ding_tyii");
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("baseline residuals"), std::string::npos);
  // A physically impossible row is left out with a warning naming its line.
  TempDir dir;
  const std::string steer = dir.file("steer.csv");
  std::string rows = "radius_m,width_m,load_N,slip,slip_angle_deg,drawbar_pull_N,lateral_force_N,sinkage_m\n";
  for (int k = 0; k < 8; ++k) rows += "0.15735,0.165,80," + std::to_string(0.1 * k) + ",0,5,,0.02\n";
  rows += "0.15735,0.165,80,0.3,0,5,,0.5\n";  // line 10: sinkage beyond the diameter
  write_text(steer, rows);
  const CommandResult w = run_roverlab("discrepancy single-wheel " + quote(steer) + " --soil ding_tyii --json");
  EXPECT_EQ(w.exit_code, 0) << w.err;
  EXPECT_NE(w.err.find("line 10"), std::string::npos) << w.err;
  EXPECT_EQ(nlohmann::json::parse(w.out).at("points"), 8);
  // Points at a slip angle (issue 33 item 3): the slip-angle model is the
  // baseline and the lateral force one of the quantities.
  write_text(steer, rows + "0.15735,0.165,80,0.3,20,5,-12,0.03\n");
  const CommandResult steered =
      run_roverlab("discrepancy single-wheel " + quote(steer) + " --soil ding_tyii --family wong --json");
  EXPECT_EQ(steered.exit_code, 0) << steered.err;
  EXPECT_EQ(count_lines(steered.err), 1u) << steered.err;  // the warning
  const auto sdoc = nlohmann::json::parse(steered.out);
  EXPECT_EQ(sdoc.at("baseline_model"), "Ishigami (slip angle)");
  EXPECT_EQ(sdoc.at("baseline").at("residuals").at("lateral_force").at("count"), 1);
  // Bad input: a file without the measured columns.
  write_text(dir.file("bad.csv"), "radius_m,width_m,load_N,slip\n0.1,0.1,80,0.2\n");
  const CommandResult bad =
      run_roverlab("discrepancy single-wheel " + quote(dir.file("bad.csv")) + " --soil ding_tyii");
  EXPECT_EQ(bad.exit_code, 3);
  EXPECT_EQ(count_lines(bad.err), 1u);
  EXPECT_NE(bad.err.find("bad.csv"), std::string::npos);
}

// --- seed 002: INS slip detection and the odometry discrepancy study -------

TEST(CliInsSlip, OnThePathfinderLogThePseudoMeasurementInsBeatsPureInsAndWheelOdometry) {
  const CommandResult full = run_roverlab("estimate ins-slip " + quote(kPathfinder) + " -m wvu_pathfinder --json");
  ASSERT_EQ(full.exit_code, 0) << full.err;
  const CommandResult pure = run_roverlab("estimate ins-slip " + quote(kPathfinder) +
                                          " -m wvu_pathfinder --no-zupt --no-zaru --no-nhc --no-odometry-aiding "
                                          "--no-smoother --json");
  ASSERT_EQ(pure.exit_code, 0) << pure.err;
  const CommandResult pseudo =
      run_roverlab("estimate ins-slip " + quote(kPathfinder) + " -m wvu_pathfinder --no-odometry-aiding --json");
  ASSERT_EQ(pseudo.exit_code, 0) << pseudo.err;
  const auto f = nlohmann::json::parse(full.out), p = nlohmann::json::parse(pure.out);
  const auto q = nlohmann::json::parse(pseudo.out);
  const double ins = f.at("ins").at("final_position_error_m").get<double>();
  const double odometry = f.at("wheel_odometry").at("final_position_error_m").get<double>();
  const double inertial = p.at("ins").at("final_position_error_m").get<double>();
  const double pseudo_only = q.at("ins").at("final_position_error_m").get<double>();
  EXPECT_NEAR(f.at("distance_m").get<double>(), 34.3, 0.5);
  // The initial heading comes from aligning a first pass to the GPS track; the
  // wheel odometry starts from the same pose and drifts by its own heading.
  EXPECT_EQ(f.at("initial_heading").at("method"), "aligned");
  EXPECT_LT(f.at("initial_heading").at("sigma_rad").get<double>(), 0.02);
  EXPECT_GT(odometry, 5.0);
  EXPECT_GT(inertial, 100.0);              // 70 s of free inertial drift
  EXPECT_LT(pseudo_only, 0.6 * odometry);  // ZUPT, ZARU and NHC alone
  EXPECT_LT(ins, 0.3 * odometry);          // plus gated wheel-speed aiding
  EXPECT_EQ(f.at("slip_confusion").at("counts").size(), 5u);
  // Issue 14 item 3: from a wrong heading (given: north, where the rover
  // drove 5 deg east of it) the error as it is grows, the error after the
  // best rigid alignment over the first stretch stays the aligned run's.
  const CommandResult north =
      run_roverlab("estimate ins-slip " + quote(kPathfinder) + " -m wvu_pathfinder --initial-heading 0 --json");
  ASSERT_EQ(north.exit_code, 0) << north.err;
  const auto n = nlohmann::json::parse(north.out);
  EXPECT_EQ(n.at("initial_heading").at("method"), "given");
  EXPECT_GT(n.at("ins").at("position_rmse_m").get<double>(), 2.0 * f.at("ins").at("position_rmse_m").get<double>());
  EXPECT_NEAR(n.at("ins").at("aligned_position_rmse_m").get<double>(),
              f.at("ins").at("aligned_position_rmse_m").get<double>(), 0.05);
  EXPECT_NEAR(n.at("ins").at("alignment_rotation_rad").get<double>(),
              f.at("initial_heading").at("heading_rad").get<double>(), 0.01);
  EXPECT_LT(f.at("ins").at("aligned_position_rmse_m").get<double>(),
            f.at("wheel_odometry").at("aligned_position_rmse_m").get<double>());
}

TEST(CliInsSlip, WritesEstimateStreamsAndReadsItsOwnSimulatedLogs) {
  TempDir dir;
  const std::string sim = dir.file("sim.h5"), out = dir.file("est.h5");
  ASSERT_EQ(run_roverlab("scenario skid-steer-slip --seed 2 -o " + quote(sim)).exit_code, 0);
  const CommandResult r = run_roverlab("estimate ins-slip " + quote(sim) + " -o " + quote(out) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  const auto& diag = doc.at("slip_confusion").at("column_normalised");
  EXPECT_GE(diag.at(0).at(0).get<double>(), 0.983);
  EXPECT_GE(diag.at(1).at(1).get<double>(), 0.96);
  const log::Log lg = io::read_hdf5_log(out);
  for (const char* s : {"imu", "wheels", "gps", "estimate/ins/pose", "estimate/ins/velocity", "estimate/ins/bias",
                        "estimate/ins/standstill", "estimate/ins/slip", "estimate/odometry/pose"}) {
    EXPECT_NE(lg.find_stream(s), nullptr) << s;
  }
  const auto& slip = lg.stream("estimate/ins/slip");
  EXPECT_NE(slip.find_channel("slip_class"), nullptr);
  EXPECT_NE(slip.find_channel("reference_slip"), nullptr);
}

// Issue 14: loops with turns in place, starting south-east, 3 m GPS noise.
TEST(CliInsSlip, LoopDriveWithTurnsInPlaceAndNoisyGps) {
  TempDir dir;
  const std::string sim = dir.file("loops.h5");
  ASSERT_EQ(run_roverlab("scenario skid-steer-slip --drive loops --seed 7 -o " + quote(sim)).exit_code, 0);
  const CommandResult r = run_roverlab("estimate ins-slip " + quote(sim) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  const auto& h = doc.at("initial_heading");
  EXPECT_EQ(h.at("method"), "aligned");
  EXPECT_NEAR(h.at("heading_rad").get<double>(), 2.3, 3.0 * h.at("sigma_rad").get<double>());
  EXPECT_NEAR(doc.at("gps_reference").at("fix_sigma_m").get<double>(), 3.0, 0.3);
  EXPECT_GE(doc.at("slip_confusion").at("accuracy").get<double>(), 0.9);
  EXPECT_EQ(run_roverlab("scenario skid-steer-slip --drive spiral -o " + quote(dir.file("x.h5"))).exit_code, 2);
}

// --imu-mounting: the NHC and wheel speed then hold in chassis axes; the
// angles are stated in the JSON and the text, and change the detector.
TEST(CliInsSlip, ImuMountingIsStatedAndUsed) {
  const std::string cmd = "estimate ins-slip " + quote(kPathfinder) + " -m wvu_pathfinder";
  const CommandResult plain = run_roverlab(cmd + " --json");
  const CommandResult mounted = run_roverlab(cmd + " --imu-mounting 0,-2,0 --json");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(mounted.exit_code, 0) << mounted.err;
  const auto a = nlohmann::json::parse(plain.out), b = nlohmann::json::parse(mounted.out);
  EXPECT_EQ(a.at("updates").at("imu_mounting_deg"), nlohmann::json::array({0.0, 0.0, 0.0}));
  EXPECT_NEAR(b.at("updates").at("imu_mounting_deg").at(1).get<double>(), -2.0, 1e-12);
  EXPECT_NE(a.at("slip_confusion").at("accuracy").get<double>(), b.at("slip_confusion").at("accuracy").get<double>());
  const CommandResult text = run_roverlab(cmd + " --imu-mounting 0,-2,0");
  EXPECT_NE(text.out.find("IMU mounting against the chassis: roll 0.00, pitch -2.00"), std::string::npos) << text.out;
}

TEST(CliInsSlip, BadInputAndUsage) {
  TempDir dir;
  // A log without an imu stream.
  write_raw_log(dir.file("noimu.h5"), {0.0, 1.0, 2.0}, {1.0, 2.0, 3.0});
  {
    RawHdf5 f(dir.file("wheels_only.h5"));
    f.roverlab_header(1);
    f.roverlab_stream("wheels");
    H5Dclose(f.dataset("streams/wheels/time", std::vector<double>{0.0, 0.1, 0.2}));
    hid_t angle = f.dataset("streams/wheels/channels/angle_FL", std::vector<double>{0.0, 0.1, 0.2});
    RawHdf5::string_attribute(angle, "unit", "rad");
    H5Dclose(angle);
  }
  for (const std::string name : {"noimu.h5", "wheels_only.h5", "missing.h5"}) {
    const CommandResult r =
        run_roverlab("estimate ins-slip " + quote(dir.file(name)) + " -o " + quote(dir.file("o.h5")));
    EXPECT_EQ(r.exit_code, 3) << name << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir.file("o.h5")));
  }
  // --imu-mounting takes three angles within +-30 deg.
  for (const std::string bad : {"0,2", "0,45,0", "0,nan,0"}) {
    const CommandResult r = run_roverlab("estimate ins-slip " + quote(kPathfinder) +
                                         " -m wvu_pathfinder --imu-mounting " + bad + " -o " + quote(dir.file("o.h5")));
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("imu-mounting"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir.file("o.h5")));
  }
  EXPECT_EQ(run_roverlab("scenario skid-steer-slip --effect wheel-size=2 -o " + quote(dir.file("s.h5"))).exit_code, 2);
  EXPECT_EQ(run_roverlab("scenario skid-steer-slip --effect radius-scale=big -o " + quote(dir.file("s.h5"))).exit_code,
            2);
  EXPECT_FALSE(fs::exists(dir.file("s.h5")));
}

TEST(CliDiscrepancy, OdometryOnThePathfinderLogNamesACauseAndItsGain) {
  const CommandResult r = run_roverlab("discrepancy odometry " + quote(kPathfinder) + " -m wvu_pathfinder --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_FALSE(doc.at("cause").is_null()) << doc.at("verdict");
  EXPECT_EQ(doc.at("candidates").size(), 5u);
  double best = 1e9;
  for (const auto& c : doc.at("candidates")) {
    if (c.at("name") == doc.at("cause")) best = c.at("held_out_rmse_m").get<double>();
  }
  // The named correction at least halves the held-out error of the nominal model.
  EXPECT_LT(best, 0.5 * doc.at("baseline").at("held_out_rmse_m").get<double>());
}

TEST(CliDiscrepancy, OdometryFindsAHiddenEffectInASimulatedLog) {
  TempDir dir;
  const std::string sim = dir.file("sim.h5");
  ASSERT_EQ(run_roverlab("scenario skid-steer-slip --seed 9 --effect slip=0 --effect right-radius-scale=1.03 -o " +
                         quote(sim))
                .exit_code,
            0);
  const CommandResult r = run_roverlab("discrepancy odometry " + quote(sim) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc.at("cause"), "per-side scale") << doc.at("verdict");
}

// --- seed 000: contact-angle estimation ------------------------------------

TEST(CliContactAngle, ScenarioThenEstimatePrintsTheErrorTable) {
  TempDir dir;
  const std::string sim = dir.file("fl.h5"), out = dir.file("est.h5");
  ASSERT_EQ(run_roverlab("scenario fl-bogie-rotation --rate 100 -o " + quote(sim)).exit_code, 0);
  const CommandResult r = run_roverlab("estimate contact-angle " + quote(sim) +
                                       " --model c --reset-cross-covariance -o " + quote(out) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc.at("rover"), "exomars_bb2");
  EXPECT_EQ(doc.at("rms").at("contact_angle_deg").size(), 6u);
  EXPECT_LT(doc.at("rms").at("velocity_mps").at(0).get<double>(), 0.01);
  // Unmoved bogies: contact angles of MR and FR stay near zero.
  EXPECT_LT(doc.at("rms").at("contact_angle_deg").at(5).get<double>(), 3.0);
  const log::Log lg = io::read_hdf5_log(out);
  EXPECT_NE(lg.find_stream("estimate/contact/wheels"), nullptr);
  EXPECT_NE(lg.stream("estimate/contact/wheels").find_channel("contact_angle_FL"), nullptr);
  const CommandResult text = run_roverlab("estimate contact-angle " + quote(sim) + " --model c");
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("Tables 6.2-6.5"), std::string::npos);
  // --model auto (the default): three candidates, the choice and its evidence, in JSON and in words.
  const CommandResult automatic =
      run_roverlab("estimate contact-angle " + quote(sim) + " --reset-cross-covariance --json");
  ASSERT_EQ(automatic.exit_code, 0) << automatic.err;
  const auto chosen = nlohmann::json::parse(automatic.out);
  const auto& selection = chosen.at("model_selection");
  ASSERT_EQ(selection.at("candidates").size(), 3u);
  EXPECT_EQ(chosen.at("model"), selection.at("chosen"));
  for (const auto& c : selection.at("candidates")) {
    EXPECT_GT(c.at("updates").get<double>(), 1000.0);
    EXPECT_GT(c.at("effective_dof").get<double>(), 0.0);
  }
  const CommandResult words = run_roverlab("estimate contact-angle " + quote(sim) + " --reset-cross-covariance");
  EXPECT_NE(words.out.find("model auto: model " + selection.at("chosen").get<std::string>()), std::string::npos)
      << words.out;
  // A model set by hand that the data reject says so.
  const CommandResult smooth =
      run_roverlab("estimate contact-angle " + quote(sim) + " --model smooth --reset-cross-covariance --json");
  ASSERT_EQ(smooth.exit_code, 0) << smooth.err;
  EXPECT_FALSE(nlohmann::json::parse(smooth.out).at("model_evidence").at("consistent").get<bool>());
  // Smoothing the run without the reset is allowed but said to be unreliable; with it (the
  // default, as in the GUI and the report), nothing is said, and the settings line names both.
  const std::string warning = "warning: smoothed without --reset-cross-covariance";
  const CommandResult bare =
      run_roverlab("estimate contact-angle " + quote(sim) + " --model c --no-reset-cross-covariance");
  ASSERT_EQ(bare.exit_code, 0) << bare.err;
  EXPECT_NE(bare.out.find(warning), std::string::npos) << bare.out;
  const CommandResult reset = run_roverlab("estimate contact-angle " + quote(sim) + " --model c");
  ASSERT_EQ(reset.exit_code, 0) << reset.err;
  EXPECT_EQ(reset.out.find(warning), std::string::npos) << reset.out;
  EXPECT_NE(reset.out.find("settings: "), std::string::npos) << reset.out;
  EXPECT_NE(reset.out.find("reset_cross_covariance true"), std::string::npos) << reset.out;
  EXPECT_NE(reset.out.find("smoother true"), std::string::npos) << reset.out;
  const CommandResult forward =
      run_roverlab("estimate contact-angle " + quote(sim) + " --model c --no-smoother --json");
  ASSERT_EQ(forward.exit_code, 0) << forward.err;
  EXPECT_EQ(nlohmann::json::parse(forward.out).at("configuration").at("smoother"), false);
}

TEST(CliContactAngle, BadInputAndUsage) {
  TempDir dir;
  EXPECT_EQ(run_roverlab("estimate contact-angle " + quote(kPathfinder) + " -m wvu_pathfinder --model c").exit_code, 3);
  EXPECT_EQ(run_roverlab("estimate contact-angle " + quote(kPathfinder) + " -m wvu_pathfinder --model z").exit_code, 2);
  EXPECT_EQ(run_roverlab("scenario fl-bogie-rotation --rover wvu_pathfinder -o " + quote(dir.file("x.h5"))).exit_code,
            3);
  EXPECT_EQ(run_roverlab("scenario fl-bogie-rotation --rate 0 -o " + quote(dir.file("x.h5"))).exit_code, 2);
  // The steering manoeuvre's options (issue 33): one line naming the option, no file.
  for (const auto& [options, named] :
       std::vector<std::pair<std::string, std::string>>{{"--turn-radius 0.5", "--turn-radius"},
                                                        {"--slip-angle 60", "--slip-angle"},
                                                        {"--slip-angle 5 --slip-angle-from 40", "--slip-angle-from"}}) {
    const CommandResult r = run_roverlab("scenario flat-turn " + options + " -o " + quote(dir.file("x.h5")));
    EXPECT_EQ(r.exit_code, 2) << options;
    EXPECT_EQ(count_lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(named + ":"), std::string::npos) << r.err;
  }
  EXPECT_EQ(files_in(dir.path()), 0u);
}

// --- seed 003: planar rocker-bogie simulation ------------------------------

TEST(CliSimulate, RockerBogieOnFlatGroundWritesTruthStreams) {
  TempDir dir;
  const std::string out = dir.file("rb.h5");
  const CommandResult r = run_roverlab("simulate flat_60s --duration 10 -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("stuck rover"), std::string::npos) << r.out;
  // Issue 30: Eq. 4.51's first 11 deg slope stops Kapvik on TYII; the run says so.
  const CommandResult stuck =
      run_roverlab("simulate " + quote(std::string(ROVERLAB_TEST_DATA) + "/scenarios/eq451_hills_200s.json") +
                   " --duration 30 -o " + quote(dir.file("roll.h5")));
  ASSERT_EQ(stuck.exit_code, 0) << stuck.err;
  EXPECT_NE(stuck.out.find("note: the rover drove"), std::string::npos) << stuck.out;
  EXPECT_NE(stuck.out.find("stuck rover"), std::string::npos) << stuck.out;
  const log::Log lg = io::read_hdf5_log(out);
  const auto& pose = lg.stream("truth/pose");
  EXPECT_EQ(pose.size(), 501u);  // 50 Hz
  EXPECT_GT(pose.channel("x").values.back(), pose.channel("x").values.front());
  EXPECT_NE(lg.stream("truth/wheels").find_channel("drawbar_pull_2"), nullptr);
  EXPECT_NE(lg.find_stream("commands"), nullptr);
  write_text(dir.file("bad.json"),
             "{\"format\": \"roverlab-scenario\", \"kind\": \"rocker-bogie\", \"rover\": \"exomars_bb2\", "
             "\"path\": \"flat\", \"soil\": \"ding_tyii\", \"duration_s\": 1}");
  EXPECT_EQ(run_roverlab("simulate " + quote(dir.file("bad.json")) + " -o " + quote(dir.file("x.h5"))).exit_code, 3);
  EXPECT_EQ(run_roverlab("simulate no_such_scenario -o " + quote(dir.file("x.h5"))).exit_code, 3);
  EXPECT_EQ(run_roverlab("simulate flat_60s --effect warp=9 -o " + quote(dir.file("x.h5"))).exit_code, 2);
  EXPECT_EQ(run_roverlab("simulate flat_60s --traction magic -o " + quote(dir.file("x.h5"))).exit_code, 2);
  // Effects land in the truth metadata only.
  ASSERT_EQ(run_roverlab("simulate flat_60s --duration 2 --effect gyro-bias=0.01 -o " + quote(out)).exit_code, 0);
  EXPECT_EQ(std::stod(io::read_hdf5_log(out).metadata.extra.at("truth/effect/gyro-bias")), 0.01);  // every digit
  fs::remove(dir.file("bad.json"));
  EXPECT_FALSE(fs::exists(dir.file("x.h5")));
}

// Issue 30 item 3: every bundled scenario does what its name says: its rover
// drives most of the distance its speed command asks for (rolling_200s, on
// Eq. 4.51's 0.12 m hills, drove 0.16 m of 4 m), and no run is called stuck.
TEST(CliSimulate, EveryBundledScenarioDrivesMostOfItsCommandedDistance) {
  TempDir dir;
  int scenarios = 0;
  for (const auto& entry : fs::directory_iterator(std::string(ROVERLAB_RESOURCES_DIR) + "/scenarios")) {
    if (entry.path().extension() != ".json") continue;
    ++scenarios;
    const std::string name = entry.path().stem().string();
    const CommandResult r = run_roverlab("simulate " + name + " -o " + quote(dir.file(name + ".h5")));
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_EQ(r.out.find("stuck rover"), std::string::npos) << r.out;
    const nlohmann::json sc = nlohmann::json::parse(read_text(entry.path().string()));
    const double commanded = sc.at("desired_speed_mps").get<double>() * sc.at("duration_s").get<double>();
    const log::Log lg = io::read_hdf5_log(dir.file(name + ".h5"));
    const std::vector<double>& x = lg.stream("truth/pose").channel("x").values;
    EXPECT_GT(x.back() - x.front(), 0.5 * commanded) << name;
    // ... and is still driving at the end (bump_crossing's rear wheel
    // stopped on its 23 deg bump at 95 of 120 s).
    const std::size_t tail = x.size() / 10;
    const double speed = sc.at("desired_speed_mps").get<double>();
    EXPECT_GT((x.back() - x[x.size() - 1 - tail]) / (0.1 * sc.at("duration_s").get<double>()), 0.25 * speed) << name;
  }
  EXPECT_GE(scenarios, 4);
}

// --- seed 003: net-traction estimation --------------------------------------

TEST(CliNetTraction, SimulateThenEstimatePrintsTheTablesAndTheSurfaceFits) {
  TempDir dir;
  const std::string sim = dir.file("roll.h5");
  ASSERT_EQ(run_roverlab("simulate rolling_200s --duration 60 --effect soil-strength=2.5 -o " + quote(sim)).exit_code,
            0);
  const CommandResult text = run_roverlab("estimate net-traction " + quote(sim) + " --order 2");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("Estimators 1 and 2 (two-axis)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("Estimators 1 and 3 (single-axis)"), std::string::npos);
  EXPECT_NE(text.out.find("true local"), std::string::npos);
  EXPECT_NE(text.out.find("s W"), std::string::npos);  // a Table 5.2 row, p_11
  const CommandResult js =
      run_roverlab("estimate net-traction " + quote(sim) + " --order 2 --json -o " + quote(dir.file("out.h5")));
  ASSERT_EQ(js.exit_code, 0) << js.err;
  const auto j = nlohmann::json::parse(js.out);
  EXPECT_EQ(j.at("force_sensors"), "two-axis");
  const auto& tau = j.at("estimators").at("two-axis").at("resistive_torque");
  EXPECT_EQ(tau.at("terms").size(), 6u);
  EXPECT_EQ(tau.at("coefficients").size(), 6u);
  EXPECT_EQ(tau.at("region").at("slip").size(), 2u);
  EXPECT_LT(tau.at("rms_vs_truth").at("rms_percent").get<double>(),
            15.0);  // 60 s: a small region; tests/core holds the 200 s figures
  EXPECT_LT(j.at("estimators").at("two-axis").at("tracking_rms").at("resistive_torque_Nm").at(0).get<double>(), 0.01);
  // Section 5.9, and the campaign's key metrics
  // point at the streams' estimator's figures; the points for the view.
  // 60 s is too short a path for the scan (0.6 m after its 20 s): it says so.
  EXPECT_TRUE(j.at("change_points").empty());
  EXPECT_NE(j.at("estimators").at("two-axis").at("change_detector").at("not_run").get<std::string>(), "");
  EXPECT_EQ(j.at("summary").at("change_count"), 0);
  EXPECT_EQ(j.at("summary").at("resistive_torque_rms_percent"), tau.at("rms_vs_truth").at("rms_percent"));
  EXPECT_GT(j.at("estimators").at("two-axis").at("estimated_points").at("wheel").size(), 100u);
  EXPECT_NE(text.out.find("soil change: not tested (the front wheel's points span"), std::string::npos);
  const log::Log out = io::read_hdf5_log(dir.file("out.h5"));
  EXPECT_NE(out.stream("estimate/net_traction/wheels").find_channel("drawbar_pull_sigma_3"), nullptr);
  EXPECT_NE(out.stream("estimate/net_traction/wheels").find_channel("path_x_1"), nullptr);
  EXPECT_NE(out.find_stream("estimate/net_traction/body"), nullptr);
  // Single-axis on request: only Estimator 3 beside Estimator 1.
  const CommandResult single =
      run_roverlab("estimate net-traction " + quote(sim) + " --force-sensors single-axis --json");
  ASSERT_EQ(single.exit_code, 0) << single.err;
  const nlohmann::json sj = nlohmann::json::parse(single.out);
  EXPECT_EQ(sj.at("estimators").count("two-axis"), 0u);
  // The bogie split is stated: by default auto, with its evidence (on this
  // short run the second pass's points fit worse: Eq. 5.66, one pass); on
  // request Eq. 5.66 alone or the two-pass shape split; they differ.
  const nlohmann::json& split = sj.at("estimators").at("single-axis").at("bogie_split");
  EXPECT_EQ(split.at("requested"), "auto");
  const nlohmann::json& evidence = split.at("auto_evidence");
  const bool shape_kept =
      evidence.at("second_pass_dp_fit_rmse_N").get<double>() <
      evidence.at("growth_limit").get<double>() * evidence.at("first_pass_dp_fit_rmse_N").get<double>();
  EXPECT_EQ(split.at("method"), shape_kept ? "shape" : "eq-5.66");
  EXPECT_EQ(evidence.at("kept"), split.at("method"));
  // The single-axis estimator's JSON with the split given.
  const auto single_axis_with = [&](const std::string& split) {
    const CommandResult r = run_roverlab("estimate net-traction " + quote(sim) +
                                         " --force-sensors single-axis --json --bogie-split " + split);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.exit_code == 0 ? nlohmann::json::parse(r.out).at("estimators").at("single-axis") : nlohmann::json();
  };
  const nlohmann::json pj = single_axis_with("eq-5.66");
  ASSERT_FALSE(pj.is_null());
  EXPECT_EQ(pj.at("bogie_split").at("method"), "eq-5.66");
  EXPECT_EQ(pj.at("bogie_split").at("passes"), 1);
  EXPECT_TRUE(pj.at("bogie_split").at("auto_evidence").is_null());
  const nlohmann::json hj = single_axis_with("shape");
  ASSERT_FALSE(hj.is_null());
  EXPECT_EQ(hj.at("bogie_split").at("method"), "shape");
  EXPECT_EQ(hj.at("bogie_split").at("passes"), 2);
  EXPECT_NE(hj.at("bogie_split").at("assumption").get<std::string>().find("contact angle"), std::string::npos);
  EXPECT_NE(hj.at("drawbar_pull").at("coefficients"), pj.at("drawbar_pull").at("coefficients"));
  EXPECT_NE(text.out.find("bogie split (section 5.6): "), std::string::npos);
  EXPECT_NE(text.out.find("chosen by auto: DP points' order-2 fit RMS"), std::string::npos);
}

TEST(CliNetTraction, BadInputAndUsage) {
  TempDir dir;
  const std::string sim = dir.file("flat.h5");
  ASSERT_EQ(run_roverlab("simulate flat_60s --duration 4 -o " + quote(sim)).exit_code, 0);
  log::Log lg = io::read_hdf5_log(sim);
  log::Log without;
  without.metadata = lg.metadata;
  for (const auto& s : lg.streams()) {
    if (s.name() != "forces") without.add_stream(s);
  }
  io::write_hdf5_log(without, dir.file("noforces.h5"));
  const CommandResult r = run_roverlab("estimate net-traction " + quote(dir.file("noforces.h5")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("no forces stream"), std::string::npos) << r.err;
  EXPECT_EQ(run_roverlab("estimate net-traction " + quote(sim) + " --order 9").exit_code, 2);
  EXPECT_EQ(run_roverlab("estimate net-traction " + quote(sim) + " --force-sensors three-axis").exit_code, 2);
  EXPECT_EQ(run_roverlab("estimate net-traction " + quote(sim) + " --bogie-split halves").exit_code, 2);
  // A rover that has not moved yet (0.3 s of spin-up) is refused in one line.
  ASSERT_EQ(run_roverlab("simulate flat_60s --duration 0.3 -o " + quote(dir.file("still.h5"))).exit_code, 0);
  const CommandResult still = run_roverlab("estimate net-traction " + quote(dir.file("still.h5")));
  EXPECT_EQ(still.exit_code, 3);
  EXPECT_NE(still.err.find("never moves"), std::string::npos) << still.err;
  // A skid-steer log is not a planar rocker-bogie.
  ASSERT_EQ(run_roverlab("scenario skid-steer-slip -o " + quote(dir.file("ss.h5"))).exit_code, 0);
  EXPECT_EQ(run_roverlab("estimate net-traction " + quote(dir.file("ss.h5"))).exit_code, 3);
}

// discrepancy rover (issue 13): a log it cannot study is one line, exit 3.
TEST(Cli, DiscrepancyRoverRefusesALogItCannotStudyInOneLine) {
  TempDir dir;
  const std::string shortlog = dir.file("short.h5"), flat = dir.file("flat.h5");
  ASSERT_EQ(run_roverlab("simulate flat_60s --duration 5 -o " + quote(shortlog)).exit_code, 0);
  ASSERT_EQ(run_roverlab("simulate flat_60s --duration 12 -o " + quote(flat)).exit_code, 0);
  struct Case {
    std::string args, problem;
  };
  const Case cases[] = {
      {"discrepancy rover " + quote(shortlog), "8 blocks"},  // too short for fit and test
      {"discrepancy rover " + quote(kPathfinder) + " -m wvu_pathfinder --scenario flat_60s", "rover"},  // another rover
      {"discrepancy rover " + quote(flat) + " --scenario nosuch", "nosuch"},
  };
  for (const auto& c : cases) {
    const CommandResult r = run_roverlab(c.args);
    EXPECT_EQ(r.exit_code, 3) << c.args << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1U) << r.err;
    EXPECT_NE(r.err.find(c.problem), std::string::npos) << r.err;
  }
  const CommandResult ok = run_roverlab("discrepancy rover " + quote(flat) + " --json");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("\"causes\": []"), std::string::npos) << ok.out.substr(0, 400);
}

// Issue 33, item 2: the traction-surface view draws F_y(W, s) of a steered
// single-wheel file at one slip angle (the largest by default); an angle the
// file does not have, or a file without lateral forces, is one line naming it.
TEST(Cli, RenderDrawsTheLateralForceSurfaceOfASteeredFile) {
  TempDir dir;
  const std::string steer = dir.file("steer.csv");
  std::string rows = "wheel,radius_m,width_m,load_N,slip,slip_angle_deg,drawbar_pull_N,lateral_force_N\n";
  for (const char* wheel : {"smooth", "grousered"}) {
    for (double load : {40.0, 80.0}) {
      for (double s : {0.1, 0.3, 0.5}) {
        for (double beta : {0.0, 20.0}) {
          const double fy = beta == 0 ? 0.0 : -(10 + 0.1 * load) * (1 - s);
          rows += std::string(wheel) + ",0.15,0.1," + std::to_string(load) + "," + std::to_string(s) + "," +
                  std::to_string(beta) + ",5," + std::to_string(fy) + "\n";
        }
      }
    }
  }
  write_text(steer, rows);
  const std::string png = dir.file("fy.png");
  const CommandResult ok = run_roverlab(
      "render " + quote(steer) + " --view traction-surface --quantity lateral-force --size 640x400 -o " + quote(png));
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_TRUE(std::filesystem::exists(png));
  const CommandResult absent =
      run_roverlab("render " + quote(steer) + " --view traction-surface --quantity lateral-force --slip-angle 15 -o " +
                   quote(dir.file("no.png")));
  EXPECT_NE(absent.exit_code, 0);
  EXPECT_EQ(count_lines(absent.err), 1u) << absent.err;
  EXPECT_NE(absent.err.find("steer.csv"), std::string::npos) << absent.err;
  EXPECT_NE(absent.err.find("slip angles 0, 20 deg"), std::string::npos) << absent.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("no.png")));
  const std::string ding = quote(std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv");
  const CommandResult straight = run_roverlab(
      "render " + ding + " --view traction-surface --quantity lateral-force -o " + quote(dir.file("d.png")));
  EXPECT_NE(straight.exit_code, 0);
  EXPECT_NE(straight.err.find("no lateral_force_N values"), std::string::npos) << straight.err;
  // With a soil, its model's F_y surface at the asked angle, the straight file's wheel.
  const CommandResult model = run_roverlab("render " + ding +
                                           " --view traction-surface --quantity lateral-force --soil ding_tyii "
                                           "--slip-angle 20 --size 640x400 -o " +
                                           quote(dir.file("m.png")));
  EXPECT_EQ(model.exit_code, 0) << model.err;
}

// Issue 43: `roverlab --progress` prints progress on stderr also when it is
// not a terminal (here a pipe): a line every kProgressLinePeriod (5 s) while
// the study runs and one when it is done; without it, no progress at all.
TEST(Cli, ProgressLinesWhenStderrIsNotATerminal) {
  const std::string study = "discrepancy single-wheel " +
                            quote(std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv") +
                            " --soil ding_tyii";
  const auto start = std::chrono::steady_clock::now();
  const CommandResult with = run_roverlab("--progress " + study);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(with.exit_code, 0) << with.err;
  EXPECT_NE(with.err.find("single-wheel study: done in "), std::string::npos) << with.err;
  EXPECT_EQ(with.err.find('\r'), std::string::npos) << "a terminal's carriage returns in a pipe";
  // One line each full 5 s of the run (two seconds of slack for start-up).
  std::size_t lines = 0;
  for (std::size_t at = 0; (at = with.err.find("% after ", at)) != std::string::npos; ++at) ++lines;
  EXPECT_GE(lines, static_cast<std::size_t>(std::max(0.0, std::floor((seconds - 2.0) / 5.0)))) << with.err;
  const CommandResult without = run_roverlab(study);
  ASSERT_EQ(without.exit_code, 0) << without.err;
  EXPECT_EQ(without.err.find("single-wheel study"), std::string::npos) << without.err;
}
