#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/common/error.h"
#include "importers/hdf5_support.h"
#include "importers/log_file.h"
#include "importers/matlab_importer.h"
#include "raw_hdf5.h"
#include "test_support.h"

using namespace roverlab;
using roverlab::test::RawHdf5;
using roverlab::test::TempDir;
using roverlab::test::write_text;

namespace {

const std::string kPathfinder = std::string(ROVERLAB_TEST_DATA) + "/test17run.mat";

io::Mapping pathfinder_mapping() {
  return io::load_mapping(std::string(ROVERLAB_RESOURCES_DIR) + "/mappings/wvu_pathfinder.json");
}

std::vector<double> raw_variable(const std::string& path, const std::string& name) {
  io::h5::Handle f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  io::h5::Handle d(H5Dopen2(f.get(), name.c_str(), H5P_DEFAULT));
  return io::h5::read_doubles(d.get());
}

}  // namespace

TEST(MatlabImporter, RecognisesVersions) {
  EXPECT_EQ(io::matlab_file_version(kPathfinder), io::MatFileVersion::v7_3);
  TempDir dir;
  std::string v5(128, ' ');
  v5.replace(0, 19, "MATLAB 5.0 MAT-file");
  write_text(dir.file("old.mat"), v5 + std::string(64, '\0'));
  EXPECT_EQ(io::matlab_file_version(dir.file("old.mat")), io::MatFileVersion::older);
  write_text(dir.file("x.csv"), "time,a\n0,1\n");
  EXPECT_EQ(io::matlab_file_version(dir.file("x.csv")), io::MatFileVersion::not_matlab);
}

TEST(MatlabImporter, PathfinderLogHasImuAndWheelStreams) {
  const log::Log lg = io::read_mapped_hdf5(kPathfinder, pathfinder_mapping());
  const auto& imu = lg.stream("imu");
  EXPECT_EQ(imu.size(), 17611u);
  EXPECT_NEAR(imu.mean_rate_hz(), 250.0, 2.0);
  EXPECT_EQ(imu.channels().size(), 6u);
  EXPECT_EQ(imu.channel("specific_force_z").unit, "m/s^2");
  EXPECT_EQ(imu.channel("angular_rate_z").unit, "rad/s");
  // At rest the z specific force reads about -g.
  EXPECT_NEAR(imu.channel("specific_force_z").values[0], -9.79, 0.05);
  const auto& wheels = lg.stream("wheels");
  EXPECT_EQ(wheels.size(), 705u);
  EXPECT_NEAR(wheels.mean_rate_hz(), 10.0, 0.1);
  EXPECT_EQ(wheels.channel("angle_FL").unit, "rad");
  // Time origin: the earliest sample of any stream is t = 0.
  EXPECT_EQ(imu.start_time(), 0.0);
  EXPECT_GT(wheels.start_time(), 0.0);
  EXPECT_NEAR(std::stod(lg.metadata.extra.at("time_origin")), 1566770959.742861, 1e-5);
  EXPECT_EQ(lg.metadata.rover_id, "wvu_pathfinder");
}

TEST(MatlabImporter, AppliesSignFlipsAndSelectsComponents) {
  const log::Log lg = io::read_mapped_hdf5(kPathfinder, pathfinder_mapping());
  const auto raw_fl = raw_variable(kPathfinder, "frontLeftPos");
  const auto raw_fr = raw_variable(kPathfinder, "frontRightPos");
  const auto& fl = lg.channel("wheels/angle_FL").values;
  const auto& fr = lg.channel("wheels/angle_FR").values;
  ASSERT_EQ(fl.size(), raw_fl.size());
  for (std::size_t i = 0; i < fl.size(); ++i) {
    EXPECT_EQ(fl[i], -raw_fl[i]);
    EXPECT_EQ(fr[i], raw_fr[i]);
  }
  // Driving forward, both sides now count up: about 290 rad over the run.
  EXPECT_GT(fl.back(), 280.0);
  EXPECT_GT(fr.back(), 280.0);
  // ENUGPS is stored [705, 3]: component 1 (north) is every third value from 1.
  const auto raw_enu = raw_variable(kPathfinder, "ENUGPS");
  const auto& north = lg.channel("gps/north").values;
  ASSERT_EQ(raw_enu.size(), 3 * north.size());
  for (std::size_t i = 0; i < north.size(); ++i) EXPECT_EQ(north[i], raw_enu[3 * i + 1]);
  EXPECT_NEAR(north.back(), 34.0, 1.0);  // the ~34 m drive north
}

TEST(MatlabImporter, MappingNamingAMissingVariableIsAnError) {
  io::Mapping m = pathfinder_mapping();
  m.streams[0].channels[0].variable = "AccelerometerX";
  try {
    io::read_mapped_hdf5(kPathfinder, m);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), kPathfinder);
    EXPECT_NE(std::string(e.what()).find("'AccelerometerX'"), std::string::npos) << e.what();
  }
}

TEST(MatlabImporter, GenericHdf5WithUserBlockAndWrongLengths) {
  TempDir dir;
  const std::string path = dir.file("run.mat");
  {
    RawHdf5 f(path, 512);
    H5Dclose(f.dataset("t", {100.0, 100.1, 100.2}, {1, 3}));
    H5Dclose(f.dataset("pitch", {0.0, 45.0, 90.0}, {1, 3}));
    H5Dclose(f.dataset("short", {1.0, 2.0}, {1, 2}));
    H5Dclose(f.dataset("xyz", {1, 2, 3, 4, 5, 6, 7, 8, 9}, {3, 3}));
  }
  io::Mapping m;
  m.name = "test";
  io::StreamMapping s;
  s.name = "joints";
  s.time_variable = "t";
  s.channels.push_back({"pitch", "pitch", std::nullopt, "deg", 1.0, ""});
  m.streams.push_back(s);
  const log::Log lg = io::read_mapped_hdf5(path, m);
  EXPECT_NEAR(lg.channel("joints/pitch").values[2], M_PI / 2, 1e-15);
  EXPECT_NEAR(lg.stream("joints").time()[2], 0.2, 1e-12);

  io::Mapping bad_length = m;
  bad_length.streams[0].channels.push_back({"short", "short", std::nullopt, "1", 1.0, ""});
  try {
    io::read_mapped_hdf5(path, bad_length);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2 samples but the time base has 3"), std::string::npos) << e.what();
  }
  io::Mapping two_d = m;
  two_d.streams[0].channels.push_back({"x", "xyz", std::nullopt, "m", 1.0, ""});
  EXPECT_THROW(io::read_mapped_hdf5(path, two_d), InputError);  // 2-D needs a component
  two_d.streams[0].channels.back().component = 2;
  // [3, 3] row-major: the sample axis is ambiguous; rows are taken as samples.
  EXPECT_EQ(io::read_mapped_hdf5(path, two_d).channel("joints/x").values, (std::vector<double>{3, 6, 9}));
}
