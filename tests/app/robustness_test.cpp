// Bad input that used to crash RoverLab, hang it or fill the memory, run as a
// user runs it: one line naming the file and the problem, exit code 3, in
// bounded time (shared/robustness/findings.md F1, F31, F32, F36, F40, F41).
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace roverlab {
namespace {

using test::CommandResult;
using test::quote;
using test::TempDir;

const std::string kExe = ROVERLAB_EXE;
const std::string kData = ROVERLAB_TEST_DATA;

CommandResult run_roverlab(const std::string& args) {
  // `timeout` turns a hang into a failure instead of a stuck test.
  return test::run_command("timeout 60 " + quote(kExe) + " " + args);
}

void expect_one_line_bad_input(const CommandResult& r, const std::string& file, const std::string& problem) {
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(problem), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;  // one line
}

// The bundled log as a RoverLab HDF5 log, opened for writing with HDF5.
class ConvertedLog {
 public:
  explicit ConvertedLog(const TempDir& dir) : path_(dir.file("log.h5")) {
    const CommandResult r =
        run_roverlab("convert " + quote(kData + "/test17run.mat") + " " + quote(path_) + " -m wvu_pathfinder");
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
  const std::string& path() const { return path_; }
  // Runs `edit` on the open file, then closes it.
  template <class Edit>
  void edit(Edit&& edit_file) const {
    const hid_t f = H5Fopen(path_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    edit_file(f);
    H5Fclose(f);
  }

 private:
  std::string path_;
};

TEST(Robustness, OneCorruptedByteInAnHdf5LogIsABadInputNotACrash) {
  for (const char* name : {"segv_byte189.h5", "segv_h006_1634.h5", "segv_h150_1234.h5"}) {
    const std::string file = kData + "/robustness/" + name;
    for (const char* command : {"info ", "estimate ins-slip "}) {
      // libhdf5 crashes on these in the reading process (or, in some memory
      // layouts, reads garbage and finds no RoverLab log): bad input either way.
      const CommandResult r = run_roverlab(command + quote(file));
      EXPECT_EQ(r.exit_code, 3) << r.err;
      EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
      EXPECT_TRUE(r.err.find("corrupt") != std::string::npos || r.err.find("not a RoverLab log") != std::string::npos)
          << r.err;
      EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    }
  }
}

TEST(Robustness, SoftLinkCycleAndExternalLinksAreRefused) {
  TempDir dir;
  const ConvertedLog cycle(dir);
  cycle.edit([](hid_t f) { ASSERT_GE(H5Lcreate_soft("/streams", f, "/streams/loop", H5P_DEFAULT, H5P_DEFAULT), 0); });
  expect_one_line_bad_input(run_roverlab("info " + quote(cycle.path())), cycle.path(), "soft or external link");
  const std::string other = dir.file("other.h5");
  ASSERT_EQ(run_roverlab("convert " + quote(cycle.path()) + " " + quote(other)).exit_code, 3);
  const ConvertedLog external(dir);
  ASSERT_EQ(test::run_command("cp " + quote(external.path()) + " " + quote(other)).exit_code, 0);
  external.edit([&](hid_t f) {
    ASSERT_GE(H5Lcreate_external(other.c_str(), "/streams/imu/time", f, "/streams/imu/channels/ext", H5P_DEFAULT,
                                 H5P_DEFAULT),
              0);
  });
  expect_one_line_bad_input(run_roverlab("info " + quote(external.path())), external.path(), "soft or external link");
}

// Replaces a string attribute of an open file's object.
void set_string_attribute(hid_t file, const char* object, const char* name, const std::string& value) {
  const hid_t o = H5Oopen(file, object, H5P_DEFAULT);
  ASSERT_GE(o, 0);
  H5Adelete(o, name);
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size());
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(o, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(H5Awrite(a, type, value.data()), 0);
  H5Aclose(a);
  H5Sclose(space);
  H5Tclose(type);
  H5Oclose(o);
}

TEST(Robustness, AStreamOfAnUnknownKindIsNamedNotDropped) {
  TempDir dir;
  const ConvertedLog log(dir);
  log.edit([](hid_t f) { set_string_attribute(f, "/streams/imu", "roverlab_kind", "banana"); });
  const CommandResult r = run_roverlab("convert " + quote(log.path()) + " " + quote(dir.file("out.h5")));
  expect_one_line_bad_input(r, log.path(), "roverlab_kind 'banana'");
  EXPECT_FALSE(std::filesystem::exists(dir.file("out.h5")));
}

TEST(Robustness, AChannelWithoutAUnitIsRefused) {
  TempDir dir;
  const ConvertedLog log(dir);
  log.edit([](hid_t f) {
    const hid_t ds = H5Dopen2(f, "/streams/imu/channels/angular_rate_x", H5P_DEFAULT);
    ASSERT_GE(H5Adelete(ds, "unit"), 0);
    H5Dclose(ds);
  });
  // F4: it was read as dimensionless and used as an angular rate.
  expect_one_line_bad_input(run_roverlab("estimate ins-slip " + quote(log.path())), log.path(),
                            "has no unit attribute");
}

TEST(Robustness, ALogsRoverIdIsANameNeverAPath) {
  TempDir dir;
  const std::string sim = dir.file("fl.h5");
  ASSERT_EQ(run_roverlab("scenario fl-bogie-rotation --rate 50 -o " + quote(sim)).exit_code, 0);
  const hid_t f = H5Fopen(sim.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  set_string_attribute(f, "/", "rover_id", "../../../etc/passwd");
  H5Fclose(f);
  const CommandResult r = run_roverlab("estimate contact-angle " + quote(sim));
  expect_one_line_bad_input(r, sim, "is not a rover name");
  EXPECT_EQ(r.err.find("root:"), std::string::npos) << r.err;
}

// Adds `offset` to the last (or every) time stamp of a stream of an open file.
void shift_time(hid_t file, const std::string& stream, double offset, bool last_only) {
  const std::string path = "/streams/" + stream + "/time";
  const hid_t ds = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  ASSERT_GE(ds, 0);
  const hid_t space = H5Dget_space(ds);
  std::vector<double> t(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  ASSERT_GE(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, t.data()), 0);
  if (last_only) {
    t.back() = offset;
  } else {
    for (double& v : t) v += offset;
  }
  ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, t.data()), 0);
  H5Sclose(space);
  H5Dclose(ds);
}

TEST(Robustness, EstimatorsRefuseABrokenTimeBaseInsteadOfPrintingNaN) {
  TempDir dir;
  // F2: one absurd IMU time stamp.
  const ConvertedLog log(dir);
  log.edit([](hid_t f) { shift_time(f, "imu", 1e300, true); });
  const CommandResult ins = run_roverlab("estimate ins-slip " + quote(log.path()));
  expect_one_line_bad_input(ins, log.path(), "a gap of");
  EXPECT_EQ(ins.out.find("nan"), std::string::npos) << ins.out;
  // F6: the same for the contact-angle estimator; F7: joints an hour after the IMU.
  const std::string gap = dir.file("gap.h5"), late = dir.file("late.h5");
  for (const std::string& sim : {gap, late}) {
    ASSERT_EQ(run_roverlab("scenario fl-bogie-rotation --rate 50 -o " + quote(sim)).exit_code, 0);
  }
  hid_t f = H5Fopen(gap.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  shift_time(f, "imu", 1e300, true);
  H5Fclose(f);
  expect_one_line_bad_input(run_roverlab("estimate contact-angle " + quote(gap)), gap, "a gap of");
  f = H5Fopen(late.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  shift_time(f, "joints", 3600.0, false);
  H5Fclose(f);
  expect_one_line_bad_input(run_roverlab("estimate contact-angle " + quote(late)), late, "do not share a time base");
}

// Sets samples [first, first + count) of a stream's channel in an open file to `value`.
void set_samples(hid_t file, const std::string& stream, const std::string& channel, std::size_t first,
                 std::size_t count, double value) {
  const std::string path = "/streams/" + stream + "/channels/" + channel;
  const hid_t ds = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  ASSERT_GE(ds, 0);
  const hid_t space = H5Dget_space(ds);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  ASSERT_GE(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  ASSERT_LE(first + count, v.size());
  for (std::size_t i = first; i < first + count; ++i) v[i] = value;
  ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  H5Sclose(space);
  H5Dclose(ds);
}

// Issue 17 item 4: outliers that took the contact-angle EKF's error from
// degrees to a hundred with exit 0, and a 0.1 s dropout that made the INS
// refuse the whole log, are now rejected or bridged, and the command says so
// in words and in its JSON.
TEST(Robustness, EstimatorsRejectImuOutliersBridgeDropoutsAndSaySo) {
  TempDir dir;
  const std::string sim = dir.file("fl.h5");
  ASSERT_EQ(run_roverlab("scenario fl-bogie-rotation --rate 200 -o " + quote(sim)).exit_code, 0);
  const hid_t f = H5Fopen(sim.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  set_samples(f, "imu", "angular_rate_x", 1800, 1, 40.0);  // 200 Hz, 30 s: at 9, 15 and 21 s
  set_samples(f, "imu", "angular_rate_z", 3000, 1, -35.0);
  set_samples(f, "imu", "specific_force_z", 4200, 1, 400.0);
  H5Fclose(f);
  const CommandResult json = run_roverlab("estimate contact-angle " + quote(sim) + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto doc = nlohmann::json::parse(json.out);
  EXPECT_EQ(doc.at("health").at("outliers_rejected").get<int>(), 3);
  EXPECT_EQ(doc.at("health").at("status"), "degraded");
  double sum = 0;
  for (const auto& e : doc.at("rms").at("contact_angle_deg")) sum += e.get<double>();
  // 7.58 deg clean with the defaults (the reset and the smoother; 6.24 for the original filter alone);
  // unprotected, these outliers made it about 130 deg.
  EXPECT_LT(sum / 6.0, 8.3);
  const CommandResult text = run_roverlab("estimate contact-angle " + quote(sim));
  EXPECT_NE(text.out.find("health: degraded: 3 IMU samples rejected as outliers"), std::string::npos) << text.out;

  const ConvertedLog log(dir);
  log.edit([](hid_t file) {  // 250 Hz: 0.1 s of NaN from 35 s
    for (const char* c : {"angular_rate_x", "angular_rate_y", "angular_rate_z", "specific_force_x", "specific_force_y",
                          "specific_force_z"})
      set_samples(file, "imu", c, 8800, 25, NAN);
  });
  const CommandResult ins = run_roverlab("estimate ins-slip " + quote(log.path()) + " --json");
  ASSERT_EQ(ins.exit_code, 0) << ins.err;
  const auto h = nlohmann::json::parse(ins.out).at("health");
  EXPECT_EQ(h.at("missing_samples").get<int>(), 25);
  ASSERT_EQ(h.at("gaps").size(), 1u);
  EXPECT_NEAR(h.at("gaps").at(0).at("end").get<double>() - h.at("gaps").at(0).at("start").get<double>(), 0.104, 0.005);
  EXPECT_NE(h.at("message").get<std::string>().find("1 gap of 0.10 s bridged by prediction"), std::string::npos);
}

TEST(Robustness, ADatasetDeclaringTerabytesIsABadInput) {
  TempDir dir;
  const ConvertedLog huge(dir);
  huge.edit([](hid_t f) {
    ASSERT_GE(H5Ldelete(f, "/streams/imu/channels/angular_rate_x", H5P_DEFAULT), 0);
    const hsize_t dims = hsize_t{1} << 40, max = H5S_UNLIMITED, chunk = 1 << 16;
    const hid_t space = H5Screate_simple(1, &dims, &max);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, &chunk);
    const hid_t ds =
        H5Dcreate2(f, "/streams/imu/channels/angular_rate_x", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ASSERT_GE(ds, 0);
    H5Dclose(ds);
    set_string_attribute(f, "/streams/imu/channels/angular_rate_x", "unit", "rad/s");
    H5Pclose(dcpl);
    H5Sclose(space);
  });
  const CommandResult r = run_roverlab("info " + quote(huge.path()));
  expect_one_line_bad_input(r, huge.path(), "angular_rate_x");
  EXPECT_NE(r.err.find("more than the file"), std::string::npos) << r.err;
}

TEST(Robustness, AValueTypeZeroBytesWideIsABadInput) {
  // Found by fuzzing the MATLAB importer (tests/data/robustness/README.md): a
  // float type 0 bytes wide let a declared 1.08e18 values pass the
  // declared-size check, and the reader tried to allocate them.
  const std::string file = kData + "/robustness/matlab_value_width_0.mat";
  const CommandResult r = run_roverlab("info " + quote(file) + " --mapping wvu_pathfinder");
  expect_one_line_bad_input(r, file, "values are 0 bytes wide");
}

TEST(Robustness, ADatasetInTooManyChunksIsABadInputNotAHang) {
  // Found by fuzzing (tests/fuzz/corpus/hdf5_log/too_many_chunks.h5): a time
  // base declaring chunks of one value made libhdf5 spend seconds on a 70 kB file.
  TempDir dir;
  const ConvertedLog log(dir);
  log.edit([](hid_t f) {
    ASSERT_GE(H5Ldelete(f, "/streams/imu/time", H5P_DEFAULT), 0);
    const hsize_t dims = 100000, chunk = 1;  // 800 kB declared: less than the file, no more than a log may be
    const hid_t space = H5Screate_simple(1, &dims, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, &chunk);
    const hid_t ds = H5Dcreate2(f, "/streams/imu/time", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ASSERT_GE(ds, 0);
    H5Dclose(ds);
    set_string_attribute(f, "/streams/imu/time", "unit", "s");
    H5Pclose(dcpl);
    H5Sclose(space);
  });
  const CommandResult r = run_roverlab("info " + quote(log.path()));
  expect_one_line_bad_input(r, log.path(), "100000 chunks");
}

TEST(Robustness, ACsvThatNeverEndsIsRefused) {
  TempDir dir;
  const std::string zero = dir.file("zero.csv"), fifo = dir.file("pipe.csv"), binary = dir.file("binary.csv");
  ASSERT_EQ(symlink("/dev/zero", zero.c_str()), 0);
  expect_one_line_bad_input(run_roverlab("info " + quote(zero)), zero, "not a regular file");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  expect_one_line_bad_input(run_roverlab("info " + quote(fifo)), fifo, "not a regular file");
  test::write_text(binary, std::string("time [s],x [m]\n0,1\n1,\0\0\0\n", 24));
  expect_one_line_bad_input(run_roverlab("info " + quote(binary)), binary, "NUL byte");
  // The views look at a .csv's header first: the same answers there.
  expect_one_line_bad_input(run_roverlab("render " + quote(fifo) + " -o " + quote(dir.file("x.png"))), fifo,
                            "not a regular file");
  expect_one_line_bad_input(run_roverlab("report " + quote(zero) + " -o " + quote(dir.file("r"))), zero,
                            "not a regular file");
}

TEST(Robustness, OutputsNeverReplaceTheInputNorWriteProtectedFiles) {
  TempDir dir;
  const ConvertedLog log(dir);
  const std::string before = test::read_text(log.path());
  // F28: the output is the input.
  CommandResult r = run_roverlab("convert " + quote(log.path()) + " " + quote(log.path()));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("input file"), std::string::npos) << r.err;
  r = run_roverlab("estimate ins-slip " + quote(log.path()) + " -o " + quote(dir.file("./log.h5")));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(test::read_text(log.path()) == before) << "the input was changed";
  // F35: a write-protected file is refused, a private one stays private, a link stays a link.
  const std::string locked = dir.file("locked.h5"), secret = dir.file("secret.h5"), target = dir.file("target.h5"),
                    link = dir.file("link.h5");
  test::write_text(locked, "mine");
  chmod(locked.c_str(), 0444);
  r = run_roverlab("convert " + quote(log.path()) + " " + quote(locked));
  expect_one_line_bad_input(r, locked, "write-protected");
  EXPECT_EQ(test::read_text(locked), "mine");
  test::write_text(secret, "old");
  chmod(secret.c_str(), 0600);
  ASSERT_EQ(run_roverlab("convert " + quote(log.path()) + " " + quote(secret)).exit_code, 0);
  struct stat st {};
  ASSERT_EQ(stat(secret.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  test::write_text(target, "old");
  ASSERT_EQ(symlink(target.c_str(), link.c_str()), 0);
  ASSERT_EQ(run_roverlab("convert " + quote(log.path()) + " " + quote(link)).exit_code, 0);
  struct stat lst {};
  ASSERT_EQ(lstat(link.c_str(), &lst), 0);
  EXPECT_TRUE(S_ISLNK(lst.st_mode));
  EXPECT_EQ(run_roverlab("info " + quote(target)).exit_code, 0) << "the link's target holds the new log";
}

TEST(Robustness, AReportNeverOverwritesTheUsersFilesNorIgnoresAnUnknownSoil) {
  TempDir dir;
  const std::string mine = dir.file("mine"), wheel = kData + "/single_wheel/ding2011_tyii.csv";
  std::filesystem::create_directories(mine);
  test::write_text(mine + "/index.html", "<html>mine</html>");
  CommandResult r = run_roverlab("report " + quote(wheel) + " --soil ding_tyii --size 200x150 -o " + quote(mine));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(test::read_text(mine + "/index.html"), "<html>mine</html>");
  // Over a previous report: fine.
  const std::string previous = dir.file("previous");
  ASSERT_EQ(run_roverlab("report " + quote(wheel) + " --soil ding_tyii --size 200x150 -o " + quote(previous)).exit_code,
            0);
  r = run_roverlab("report " + quote(wheel) + " --soil ding_tyii --size 200x150 -o " + quote(previous));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_roverlab("report " + quote(wheel) + " --soil no_such_soil -o " + quote(dir.file("new")));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("no_such_soil"), std::string::npos) << r.err;
}

TEST(Robustness, AbsurdOptionValuesAreUsageErrorsNamingTheOption) {
  // Parsed before any file is read: the files need not exist.
  const std::string tm = "terramechanics --soil ding_tyii --radius 0.075 --width 0.07 --load 50 --slip 0.2";
  const std::pair<std::string, std::string> cases[] = {
      {tm + " --soil-strength -3", "--soil-strength"},        // F22: 5.2 kN of pull from 50 N
      {tm + " --bulldozing-scale -5", "--bulldozing-scale"},  // F22
      {tm + " --slip-sinkage-n1 -100", "--slip-sinkage-n1"},  // F22: NaN fields
      {tm + " --radius 1e300", "--radius"},                   // F22
      {tm + " --slip 0.2,2", "--slip"},
      {tm + " --slip-angle nan", "--slip-angle"},  // issue 33
      {tm + " --slip-angle 10,120", "--slip-angle"},
      {tm + " --slip-angle 10 --sidewall-scale -1", "--sidewall-scale"},
      {tm + " --riemann-points 2000000000", "--riemann-points"},                                        // F23: minutes
      {"terramechanics surface --soil ding_tyii --radius 0.075 --width 0.07 --grid 100000", "--grid"},  // F24
      {"terramechanics fit points.csv --grid 1000000000", "--grid"},                                    // F17
      {"estimate ins-slip log.h5 --odometry-sigma -1", "--odometry-sigma"},                             // F33
      {"estimate ins-slip log.h5 --odometry-sigma nan", "--odometry-sigma"},                            // F33
      {"estimate contact-angle log.h5 --velocity-variance -1", "--velocity-variance"},                  // F33
      {"estimate contact-angle log.h5 --angle-variance nan", "--angle-variance"},                       // F33
      {"estimate contact-angle log.h5 --joint-rate-window -1", "--joint-rate-window"},                  // F33
      {"discrepancy odometry log.h5 --fit-fraction nan", "--fit-fraction"},                             // F33
      {"render log.h5 --quantity banana -o x.png", "--quantity"},                                       // F26
      {"render log.h5 --time nan -o x.png", "--time"},                                                  // F25
      {"simulate flat_60s --effect gyro-bias=1e300 -o x.h5", "gyro-bias"},                              // F27
      {"simulate flat_60s --effect imu-time-offset=1e9 -o x.h5", "imu-time-offset"},                    // F27
      {"scenario skid-steer-slip --effect slip=-5 -o x.h5", "slip"},
      {"simulate flat_60s --duration 1e6 -o x.h5", "100000"},  // F18: "--duration must be positive" // F27
  };
  for (const auto& [args, option] : cases) {
    const CommandResult r = run_roverlab(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("roverlab: ", 0), 0u) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(option), std::string::npos) << args << "\n" << r.err;
  }
}

TEST(Robustness, ATractionSurfaceIsNotFittedToPointsThatCannotDefineIt) {
  TempDir dir;
  const std::string one_place = dir.file("one.csv"), garbage = dir.file("bad.csv");
  std::string rows = "load_N,slip,drawbar_pull_N\n", bad = rows;
  for (int k = 1; k <= 10; ++k) {
    rows += "80,0.5," + std::to_string(k) + "\n";                               // F16: one (W, s)
    bad += std::to_string(-10 * k) + "," + std::to_string(3 * k) + ",1e300\n";  // F15
  }
  test::write_text(one_place, rows);
  test::write_text(garbage, bad);
  expect_one_line_bad_input(run_roverlab("terramechanics fit " + quote(one_place)), one_place,
                            "two loads and two slips");
  expect_one_line_bad_input(run_roverlab("terramechanics fit " + quote(garbage)), garbage, "row 1: load_N must be");
}

TEST(Robustness, AnEmptyFileNameIsCalledSo) {
  // F42: "roverlab: : no such file".
  const CommandResult r = run_roverlab("info ''");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("the file name is empty"), std::string::npos) << r.err;
}

TEST(Robustness, MessagesNameWhatIsReallyWrong) {
  // F42: a hidden file named ".h5" written; a folder called "no such scenario
  // file"; a 2-D channel called a length mismatch.
  TempDir dir;
  CommandResult r = run_roverlab("simulate flat_60s --duration 1 -o " + quote(dir.file(".h5")));
  expect_one_line_bad_input(r, ".h5", "no name before its extension");
  EXPECT_FALSE(std::filesystem::exists(dir.file(".h5")));
  expect_one_line_bad_input(run_roverlab("simulate " + quote(dir.path().string()) + " -o " + quote(dir.file("x.h5"))),
                            dir.path().string(), "is a folder, not a scenario file");
  const ConvertedLog log(dir);
  log.edit([](hid_t file) {
    const hsize_t dims[2] = {10, 2};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t ds =
        H5Dcreate2(file, "/streams/imu/channels/wide", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(ds, 0);
    H5Dclose(ds);
    H5Sclose(space);
    set_string_attribute(file, "/streams/imu/channels/wide", "unit", "m");
  });
  expect_one_line_bad_input(run_roverlab("info " + quote(log.path())), log.path(), "expected a 1-D dataset");
}

TEST(Robustness, AHugeCellIsNotEchoedWhole) {
  TempDir dir;
  const std::string csv = dir.file("wide.csv");
  test::write_text(csv, "time [s],x [m]\n0,1\n1," + std::string(3'000'000, 'x') + "\n");
  const CommandResult r = run_roverlab("info " + quote(csv));
  expect_one_line_bad_input(r, csv, "cannot parse");
  EXPECT_LT(r.err.size(), 400u);  // F10: the 3 MB cell was echoed whole
}

TEST(Robustness, ACsvInAnotherDialectIsNamedForWhatItIs) {
  // F11: the symptom (a unit 'A' on the time column, a ragged row) was named, not the cause.
  TempDir dir;
  const std::pair<std::string, std::string> cases[] = {
      {"time [s];bogie [deg];current [A]\n0;1;2\n1;2;3\n", "separated by ';'"},
      {"time [s]\tbogie [deg]\n0\t1\n1\t2\n", "separated by tabs"},
      {"time [s],\"x, y [m]\"\n0,1\n", "quoted cells"},
      {"time,bogie,current\n0,1,2\n1,2,3\n", "write its header as 'time [s]'"},
  };
  int k = 0;
  for (const auto& [text, problem] : cases) {
    const std::string csv = dir.file("dialect" + std::to_string(k++) + ".csv");
    test::write_text(csv, text);
    expect_one_line_bad_input(run_roverlab("info " + quote(csv)), csv, problem);
  }
}

TEST(Robustness, DegenerateSingleWheelDataIsRefusedQuietly) {
  TempDir dir;
  const std::string header = "wheel,grouser_count,grouser_height_m,radius_m,width_m,load_N,slip,drawbar_pull_N\n";
  const std::string same = dir.file("allsame.csv"), one = dir.file("onerow.csv"), grousers = dir.file("grouser.csv");
  std::string rows = header;
  for (int i = 0; i < 8; ++i) rows += "smooth,0,0,0.157,0.165,80,0.1,12\n";
  test::write_text(same, rows);
  test::write_text(one, header + "smooth,0,0,0.157,0.165,80,0.1,12\n");
  test::write_text(grousers, header + "g,-5,-0.01,0.157,0.165,80,0.1,12\n");
  // F12: a "+128 N per unit slip" trend with t = 1e9, NaN sigmas and glog lines;
  // F14: "no measured quantities" and glog lines; F13: a negative grouser count modelled.
  const std::string study = "discrepancy single-wheel --soil ding_tyii ";
  expect_one_line_bad_input(run_roverlab(study + quote(same)), same, "two slips");
  expect_one_line_bad_input(run_roverlab(study + quote(one)), one, "at least 4 points");
  expect_one_line_bad_input(run_roverlab(study + quote(grousers)), grousers, "grouser_count");
}

TEST(Robustness, ASoilFileOfAnotherVersionOrUnitIsRefused) {
  // F21: version 99 and kc in furlongs were read as version 1 in Pa.
  TempDir dir;
  const std::string base = test::read_text(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
  const std::pair<std::string, std::string> cases[] = {{"\"version\": 1", "\"version\": 99"},
                                                       {"Pa/m^(n-1)", "furlong"}};
  for (const auto& [from, to] : cases) {
    std::string text = base;
    text.replace(text.find(from), from.size(), to);
    const std::string soil = dir.file("soil.json");
    test::write_text(soil, text);
    const CommandResult r =
        run_roverlab("terramechanics --soil " + quote(soil) + " --radius 0.075 --width 0.07 --load 50 --slip 0.2");
    expect_one_line_bad_input(r, soil, to == "furlong" ? "kc_unit" : "version");
  }
}

TEST(Robustness, AnUnwritableFolderIsNamedNotTheTemporaryFile) {
  // F29, F34: raw HDF5 text with the hidden temporary name, errno and flags.
  TempDir dir;
  const ConvertedLog log(dir);
  const CommandResult r = run_roverlab("convert " + quote(log.path()) + " /proc/out.h5");
  expect_one_line_bad_input(r, "/proc/out.h5", "cannot write");
  EXPECT_EQ(r.err.find(".tmp-"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("o_flags"), std::string::npos) << r.err;
}

TEST(Robustness, APlotOfNothingButNaNIsRefusedAndATimeOutsideTheLogIsAUsageError) {
  TempDir dir;
  const std::string nan_log = dir.file("allnan.csv"), log = dir.file("log.csv");
  test::write_text(nan_log, "time [s],x [m],y [m]\n0,nan,nan\n1,nan,nan\n2,nan,nan\n");
  test::write_text(log, "time [s],x [m],y [m]\n0,1,2\n1,2,3\n2,3,4\n");
  // F8: exit 0, empty axes and VTK error lines.
  expect_one_line_bad_input(
      run_roverlab("render " + quote(nan_log) + " --view timeseries -o " + quote(dir.file("nan.png"))), nan_log,
      "two finite samples");
  // F25: a blank picture at t = 1e9 s.
  const CommandResult r =
      run_roverlab("render " + quote(log) + " --view timeseries --time 1e9 -o " + quote(dir.file("late.png")));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("outside the log"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("late.png")));
}

}  // namespace
}  // namespace roverlab
