// `roverlab compare` run as a user runs it: the WVU log against a shifted copy
// without its GPS, simulated runs with and without a hidden effect, bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "importers/hdf5_log.h"
#include "importers/log_file.h"
#include "test_support.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

const std::string kExe = ROVERLAB_EXE;
const std::string kPathfinder = std::string(ROVERLAB_TEST_DATA) + "/test17run.mat";

CommandResult run_roverlab(const std::string& args) { return run_command(quote(kExe) + " " + args); }

nlohmann::json compare_json(const std::string& args) {
  const CommandResult r = run_roverlab("compare --json " + args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

// The log with every time moved by `shift` seconds and without the stream `drop`.
void write_shifted_copy(const std::string& from, const std::string& to, double shift, const std::string& drop) {
  const log::Log source = io::load_log(from).log;
  log::Log out;
  out.metadata = source.metadata;
  for (const auto& s : source.streams()) {
    if (s.name() == drop) continue;
    std::vector<double> t = s.time();
    for (double& v : t) v += shift;
    log::Stream shifted(s.name(), t);
    for (const auto& c : s.channels()) shifted.add_channel(c.name, c.unit, c.values, c.description);
    out.add_stream(std::move(shifted));
  }
  io::write_hdf5_log(out, to);
}

TEST(CompareCli, FindsTheWvuLogsShiftAndListsTheDroppedGps) {
  TempDir dir;
  const std::string full = dir.file("full.h5"), shifted = dir.file("shifted.h5");
  ASSERT_EQ(run_roverlab("convert " + quote(kPathfinder) + " -m wvu_pathfinder " + quote(full)).exit_code, 0);
  write_shifted_copy(full, shifted, 1.7, "gps");
  const nlohmann::json doc = compare_json("--find-offset " + quote(full) + " " + quote(shifted));
  const auto& run = doc["runs"][0];
  const double imu_period = 1.0 / 250.0;  // the IMU, the fastest stream, cross-correlated
  EXPECT_NEAR(run["alignment"]["offset_s"].get<double>(), 1.7, imu_period);
  const std::vector<std::string> only = run["only_in_baseline"];
  EXPECT_EQ(only.size(), 6u);
  for (const auto& path : only) EXPECT_EQ(path.rfind("gps/", 0), 0u) << path;
  EXPECT_TRUE(run["only_in_run"].empty());
  // The log against itself: no channel differs, whichever the alignment (the offset found is ~1e-16 s and
  // the distance map not exact: rounding-level differences are not differences).
  for (const char* how : {"--find-offset", "--align motion", "--align distance"}) {
    const nlohmann::json self = compare_json(std::string(how) + " " + quote(full) + " " + quote(full));
    EXPECT_TRUE(self["runs"][0]["differing"].empty()) << how << ": " << self["runs"][0]["differing"].dump();
  }
  // The text names the stream only one run has.
  const CommandResult text = run_roverlab("compare --find-offset " + quote(full) + " " + quote(shifted));
  EXPECT_NE(text.out.find("only in the baseline: gps (east north up latitude longitude height)"), std::string::npos)
      << text.out;
}

std::string simulate(const TempDir& dir, unsigned seed, const std::string& effect = "", int duration = 60) {
  std::string out = dir.file("run" + std::to_string(seed) + ".h5");
  const CommandResult r =
      run_roverlab("simulate flat_60s --seed " + std::to_string(seed) + " --duration " + std::to_string(duration) +
                   (effect.empty() ? "" : " --effect " + effect) + " -o " + quote(out));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return out;
}

// Two seeds of one scenario differ only in their sensor noise: at 1 % per
// channel, hardly a channel is flagged (scripts/compare-calibration measures
// the rate over 20 pairs, docs/compare.md). A force-sensor offset hidden in
// the second run is flagged on the six force channels and named.
TEST(CompareCli, SimulatedSeedsDifferOnlyWhereAHiddenEffectActs) {
  TempDir dir;
  const std::string a = simulate(dir, 1), b = simulate(dir, 2), c = simulate(dir, 3, "force-offset=0.5");
  const nlohmann::json same = compare_json(quote(a) + " " + quote(b));
  const auto& run = same["runs"][0];
  EXPECT_GE(run["channels"].size(), 30u);
  EXPECT_LE(run["differing"].size(), 1u) << run["differing"].dump();
  const nlohmann::json effect = compare_json(quote(a) + " " + quote(c));
  std::vector<std::string> differing = effect["runs"][0]["differing"];
  for (const char* channel : {"load_1", "load_2", "load_3", "perpendicular_1", "perpendicular_2", "perpendicular_3"}) {
    const std::string path = std::string("forces/") + channel;
    EXPECT_NE(std::find(differing.begin(), differing.end(), path), differing.end()) << path;
  }
  for (const auto& c : effect["runs"][0]["channels"]) {
    if (c["stream"] == "forces") {
      EXPECT_NEAR(c["bias"].get<double>(), 0.5, 0.1) << c.dump();
    }
  }
  const CommandResult text = run_roverlab("compare " + quote(a) + " " + quote(c));
  EXPECT_NE(text.out.find("differ: "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("forces/load_1"), std::string::npos) << text.out;
}

TEST(CompareCli, WritesTheDifferenceChannelsAsALog) {
  TempDir dir;
  const std::string a = simulate(dir, 1), c = simulate(dir, 3, "force-offset=0.5");
  const std::string out = dir.file("diff.h5");
  ASSERT_EQ(run_roverlab("compare -o " + quote(out) + " " + quote(a) + " " + quote(c)).exit_code, 0);
  const log::Log d = io::load_log(out).log;
  const log::Log la = io::load_log(a).log, lc = io::load_log(c).log;
  const auto& load = d.stream("difference/forces").channel("load_2").values;
  const auto& va = la.stream("forces").channel("load_2").values;
  const auto& vc = lc.stream("forces").channel("load_2").values;
  ASSERT_EQ(load.size(),
            va.size());  // the baseline's time base, whole: the runs share it and the clocks are taken as recorded
  for (std::size_t k = 0; k < load.size(); k += 101) EXPECT_NEAR(load[k], vc[k] - va[k], 1e-6);
}

// The SVG element of class `css_class` in the page.
std::string svg_of_class(const std::string& html, const std::string& css_class) {
  const auto at = html.find("<svg class=\"" + css_class + "\"");
  if (at == std::string::npos) return {};
  return html.substr(at, html.find("</svg>", at) - at);
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// `report A --compare B`: the map draws both runs' tracks (the logs' own
// positions), the force channels the hidden offset drives are drawn over each
// other with their difference below, and the drawn difference is run minus
// baseline at the baseline's times (about the 0.5 N offset).
TEST(CompareReport, DrawsBothTracksAndTheDifferenceCurve) {
  TempDir dir;
  const std::string a = simulate(dir, 1, "", 20), c = simulate(dir, 3, "force-offset=0.5", 20);
  const std::string out = dir.file("report");
  const CommandResult r = run_roverlab("report " + quote(a) + " --compare " + quote(c) + " -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json metrics = nlohmann::json::parse(read_text(out + "/metrics.json"));
  const auto& cmp = metrics.at("comparison");
  ASSERT_EQ(cmp["map"].size(), 2u);
  const log::Log la = io::load_log(a).log, lc = io::load_log(c).log;
  for (std::size_t k = 0; k < 2; ++k) {
    const log::Log& lg = k == 0 ? la : lc;
    const auto& track = cmp["map"][k];
    EXPECT_EQ(track["stream"], "truth/pose");
    const auto& x = lg.stream("truth/pose").channel("x").values;
    const std::vector<double> drawn = track["x"];
    ASSERT_GE(drawn.size(), 100u);
    EXPECT_DOUBLE_EQ(drawn.front(), x.front());
    const std::size_t stride = (x.size() + drawn.size() - 1) / drawn.size();
    for (std::size_t i = 0; i < drawn.size(); i += 37) EXPECT_DOUBLE_EQ(drawn[i], x[i * stride]);
  }
  bool drew_force = false;
  for (const auto& o : cmp["overlays"]) {
    const std::string channel = o["channel"];
    if (channel.rfind("forces/", 0) != 0) continue;
    drew_force = true;
    const std::vector<double> t = o["time"], base = o["baseline"], run = o["run"], diff = o["difference"];
    const log::Stream& forces = la.stream("forces");
    double mean = 0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      EXPECT_NEAR(base[k], forces.value_at(channel.substr(7), t[k]), 1e-9);
      EXPECT_NEAR(diff[k], run[k] - base[k], 1e-9);
      mean += diff[k] / static_cast<double>(t.size());
    }
    EXPECT_NEAR(mean, 0.5, 0.1) << channel;
  }
  EXPECT_TRUE(drew_force);
  const std::string html = read_text(out + "/index.html");
  // The baseline's track as dots (a run on the same path would hide its line), the run's as a line.
  const std::string map = svg_of_class(html, "plot compare-map");
  EXPECT_EQ(count_of(map, "<path class=\"series\""), 1u);
  EXPECT_GE(count_of(map, "<circle"), 100u);
  EXPECT_GE(count_of(html, "<svg class=\"plot compare\""), 2u);
}

TEST(CompareCli, BadInputIsOneLineNamingTheFileOrOption) {
  TempDir dir;
  const CommandResult one = run_roverlab("compare " + quote(kPathfinder));
  EXPECT_EQ(one.exit_code, 2);
  const std::string missing = dir.file("missing.h5");
  const CommandResult absent = run_roverlab("compare -m wvu_pathfinder " + quote(kPathfinder) + " " + quote(missing));
  EXPECT_EQ(absent.exit_code, 3);
  EXPECT_NE(absent.err.find(missing), std::string::npos) << absent.err;
  const CommandResult alpha =
      run_roverlab("compare -m wvu_pathfinder --false-alarm 2 " + quote(kPathfinder) + " " + quote(kPathfinder));
  EXPECT_EQ(alpha.exit_code, 2);
  EXPECT_NE(alpha.err.find("--false-alarm"), std::string::npos) << alpha.err;
  const CommandResult output = run_roverlab("compare -m wvu_pathfinder -o " + quote(dir.file("d.csv")) + " " +
                                            quote(kPathfinder) + " " + quote(kPathfinder));
  EXPECT_EQ(output.exit_code, 2);
  EXPECT_EQ(files_in(dir.path()), 0u);
}

}  // namespace

// `render A --compare B`: the compare, compare-map and ghost-rover views as PNGs; --compare with a view that
// does not compare runs, a compare view without --compare and a missing run are one line each.
TEST(CompareRender, DrawsTheComparisonViewsAndRefusesWhatTheyCannotDraw) {
  TempDir dir;
  const std::string a = simulate(dir, 1, "", 20), c = simulate(dir, 3, "force-offset=0.5", 20);
  for (const char* view : {"compare", "compare-map"}) {
    const std::string png = dir.file(std::string(view) + ".png");
    const CommandResult r =
        run_roverlab("render " + quote(a) + " --compare " + quote(c) + " --view " + view + " -o " + quote(png));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(png)) << view;
    if (std::string(view) == "compare") {  // the channels the offset drives are drawn and said to differ
      EXPECT_NE(r.out.find("run3 aligned by the clocks as recorded"), std::string::npos) << r.out;
      EXPECT_NE(r.out.find("6 of "), std::string::npos) << r.out;
    }
  }
  const CommandResult other = run_roverlab("render " + quote(a) + " --compare " + quote(c) + " --view timeseries -o " +
                                           quote(dir.file("t.png")));
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_NE(other.err.find("--compare: only for the compare | compare-map | ghost-rover view"), std::string::npos)
      << other.err;
  const CommandResult alone = run_roverlab("render " + quote(a) + " --view compare -o " + quote(dir.file("c.png")));
  EXPECT_EQ(alone.exit_code, 3);
  EXPECT_NE(alone.err.find("needs another run to compare with"), std::string::npos) << alone.err;
  const std::string missing = dir.file("missing.h5");
  const CommandResult absent = run_roverlab("render " + quote(a) + " --compare " + quote(missing) +
                                            " --view compare -o " + quote(dir.file("m.png")));
  EXPECT_EQ(absent.exit_code, 3);
  EXPECT_NE(absent.err.find(missing), std::string::npos) << absent.err;
  // The rover of a planar simulation has no ghost: said in one line.
  const CommandResult ghost = run_roverlab("render " + quote(a) + " --compare " + quote(c) + " --view ghost-rover -o " +
                                           quote(dir.file("g.png")));
  EXPECT_EQ(ghost.exit_code, 3);
  EXPECT_EQ(std::count(ghost.err.begin(), ghost.err.end(), '\n'), 1) << ghost.err;
  EXPECT_EQ(files_in(dir.path()), 4u);  // the two runs and the two pictures
}

// `report A --compare B` draws the views that compare runs as pictures too (the overlays of every run, every
// track with a marker on each), and says in one line why a view cannot draw them (no ghost of a planar rover).
TEST(CompareReport, DrawsTheViewsThatCompareRuns) {
  TempDir dir;
  const std::string a = simulate(dir, 1, "", 20), c = simulate(dir, 3, "force-offset=0.5", 20);
  const std::string out = dir.file("report");
  const CommandResult r = run_roverlab("report " + quote(a) + " --compare " + quote(c) + " -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = read_text(out + "/index.html");
  for (const char* png : {"compare.png", "compare_map.png"}) {
    EXPECT_TRUE(fs::exists(out + "/" + png)) << png;
    EXPECT_NE(html.find(std::string("<img src=\"") + png + "\""), std::string::npos) << png;
  }
  EXPECT_NE(html.find("No ghost-rover view: "), std::string::npos);
}
