// The log reader registry: each reader picks its own files, by content
// first, then by extension; load_log keeps its errors for the rest.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/common/error.h"
#include "importers/csv_log.h"
#include "importers/hdf5_log.h"
#include "importers/log_file.h"
#include "raw_hdf5.h"
#include "test_support.h"

using namespace roverlab;
using roverlab::test::RawHdf5;
using roverlab::test::TempDir;
using roverlab::test::write_text;

namespace {

const std::string kPathfinder = std::string(ROVERLAB_TEST_DATA) + "/test17run.mat";
const char* kRoverLab = "RoverLab HDF5 log";
const char* kMapped = "HDF5 / MATLAB v7.3 through a mapping";
const char* kCsv = "CSV";

io::LoadOptions with_mapping() {
  io::LoadOptions o;
  o.mapping = io::load_mapping(std::string(ROVERLAB_RESOURCES_DIR) + "/mappings/wvu_pathfinder.json");
  return o;
}

std::string reader_name(const std::string& path, const io::LoadOptions& options = {}) {
  const io::LogReader* reader = io::find_log_reader(path, options);
  return reader ? reader->name() : "none";
}

// The message load_log throws for `path`, or "" when it reads it.
std::string load_error(const std::string& path, const io::LoadOptions& options = {}) {
  try {
    io::load_log(path, options);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    return e.problem();
  }
  return "";
}

}  // namespace

TEST(LogReaders, TheDefListHoldsEachFormatOnce) {
  std::set<std::string> names;
  for (const auto& reader : io::log_readers()) names.insert(reader->name());
  EXPECT_EQ(names, (std::set<std::string>{kRoverLab, kMapped, kCsv, "ROS 1 bag", "MCAP"}));
  EXPECT_EQ(io::log_readers().size(), 5u);
}

TEST(LogReaders, EachReaderPicksItsFiles) {
  TempDir dir;
  write_text(dir.file("run.csv"), "time [s],x [m]\n0,1\n1,2\n");
  write_text(dir.file("run.txt"), "time [s],x [m]\n0,1\n1,2\n");
  const io::LoadedLog csv = io::load_log(dir.file("run.csv"));
  EXPECT_EQ(csv.format, kCsv);
  EXPECT_EQ(reader_name(dir.file("run.txt")), kCsv);

  io::write_hdf5_log(csv.log, dir.file("run.h5"));
  io::write_hdf5_log(csv.log, dir.file("run.csv.bin"));  // the content wins over the name
  const io::LoadedLog h5 = io::load_log(dir.file("run.h5"));
  EXPECT_EQ(h5.format, kRoverLab);
  EXPECT_EQ(h5.log.stream("run").size(), 2u);
  EXPECT_EQ(reader_name(dir.file("run.csv.bin")), kRoverLab);
  EXPECT_EQ(reader_name(dir.file("run.h5"), with_mapping()), kRoverLab);  // a RoverLab log ignores a mapping

  EXPECT_EQ(reader_name(kPathfinder), kMapped);
  EXPECT_EQ(reader_name(kPathfinder, with_mapping()), kMapped);
  const io::LoadedLog mat = io::load_log(kPathfinder, with_mapping());
  EXPECT_EQ(mat.format, kMapped);
  EXPECT_NE(mat.log.find_stream("imu"), nullptr);
}

TEST(LogReaders, ConfidenceOrdersContentBeforeExtension) {
  TempDir dir;
  { RawHdf5 foreign(dir.file("foreign.h5")); }
  // Without a mapping the RoverLab reader explains why a foreign HDF5 file is
  // not its own; with one, the mapped reader takes it.
  EXPECT_EQ(reader_name(dir.file("foreign.h5")), kRoverLab);
  EXPECT_EQ(reader_name(dir.file("foreign.h5"), with_mapping()), kMapped);
  EXPECT_NE(load_error(dir.file("foreign.h5")).find("not a RoverLab log"), std::string::npos);

  for (const auto& reader : io::log_readers()) {
    const io::Confidence c = reader->can_read(kPathfinder, {});
    EXPECT_EQ(c, reader->name() == kMapped ? io::Confidence::format : io::Confidence::none) << reader->name();
  }
  write_text(dir.file("fake.h5"), "plain text");
  write_text(dir.file("fake.mat"), "plain text");
  EXPECT_EQ(reader_name(dir.file("fake.h5")), kRoverLab);  // by its extension only
  EXPECT_EQ(reader_name(dir.file("fake.mat")), kMapped);
  // ROS bags and MCAP files: by their magic first, else by the extension.
  write_text(dir.file("fake.bag"), "plain text");
  write_text(dir.file("fake.mcap"), "plain text");
  write_text(dir.file("bag.dat"), "#ROSBAG V2.0\nrest");
  write_text(dir.file("mcap.dat"), "\x89MCAP0\r\nrest");
  EXPECT_EQ(reader_name(dir.file("fake.bag")), "ROS 1 bag");
  EXPECT_EQ(reader_name(dir.file("fake.mcap")), "MCAP");
  EXPECT_EQ(reader_name(dir.file("bag.dat")), "ROS 1 bag");
  EXPECT_EQ(reader_name(dir.file("mcap.dat")), "MCAP");
  EXPECT_EQ(load_error(dir.file("fake.mcap")), "not an MCAP file (no MCAP magic bytes)");
}

TEST(LogReaders, FilesNoReaderTakesKeepTheirErrors) {
  TempDir dir;
  write_text(dir.file("notes.doc"), "time [s],x [m]\n0,1\n");
  EXPECT_EQ(reader_name(dir.file("notes.doc")), "none");
  EXPECT_EQ(load_error(dir.file("notes.doc")),
            "unrecognised log format (expected HDF5 .h5, MATLAB v7.3 .mat, .csv, ROS 1 .bag or .mcap)");
  EXPECT_EQ(load_error(dir.file("missing.h5")), "no such file");
  EXPECT_EQ(load_error(dir.path().string()), "is a folder, not a log file");
  write_text(dir.file("fake.h5"), "plain text");
  write_text(dir.file("fake.mat"), "plain text");
  EXPECT_EQ(load_error(dir.file("fake.h5")), "not an HDF5 file");
  EXPECT_EQ(load_error(dir.file("fake.mat")), "not an HDF5 file");
  EXPECT_EQ(load_error(dir.file("fake.mat"), with_mapping()), "not an HDF5 file");
  EXPECT_NE(load_error(kPathfinder).find("pass --mapping"), std::string::npos);
  std::string v5(128, ' ');
  v5.replace(0, 19, "MATLAB 5.0 MAT-file");
  write_text(dir.file("old.mat"), v5 + std::string(64, '\0'));
  EXPECT_NE(load_error(dir.file("old.mat")).find("older than v7.3"), std::string::npos);
  EXPECT_NE(load_error(dir.file("old.mat"), with_mapping()).find("older than v7.3"), std::string::npos);
}
