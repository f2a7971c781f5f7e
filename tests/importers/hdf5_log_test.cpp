#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "core/common/error.h"
#include "importers/hdf5_log.h"
#include "raw_hdf5.h"
#include "test_support.h"

using namespace roverlab;
using roverlab::test::RawHdf5;
using roverlab::test::TempDir;
namespace fs = std::filesystem;

namespace {

log::Log sample_log() {
  log::Log lg;
  lg.metadata.rover_id = "exomars_bb2";
  lg.metadata.source_file = "field-day-3.mat";
  lg.metadata.description = "bogie test, run 7";
  lg.metadata.extra["operator"] = "J. Doe";
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<double> t;
  for (int i = 0; i < 1000; ++i) t.push_back(0.001 * i + 1e-7 * (i % 3));
  log::Stream imu("imu", t);
  std::vector<double> a, b;
  for (int i = 0; i < 1000; ++i) {
    a.push_back(noise(rng) * 1e-3);
    b.push_back(i == 500 ? std::numeric_limits<double>::quiet_NaN() : noise(rng) * 1e12);
  }
  imu.add_channel("angular_rate_x", "rad/s", a, "gyro x");
  imu.add_channel("specific_force_z", "m/s^2", b);
  lg.add_stream(std::move(imu));
  log::Stream truth("truth/joints", {0.0, 0.5, 1.0});
  truth.add_channel("bogie_FL", "rad", {0.1, -0.2, 0.3}, "front-left bogie angle");
  lg.add_stream(std::move(truth));
  lg.add_stream(log::Stream("events", {}));
  return lg;
}

void expect_identical(const log::Log& a, const log::Log& b) {
  EXPECT_EQ(a.metadata.rover_id, b.metadata.rover_id);
  EXPECT_EQ(a.metadata.source_file, b.metadata.source_file);
  EXPECT_EQ(a.metadata.description, b.metadata.description);
  EXPECT_EQ(a.metadata.extra, b.metadata.extra);
  ASSERT_EQ(a.streams().size(), b.streams().size());
  for (std::size_t s = 0; s < a.streams().size(); ++s) {
    const auto& sa = a.streams()[s];
    const auto& sb = b.streams()[s];
    EXPECT_EQ(sa.name(), sb.name());
    EXPECT_EQ(sa.time(), sb.time());
    ASSERT_EQ(sa.channels().size(), sb.channels().size()) << sa.name();
    for (std::size_t c = 0; c < sa.channels().size(); ++c) {
      const auto& ca = sa.channels()[c];
      const auto& cb = sb.channels()[c];
      EXPECT_EQ(ca.name, cb.name);
      EXPECT_EQ(ca.unit, cb.unit);
      EXPECT_EQ(ca.description, cb.description);
      ASSERT_EQ(ca.values.size(), cb.values.size());
      for (std::size_t i = 0; i < ca.values.size(); ++i) {
        if (std::isnan(ca.values[i])) {
          EXPECT_TRUE(std::isnan(cb.values[i]));
        } else {
          EXPECT_EQ(ca.values[i], cb.values[i]) << ca.name << "[" << i << "]";
        }
      }
    }
  }
}

}  // namespace

TEST(Hdf5Log, RoundTripIsBitExactInOrderWithMetadata) {
  TempDir dir;
  const log::Log original = sample_log();
  io::write_hdf5_log(original, dir.file("log.h5"));
  EXPECT_TRUE(io::is_roverlab_hdf5(dir.file("log.h5")));
  expect_identical(original, io::read_hdf5_log(dir.file("log.h5")));
}

// A log with added streams, written without copying the log (what the CLI's
// -o does), reads back as the log with the streams added; a stream the log
// has already is refused as Log::add_stream refuses it.
TEST(Hdf5Log, WritesALogWithAddedStreamsAsTheMergedLog) {
  TempDir dir;
  const log::Log base = sample_log();
  log::Log added;
  added.metadata.extra["estimator"] = "test";
  added.metadata.extra["operator"] = "K. Roe";  // added's entry wins, as write_log_with's merge
  log::Stream est("estimate/contact/wheels", {0.0, 0.5});
  est.add_channel("slip_FL", "1", {0.01, -0.02});
  added.add_stream(std::move(est));
  io::write_hdf5_log(base, added, dir.file("merged.h5"));
  log::Log merged = base;
  for (const auto& s : added.streams()) merged.add_stream(s);
  for (const auto& [key, value] : added.metadata.extra) merged.metadata.extra[key] = value;
  expect_identical(merged, io::read_hdf5_log(dir.file("merged.h5")));
  log::Log again;
  again.add_stream(log::Stream("truth/joints", {0.0}));
  EXPECT_THROW(io::write_hdf5_log(base, again, dir.file("twice.h5")), DataError);
  EXPECT_FALSE(fs::exists(dir.file("twice.h5")));
}

// The crash guard's trial read goes through every dataset (and fails where
// the real read fails) without returning the samples.
TEST(Hdf5Log, ReadsEveryDatasetDiscardingItLikeReadAll) {
  TempDir dir;
  io::write_hdf5_log(sample_log(), dir.file("log.h5"));
  EXPECT_NO_THROW(io::Hdf5LogReader(dir.file("log.h5")).read_all_discarding());
  // A damaged channel late in the file: the same error as read_all's.
  const std::string damaged = std::string(ROVERLAB_TEST_DATA) + "/../fuzz/corpus/hdf5_log/chunk_larger_than_file.h5";
  std::string full, trial;
  try {
    (void)io::Hdf5LogReader(damaged).read_all();
  } catch (const InputError& e) {
    full = e.what();
  }
  try {
    io::Hdf5LogReader(damaged).read_all_discarding();
  } catch (const InputError& e) {
    trial = e.what();
  }
  EXPECT_NE(full.find("angular_rate_z"), std::string::npos) << full;
  EXPECT_EQ(trial, full);
}

TEST(Hdf5Log, CatalogWithoutReadingAndOneChannelAlone) {
  TempDir dir;
  io::write_hdf5_log(sample_log(), dir.file("log.h5"));
  io::Hdf5LogReader reader(dir.file("log.h5"));
  EXPECT_EQ(reader.format_version(), io::kLogFormatVersion);
  ASSERT_EQ(reader.catalog().size(), 3u);
  EXPECT_EQ(reader.catalog()[0].name, "imu");
  EXPECT_EQ(reader.catalog()[0].size, 1000u);
  EXPECT_EQ(reader.catalog()[0].channels[1].unit, "m/s^2");
  EXPECT_EQ(reader.catalog()[1].name, "truth/joints");
  EXPECT_EQ(reader.catalog()[1].channels[0].description, "front-left bogie angle");
  const auto bogie = reader.read_channel("truth/joints", "bogie_FL");
  EXPECT_EQ(bogie, (std::vector<double>{0.1, -0.2, 0.3}));
  EXPECT_THROW(reader.read_channel("imu", "nope"), InputError);
}

TEST(Hdf5Log, OverwritesAtomicallyAndLeavesNoTemporaryFiles) {
  TempDir dir;
  const std::string path = dir.file("log.h5");
  io::write_hdf5_log(sample_log(), path);
  log::Log small;
  small.add_stream(log::Stream("gps", {0.0, 1.0}));
  io::write_hdf5_log(small, path);
  EXPECT_EQ(io::read_hdf5_log(path).streams().size(), 1u);
  EXPECT_EQ(roverlab::test::files_in(dir.path()), 1u);
  EXPECT_THROW(io::write_hdf5_log(small, dir.file("missing/folder/log.h5")), InputError);
}

TEST(Hdf5Log, ConvertsDeclaredUnitsToSI) {
  TempDir dir;
  const std::string path = dir.file("foreign-units.h5");
  {
    RawHdf5 f(path);
    f.roverlab_header(1);
    f.roverlab_stream("joints");
    hid_t t = f.dataset("streams/joints/time", {0.0, 500.0, 1000.0});
    RawHdf5::string_attribute(t, "unit", "ms");
    H5Dclose(t);
    hid_t c = f.dataset("streams/joints/channels/bogie", {0.0, 90.0, 180.0});
    RawHdf5::string_attribute(c, "unit", "deg");
    H5Dclose(c);
  }
  const log::Log lg = io::read_hdf5_log(path);
  const auto& s = lg.stream("joints");
  EXPECT_DOUBLE_EQ(s.time()[2], 1.0);
  EXPECT_EQ(s.channel("bogie").unit, "rad");
  EXPECT_NEAR(s.channel("bogie").values[2], M_PI, 1e-15);
}

TEST(Hdf5Log, RejectsNewerFormatVersion) {
  TempDir dir;
  const std::string path = dir.file("future.h5");
  {
    RawHdf5 f(path);
    f.roverlab_header(99);
    f.group("streams");
  }
  try {
    io::read_hdf5_log(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("version 99"), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), path);
  }
}

// Found by fuzzing (tests/fuzz/corpus/hdf5_log/chunk_larger_than_file.h5): a
// 70 kB log whose chunk index claims a 4 GB chunk for one channel made
// libhdf5 allocate and read it for seconds; it is a damaged file.
TEST(Hdf5Log, AChunkLargerThanTheFileIsADamagedFile) {
  const std::string path = std::string(ROVERLAB_TEST_DATA) + "/../fuzz/corpus/hdf5_log/chunk_larger_than_file.h5";
  try {
    (void)io::read_hdf5_log(path);
    FAIL() << "read a damaged file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("angular_rate_z"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("more than the file's"), std::string::npos) << e.what();
  }
}
