// Headless rendering, run as a user runs it: `roverlab render` and
// `roverlab report` on known logs, with the pictures' content checked —
// not blank, the rover's pixels where the chase camera puts them, its wheels
// in the slip class's colour, a plot's line where its data is, the surface's
// colour range. Each run starts its own private Xvfb when DISPLAY is unset.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <sys/stat.h>

#include "image_support.h"
#include "test_support.h"
#include "views/offscreen.h"

using namespace roverlab;
using namespace roverlab::test;
namespace fs = std::filesystem;

namespace {

const std::string kExe = ROVERLAB_EXE;
const std::string kData = ROVERLAB_TEST_DATA;
const std::string kPathfinder = kData + "/test17run.mat";

CommandResult run_roverlab(const std::string& args) { return run_command(quote(kExe) + " " + args); }

double distinct_colours(const views::Image& img) {
  std::vector<int> seen;
  for (int y = 0; y < img.height; y += 4) {
    for (int x = 0; x < img.width; x += 4) {
      const unsigned char* p = img.pixel(x, y);
      seen.push_back((p[0] >> 3) << 10 | (p[1] >> 3) << 5 | (p[2] >> 3));
    }
  }
  std::sort(seen.begin(), seen.end());
  return static_cast<double>(std::unique(seen.begin(), seen.end()) - seen.begin());
}

views::Image render(const std::string& args, const std::string& png) {
  const CommandResult r = run_roverlab("render " + args + " -o " + quote(png));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return views::read_png(png);
}

}  // namespace

TEST(Render, RoverViewPutsThePathfinderAtTheCentreWithWheelsInItsSlipClassColour) {
  TempDir dir;
  // Driving at 30 s: the INS says low slip (yellow-green wheels).
  const views::Image img =
      render(quote(kPathfinder) + " -m wvu_pathfinder --view rover -t 30 --size 640x400", dir.file("rover.png"));
  ASSERT_EQ(img.width, 640);
  ASSERT_EQ(img.height, 400);
  EXPECT_GT(distinct_colours(img), 50);  // not blank
  // Yellow-green wheels: green well above blue and at least red.
  const Region wheels = find_pixels(img, [](int r, int g, int b) { return g - b > 90 && g >= r && g > 120; });
  EXPECT_GT(wheels.count, 400);
  EXPECT_NEAR(wheels.mean_x, 320, 64);  // the chase camera centres the rover
  EXPECT_NEAR(wheels.mean_y, 200, 80);
  // The light body beside them, in the middle of the picture (the legend's
  // white box is in a corner, the sky at the top).
  const Region body = find_pixels(
      img, [&](int r, int g, int b) { return r > 200 && g > 200 && b > 200; }, 160, 480, 100, 320);
  EXPECT_GT(body.count, 300);
  EXPECT_NEAR(body.mean_x, 320, 64);
  // At rest (2 s) the slip class is none: pure green, no yellow.
  const views::Image still =
      render(quote(kPathfinder) + " -m wvu_pathfinder --view rover -t 2 --size 640x400", dir.file("still.png"));
  const Region green = find_pixels(still, [](int r, int g, int b) { return g - r > 50 && g - b > 50; });
  EXPECT_GT(green.count, 400);
  EXPECT_NEAR(green.mean_x, 320, 64);
}

TEST(Render, TimeSeriesDrawsTheLineWhereItsDataIsAndTheCursorAtItsTime) {
  TempDir dir;
  // A step: 0 for t < 5 s, then 1, sampled at 100 Hz for 10 s.
  std::string csv = "time [s],x [m]\n";
  for (int i = 0; i <= 1000; ++i) csv += std::to_string(i * 0.01) + "," + (i < 500 ? "0" : "1") + "\n";
  write_text(dir.file("step.csv"), csv);
  const views::Image img = render(
      quote(dir.file("step.csv")) + " --view timeseries --channels step:x -t 7.5 --size 800x400", dir.file("ts.png"));
  // The first plot colour, (31, 119, 180).
  auto line = [](int r, int g, int b) {
    return std::abs(r - 31) < 40 && std::abs(g - 119) < 40 && std::abs(b - 180) < 40;
  };
  // Split the line's pixels at the middle column.
  int n_left = 0, n_right = 0;
  double y_left = 0, y_right = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const unsigned char* p = img.pixel(x, y);
      if (!line(p[0], p[1], p[2])) continue;
      if (x < img.width * 0.4) {
        ++n_left;
        y_left += y;
      } else if (x > img.width * 0.6) {
        ++n_right;
        y_right += y;
      }
    }
  }
  ASSERT_GT(n_left, 50);
  ASSERT_GT(n_right, 50);
  EXPECT_GT(y_left / n_left - y_right / n_right, 150.0);  // after the step the line is far higher on screen
  // The cursor: the column with the most black pixels right of the value
  // axis, three quarters across the plot.
  int best_x = -1, best = 0;
  for (int x = img.width / 8; x < img.width; ++x) {
    int k = 0;
    for (int y = 0; y < img.height; ++y) {
      const unsigned char* p = img.pixel(x, y);
      k += p[0] < 40 && p[1] < 40 && p[2] < 40;
    }
    if (k > best) {
      best = k;
      best_x = x;
    }
  }
  EXPECT_GT(best, 150);
  EXPECT_NEAR(best_x, 0.75 * img.width, 0.12 * img.width);
}

TEST(Render, TractionSurfaceSpansItsColourMapAndShowsTheMeasuredPoints) {
  TempDir dir;
  const views::Image img = render(
      quote(kData + "/single_wheel/ding2011_tyii.csv") + " --view traction-surface --soil ding_tyii --size 800x600",
      dir.file("surface.png"));
  const Region red = find_pixels(img, [](int r, int g, int b) { return r > 170 && g < 110 && b < 110; });
  const Region blue = find_pixels(img, [](int r, int g, int b) { return b > 170 && r < 120 && g < 150; });
  const Region black = find_pixels(img, [](int r, int g, int b) { return r < 40 && g < 40 && b < 40; });
  EXPECT_GT(red.count, 2000);   // high drawbar pull (high slip)
  EXPECT_GT(blue.count, 2000);  // negative drawbar pull (low slip)
  EXPECT_GT(black.count, 200);  // points, residual lines and axis text
  // Torque surface from the same points with their own fit would need two loads.
  const CommandResult one_load = run_roverlab("render " + quote(kData + "/single_wheel/ding2011_tyii.csv") +
                                              " --view traction-surface -o " + quote(dir.file("x.png")));
  EXPECT_EQ(one_load.exit_code, 3);
  EXPECT_NE(one_load.err.find("one load"), std::string::npos) << one_load.err;
  EXPECT_FALSE(fs::exists(dir.file("x.png")));
}

// Issue 12 item 8: on a rocker-bogie log the traction-surface view shows the
// rover's own estimated points coloured by wheel (green, purple, brown),
// the surface fitted to them, and the true local model translucent grey.
TEST(Render, TractionSurfaceOfARoverLogShowsItsEstimatedPointsByWheelAndTheTrueSurface) {
  TempDir dir;
  const CommandResult sim =
      run_roverlab("simulate rolling_200s --duration 40 --effect soil-strength=2.5 -o " + quote(dir.file("roll.h5")));
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const views::Image img =
      render(quote(dir.file("roll.h5")) + " --view traction-surface --quantity torque --size 800x600",
             dir.file("surface.png"));
  const Region green = find_pixels(img, [](int r, int g, int b) { return g > 110 && r < 80 && b < 110; });
  const Region purple = find_pixels(img, [](int r, int g, int b) { return r > 100 && b > 140 && g < 80; });
  const Region brown = find_pixels(img, [](int r, int g, int b) { return r > 120 && g > 70 && g < 170 && b < 60; });
  const Region grey = find_pixels(
      img, [](int r, int g, int b) { return std::abs(r - g) < 10 && std::abs(g - b) < 10 && r > 150 && r < 235; });
  EXPECT_GT(green.count, 30);   // wheel 1's points
  EXPECT_GT(purple.count, 30);  // wheel 2's
  EXPECT_GT(brown.count, 30);   // wheel 3's
  EXPECT_GT(grey.count, 3000);  // the true local model
}

// Issue 30: a result stored with the log (estimate X -o) is reused by render,
// not computed again; the traction-surface view draws from the log that
// `estimate net-traction -o` writes; a --time outside the log and a view the
// log cannot feed are refused before any analysis runs.
TEST(Render, AStoredResultIsReusedAndWhatAViewLacksIsRefusedFirst) {
  TempDir dir;
  const std::string measured = dir.file("run.h5"), traction = dir.file("traction.h5"), study = dir.file("study.h5");
  ASSERT_EQ(run_roverlab("simulate flat_60s --duration 30 -o " + quote(measured)).exit_code, 0);
  const CommandResult nt = run_roverlab("estimate net-traction " + quote(measured) + " -o " + quote(traction));
  ASSERT_EQ(nt.exit_code, 0) << nt.err;
  const CommandResult surface =
      run_roverlab("render " + quote(traction) + " --view traction-surface -o " + quote(dir.file("s.png")));
  ASSERT_EQ(surface.exit_code, 0) << surface.err;
  EXPECT_NE(surface.out.find("reused the stored result of estimate net-traction"), std::string::npos) << surface.out;
  const CommandResult rover = run_roverlab("discrepancy rover " + quote(traction) + " -o " + quote(study));
  ASSERT_EQ(rover.exit_code, 0) << rover.err;
  const CommandResult view = run_roverlab("render " + quote(study) + " --view rover -o " + quote(dir.file("r.png")));
  ASSERT_EQ(view.exit_code, 0) << view.err;
  EXPECT_NE(view.out.find("reused the stored result of estimate net-traction"), std::string::npos) << view.out;
  EXPECT_EQ(view.out.find("ran "), std::string::npos) << view.out;
  // Issue 46: a view runs only the analyses whose streams it draws: the rover
  // view draws the net traction, not the study's residuals; the map neither.
  EXPECT_EQ(view.out.find("discrepancy rover"), std::string::npos) << view.out;
  const CommandResult fresh =
      run_roverlab("render " + quote(measured) + " --view rover -o " + quote(dir.file("f.png")));
  ASSERT_EQ(fresh.exit_code, 0) << fresh.err;
  EXPECT_NE(fresh.out.find("ran estimate net-traction"), std::string::npos) << fresh.out;
  EXPECT_EQ(fresh.out.find("discrepancy rover"), std::string::npos) << fresh.out;
  const CommandResult map = run_roverlab("render " + quote(measured) + " --view map -o " + quote(dir.file("m.png")));
  ASSERT_EQ(map.exit_code, 0) << map.err;
  EXPECT_EQ(map.out.find("ran "), std::string::npos) << map.out;
  // Refused before any analysis runs: the error comes alone, with no "ran" note before it.
  const CommandResult late =
      run_roverlab("render " + quote(measured) + " --view rover --time 1e6 -o " + quote(dir.file("t.png")));
  EXPECT_EQ(late.exit_code, 2) << late.err;
  EXPECT_NE(late.err.find("outside the log"), std::string::npos) << late.err;
  const CommandResult angles =
      run_roverlab("render " + quote(measured) + " --view contact-angles -o " + quote(dir.file("c.png")));
  EXPECT_EQ(angles.exit_code, 3) << angles.err;
  EXPECT_NE(angles.err.find("no contact-angle estimates"), std::string::npos) << angles.err;
  EXPECT_FALSE(fs::exists(dir.file("c.png")));
}

TEST(Render, ErrorsAreOneLineAndLeaveNoFile) {
  TempDir dir;
  const std::string out = quote(dir.file("o.png"));
  const CommandResult missing = run_roverlab("render " + quote(dir.file("nope.h5")) + " -o " + out);
  EXPECT_EQ(missing.exit_code, 3);
  EXPECT_NE(missing.err.find("nope.h5"), std::string::npos);
  const CommandResult contact =
      run_roverlab("render " + quote(kPathfinder) + " -m wvu_pathfinder --view contact-angles -o " + out);
  EXPECT_EQ(contact.exit_code, 3);
  EXPECT_NE(contact.err.find("contact-angle"), std::string::npos) << contact.err;
  EXPECT_EQ(std::count(contact.err.begin(), contact.err.end(), '\n'), 1);
  EXPECT_EQ(run_roverlab("render " + quote(kPathfinder) + " -m wvu_pathfinder --size 12x9000 -o " + out).exit_code, 2);
  EXPECT_EQ(run_roverlab("render " + quote(kPathfinder) + " -m wvu_pathfinder --view spaceship -o " + out).exit_code,
            2);
  EXPECT_EQ(run_roverlab("render " + quote(kPathfinder) +
                         " -m wvu_pathfinder --channels imu:nothing --view timeseries -o " + out)
                .exit_code,
            3);
  // No display and no Xvfb: a one-line message saying how to run headless.
  const CommandResult headless = run_command("/usr/bin/env -u DISPLAY PATH=/nonexistent " + quote(kExe) + " render " +
                                             quote(kPathfinder) + " -m wvu_pathfinder -o " + out);
  EXPECT_EQ(headless.exit_code, 4);
  EXPECT_NE(headless.err.find("xvfb-run"), std::string::npos) << headless.err;
  EXPECT_EQ(files_in(dir.path()), 0u);
}

TEST(Report, PathfinderReportHasTheViewsTablesAndMachineReadableMetrics) {
  TempDir dir;
  const std::string folder = dir.file("report");
  const CommandResult r =
      run_roverlab("report " + quote(kPathfinder) + " -m wvu_pathfinder --size 640x400 -o " + quote(folder));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = read_text(folder + "/index.html");
  for (const char* s : {"<h2>Rover</h2>", "rover.png", "timeseries.png", "INS slip detection", "Slip classes",
                        "What the wheel odometry gets wrong", "turning track"}) {
    EXPECT_NE(html.find(s), std::string::npos) << s;
  }
  // The default plot is the INS slip against its reference (not the raw IMU): the slip plot is not drawn twice.
  EXPECT_EQ(html.find("slip.png"), std::string::npos);
  // Issue 32: the map, its own section, every track on it.
  EXPECT_NE(html.find("map.png"), std::string::npos);
  for (const char* f : {"rover.png", "map.png", "timeseries.png"}) {
    const views::Image img = views::read_png(folder + "/" + f);
    EXPECT_GT(distinct_colours(img), 20) << f;
  }
  const auto metrics = nlohmann::json::parse(read_text(folder + "/metrics.json"));
  const auto& ins = metrics.at("analyses").at("ins-slip");
  EXPECT_LT(ins.at("ins").at("final_position_error_m").get<double>(),
            ins.at("wheel_odometry").at("final_position_error_m").get<double>());
  EXPECT_EQ(metrics.at("analyses").at("odometry").at("cause"), "turning track");
  EXPECT_EQ(ins.at("slip_confusion").at("column_normalised").size(), 5u);
  // The report holds the very document `estimate ins-slip --json` and
  // `discrepancy odometry --json` print for the same log and options.
  for (const auto& [command, name] :
       {std::pair<std::string, std::string>{"estimate ins-slip", "ins-slip"}, {"discrepancy odometry", "odometry"}}) {
    const CommandResult cli = run_roverlab(command + " " + quote(kPathfinder) + " -m wvu_pathfinder --json");
    ASSERT_EQ(cli.exit_code, 0) << cli.err;
    EXPECT_EQ(nlohmann::json::parse(cli.out), metrics.at("analyses").at(name)) << command;
  }
  EXPECT_TRUE(fs::exists(folder + "/slip_confusion.csv"));
  EXPECT_TRUE(fs::exists(folder + "/odometry_candidates.csv"));
  // Issue 32: the answers come first (the odometry study's verdict in the
  // summary, before any picture), and the report says how it was made.
  const auto summary = html.find("<h2>Summary</h2>"), first_picture = html.find("<img");
  ASSERT_NE(summary, std::string::npos);
  EXPECT_LT(summary, first_picture);
  const std::string verdict = metrics.at("analyses").at("odometry").at("verdict").get<std::string>();
  const auto in_summary = html.find(verdict.substr(0, 60));
  EXPECT_GT(in_summary, summary);
  EXPECT_LT(in_summary, first_picture);
  EXPECT_EQ(metrics.at("summary").size(), 2u);  // ins-slip's key metrics and the odometry verdict
  EXPECT_NE(html.find("<h2>How this report was made</h2>"), std::string::npos);
  EXPECT_EQ(html.find("}<h1>"), std::string::npos);  // no style rule outside <style>
  EXPECT_NE(metrics.at("made_with").at("command").get<std::string>().find("--mapping wvu_pathfinder --size 640x400"),
            std::string::npos);
  // No temporary files left behind.
  for (const auto& e : fs::directory_iterator(folder)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  }
}

TEST(Report, SingleWheelReportHasBothSurfacesAndTheirCoefficients) {
  TempDir dir;
  const std::string folder = dir.file("r");
  const CommandResult r = run_roverlab("report " + quote(kData + "/single_wheel/ding2011_tyii.csv") +
                                       " --soil ding_tyii --size 640x480 -o " + quote(folder));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(folder + "/surface_drawbar-pull.png"));
  EXPECT_TRUE(fs::exists(folder + "/surface_torque.png"));
  const auto metrics = nlohmann::json::parse(read_text(folder + "/metrics.json"));
  EXPECT_EQ(metrics.at("traction_surface_drawbar-pull").at("coefficients").size(), 15u);  // order 4
  EXPECT_LT(metrics.at("traction_surface_drawbar-pull").at("fit_rmse").get<double>(), 1.0);
  // Issue 44: the single-wheel study's verdict opens it, the test (not a rover) is described, its panels drawn.
  EXPECT_FALSE(metrics.at("single_wheel").at("verdict").get<std::string>().empty());
  EXPECT_EQ(metrics.at("single_wheel").at("test").at("rows").get<int>(), 12);
  const std::string html = read_text(folder + "/index.html");
  EXPECT_LT(html.find("Verdict of the single-wheel study"), html.find("<h2>Summary"));
  EXPECT_NE(html.find("12 rows at loads 80 N"), std::string::npos);
  EXPECT_EQ(html.find("rover unnamed"), std::string::npos);
  EXPECT_TRUE(fs::exists(folder + "/slip_panels.png"));
  EXPECT_TRUE(fs::exists(folder + "/slip_angle_residuals.png"));
  // Issue 43: both families' studies held out, the one taken said (on Ding's clayey soil, Wong-Reece).
  const auto& families = metrics.at("single_wheel").at("families");
  ASSERT_EQ(families.size(), 2u);
  EXPECT_EQ(families[0].at("family"), "Wong-Reece");
  EXPECT_EQ(families[1].at("family"), "RFT");
  EXPECT_LT(families[0].at("final_held_out_score_sigma").get<double>(),
            families[1].at("final_held_out_score_sigma").get<double>());
  EXPECT_EQ(metrics.at("single_wheel").at("baseline_model"), "Wong-Reece");
  EXPECT_NE(html.find("Model families: family Wong-Reece: its final model"), std::string::npos);
  // 12 rows: every step's candidates fitted on all of them, and no note of a subset.
  EXPECT_EQ(metrics.at("single_wheel").at("step_screen_points").get<int>(), 0);
  EXPECT_EQ(html.find("random subset"), std::string::npos);
}

// Issue 46: a long file's forward steps are ranked on a subset of its rows
// (DiscrepancyOptions::step_screen_points); the report says so, as the CLI
// and its JSON do.
TEST(Report, ALongSingleWheelFileSaysItsStepsWereRankedOnASubset) {
  TempDir dir;
  const std::string ding = read_text(kData + "/single_wheel/ding2011_tyii.csv");
  std::istringstream lines(ding);
  std::string header, line;
  std::getline(lines, header);
  std::vector<std::vector<std::string>> rows;
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::istringstream cell(line);
    for (std::string c; std::getline(cell, c, ',');) cells.push_back(c);
    cells.resize(10);  // an empty last cell (a quantity not measured) reads as none
    rows.push_back(cells);
  }
  ASSERT_EQ(rows.size(), 12u);
  // 1,104 rows: Ding's 12 at loads of 60-100 N with +-3 % on the measured forces and sinkage.
  std::string csv = header + "\n";
  for (int i = 0; i < 1104; ++i) {
    std::vector<std::string> r = rows[static_cast<std::size_t>(i) % rows.size()];
    r[5] = std::to_string(60.0 + (i * 37 % 41));
    for (std::size_t k = 7; k < r.size(); ++k) {
      if (!r[k].empty()) r[k] = std::to_string(std::stod(r[k]) * (1.0 + 0.03 * std::sin(1.7 * i + k)));
    }
    for (std::size_t k = 0; k < r.size(); ++k) csv += (k ? "," : "") + r[k];
    csv += "\n";
  }
  write_text(dir.file("long.csv"), csv);
  const std::string folder = dir.file("r");
  const CommandResult r =
      run_roverlab("report " + quote(dir.file("long.csv")) + " --soil ding_tyii --size 320x240 -o " + quote(folder));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto metrics = nlohmann::json::parse(read_text(folder + "/metrics.json"));
  EXPECT_EQ(metrics.at("single_wheel").at("test").at("rows").get<int>(), 1104);
  EXPECT_EQ(metrics.at("single_wheel").at("step_screen_points").get<int>(), 1000);
  const std::string html = read_text(folder + "/index.html");
  EXPECT_NE(html.find("ranked on a random subset of 1000 of the 1104 rows"), std::string::npos);
}

TEST(Render, ContactAnglesPointWhereTheWheelsMove) {
  TempDir dir;
  const std::string sim = dir.file("rear.h5");
  // At the seed's 1 kHz (at 100 Hz the filter follows the turning bogie about 25 deg late).
  ASSERT_EQ(run_roverlab("scenario rear-bogie-rotation -o " + quote(sim)).exit_code, 0);
  // At 12 s the rear bogie turns: RL's velocity points down (about -50 deg),
  // RR's up (+50 deg); the other wheels roll level.
  const views::Image img = render(quote(sim) + " --view contact-angles -t 12 --size 1200x600", dir.file("ca.png"));
  auto blue = [](int r, int g, int b) { return b > 180 && r < 90 && g < 140; };
  // Side-view part of each panel (panels are 400 x 300: FL ML RL on top, FR MR RR below).
  auto centroid_y = [&](int panel_x, int panel_y) {
    return find_pixels(img, blue, panel_x, panel_x + 240, panel_y, panel_y + 270);
  };
  const Region fl = centroid_y(0, 0), rl = centroid_y(800, 0), fr = centroid_y(0, 300), rr = centroid_y(800, 300);
  for (const Region* r : {&fl, &rl, &fr, &rr}) EXPECT_GT(r->count, 300);
  EXPECT_GT(rl.mean_y - fl.mean_y, 12.0);   // RL arrow points down
  EXPECT_LT(rr.mean_y - fr.mean_y, -12.0);  // RR's arrow points up
  EXPECT_NEAR(fl.mean_y, 140.0, 12.0);      // FL's is level with the wheel centre
}

TEST(Render, PlanarRockerBogieIn3DShowsBothSidesWheelsOnTheTerrainSurface) {
  TempDir dir;
  const std::string sim = dir.file("rb.h5");
  ASSERT_EQ(run_roverlab("simulate bump_crossing --duration 30 -o " + quote(sim)).exit_code, 0);
  const views::Image img = render(quote(sim) + " --view rover -t 25 --size 800x400", dir.file("rb.png"));
  // Low-slip wheels (yellow-green) of both sides around the centre of the picture.
  const Region wheels = find_pixels(img, [](int r, int g, int b) { return g - b > 90 && g >= r && g > 120; });
  EXPECT_GT(wheels.count, 3000);
  EXPECT_NEAR(wheels.mean_x, 400, 60);
  const auto is_terrain = [](int r, int g, int b) {
    return r > 120 && r < 170 && g > 100 && g < 140 && b < 110 && r > g;
  };
  const Region terrain = find_pixels(img, is_terrain);
  // The terrain is a surface under the whole rover, not a line: larger than the wheels, centred on them.
  EXPECT_GT(terrain.count, 2 * wheels.count);
  EXPECT_NEAR(terrain.mean_x, wheels.mean_x, 80);
  EXPECT_NEAR(terrain.mean_y, wheels.mean_y, 60);
  // Both sides: wheels left and right of the picture's middle column of the rover.
  const Region left = find_pixels(
      img, [](int r, int g, int b) { return g - b > 90 && g >= r && g > 120; }, 0, static_cast<int>(wheels.mean_x));
  const Region right = find_pixels(
      img, [](int r, int g, int b) { return g - b > 90 && g >= r && g > 120; }, static_cast<int>(wheels.mean_x));
  EXPECT_GT(left.count, 1000);
  EXPECT_GT(right.count, 1000);
}

TEST(Report, FlyingRoverLogGetsTheContactAngleSection) {
  TempDir dir;
  const std::string sim = dir.file("rear.h5"), folder = dir.file("r");
  ASSERT_EQ(run_roverlab("scenario rear-bogie-rotation --rate 100 -o " + quote(sim)).exit_code, 0);
  const CommandResult r = run_roverlab("report " + quote(sim) + " --size 600x400 -o " + quote(folder));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(folder + "/contact_angles.png"));
  EXPECT_NE(read_text(folder + "/index.html").find("Contact-angle estimator"), std::string::npos);
  const auto metrics = nlohmann::json::parse(read_text(folder + "/metrics.json"));
  auto contact = metrics.at("analyses").at("contact-angle");
  ASSERT_EQ(contact.at("rms").at("contact_angle_deg").size(), 6u);
  // Wheels on the unmoved side bogies keep near-zero contact angles (reset).
  for (std::size_t w : {0u, 1u, 4u, 5u}) {
    EXPECT_LT(contact.at("rms").at("contact_angle_deg").at(w).get<double>(), 2.0) << w;
  }
  EXPECT_EQ(metrics.at("analyses").count("ins-slip"), 0u);  // not a skid-steer log
  // The model chosen by the data (the report's default --model auto), with its evidence.
  EXPECT_EQ(contact.at("model_selection").at("requested"), "auto");
  EXPECT_EQ(contact.at("model"), contact.at("model_selection").at("chosen"));  // at 100 Hz: c (1 kHz: c+ss)
  EXPECT_NE(read_text(folder + "/index.html").find("consistent candidate of least AIC"), std::string::npos);
  // The same document as the command line's for the same options (but for the wall-clock time).
  EXPECT_TRUE(contact.at("smoother").get<bool>());  // the report smooths; the filter's errors beside
  EXPECT_EQ(contact.at("filter_rms").at("slip").size(), 6u);
  const CommandResult cli =
      run_roverlab("estimate contact-angle " + quote(sim) + " --reset-cross-covariance --smoother --json");
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  auto printed = nlohmann::json::parse(cli.out);
  EXPECT_GT(contact.at("wall_seconds").get<double>(), 0.0);
  printed.erase("wall_seconds");
  contact.erase("wall_seconds");
  EXPECT_EQ(printed, contact);
}

// Issue 32: every file `convert`, `render` and `report` write, and the
// report's folder, have the mode the umask gives (they were 0600 whatever
// the umask: a shared folder or a web server could not serve a report).
TEST(Report, FilesOfConvertRenderAndReportHaveTheModeTheUmaskGives) {
  TempDir dir;
  for (const auto& [umask, file_mode, folder_mode] : {std::tuple{"022", 0644u, 0755u}, {"077", 0600u, 0700u}}) {
    const std::string h5 = dir.file(std::string("wvu") + umask + ".h5"),
                      png = dir.file(std::string("map") + umask + ".png"),
                      folder = dir.file(std::string("report") + umask);
    const std::string sh = std::string("umask ") + umask + " && " + quote(kExe);
    ASSERT_EQ(run_command(sh + " convert " + quote(kPathfinder) + " " + quote(h5) + " -m wvu_pathfinder").exit_code, 0);
    ASSERT_EQ(run_command(sh + " render " + quote(h5) + " --view map --size 320x200 -o " + quote(png)).exit_code, 0);
    ASSERT_EQ(run_command(sh + " report " + quote(h5) + " --size 320x200 -o " + quote(folder)).exit_code, 0);
    struct stat st {};
    std::vector<std::string> files = {h5, png};
    for (const auto& e : fs::directory_iterator(folder)) files.push_back(e.path().string());
    EXPECT_GE(files.size(), 8u);  // index.html, metrics.json, the pictures, the CSV tables
    for (const auto& f : files) {
      ASSERT_EQ(::stat(f.c_str(), &st), 0) << f;
      EXPECT_EQ(st.st_mode & 0777, file_mode) << f << " under umask " << umask;
    }
    ASSERT_EQ(::stat(folder.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, folder_mode) << folder;
  }
}

namespace {

// The row of the widest run of INS-blue pixels at least `min_run` long (the
// map's marker, a disc 14 px across; the track itself is 3 px wide), -1 if none.
int marker_row(const views::Image& img, int min_run) {
  int best_row = -1, best = 0;
  for (int y = 0; y < img.height; ++y) {
    int run = 0;
    for (int x = 0; x < img.width; ++x) {
      const unsigned char* p = img.pixel(x, y);
      run = (p[2] > 170 && p[0] < 70 && p[1] > 50 && p[1] < 130) ? run + 1 : 0;
      if (run >= min_run && run > best) {
        best = run;
        best_row = y;
      }
    }
  }
  return best_row;
}

}  // namespace

// Issue 32: the GUI's map pane follows the cursor: the INS marker of the WVU
// drive north sits lower in the window at 10 s than at 60 s (north is up).
TEST(Render, TheGuiMapPaneFollowsTheCursor) {
  TempDir dir;
  int rows[2] = {-1, -1};
  const double times[2] = {10.0, 60.0};
  for (int k = 0; k < 2; ++k) {
    const std::string png = dir.file("map" + std::to_string(k) + ".png");
    const CommandResult r = run_roverlab("gui " + quote(kPathfinder) + " -m wvu_pathfinder --tab Map --time " +
                                         std::to_string(times[k]) + " --screenshot " + quote(png));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    rows[k] = marker_row(views::read_png(png), 11);
  }
  ASSERT_GE(rows[0], 0) << "no marker at 10 s";
  ASSERT_GE(rows[1], 0) << "no marker at 60 s";
  // 50 s at about 0.5 m/s north: about 25 m, well over 150 pixels on a 34 m track 800 pixels high.
  EXPECT_GT(rows[0] - rows[1], 150);
}

namespace {

std::vector<double> values_of(const nlohmann::json& a) {
  std::vector<double> v;
  for (const auto& x : a) v.push_back(x.is_number() ? x.get<double>() : NAN);
  return v;
}

// RMS of v's finite values where keep(k).
double rms_where(const std::vector<double>& v, const std::function<bool(std::size_t)>& keep) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (!keep(k) || !std::isfinite(v[k])) continue;
    sum += v[k] * v[k];
    ++n;
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : NAN;
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

// Issue 32: the odometry study's residuals before and after the named cause,
// overlaid, against time and slip, in the report. On a skid-steer run whose
// left wheels are 4 % larger, the track error of the held-out part falls with
// the named cause, and the plotted series are the ones the study scored.
TEST(Report, OdometryResidualsBeforeAndAfterTheCauseArePlottedAgainstTimeAndSlip) {
  TempDir dir;
  const std::string log = dir.file("hidden.h5"), folder = dir.file("report");
  ASSERT_EQ(
      run_roverlab("scenario skid-steer-slip --effect left-radius-scale=1.04 --seed 3 -o " + quote(log)).exit_code, 0);
  const CommandResult r = run_roverlab("report " + quote(log) + " -o " + quote(folder));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(read_text(folder + "/metrics.json")).at("analyses").at("odometry");
  ASSERT_TRUE(doc.at("cause").is_string());
  const nlohmann::json& res = doc.at("residuals");
  const std::vector<double> t = values_of(res.at("time_s")), before = values_of(res.at("before_m")),
                            after = values_of(res.at("after_m")), slip = values_of(res.at("slip"));
  ASSERT_GT(t.size(), 100u);
  ASSERT_EQ(before.size(), t.size());
  ASSERT_EQ(after.size(), t.size());
  ASSERT_EQ(slip.size(), t.size());
  const double split = doc.at("split_time_s").get<double>();
  const auto held_out = [&](std::size_t k) { return t[k] > split; };
  const double rms_before = rms_where(before, held_out), rms_after = rms_where(after, held_out);
  // Decimated to at most 600 samples (of 1405 here), the plotted series give the study's held-out figures.
  EXPECT_EQ(doc.at("baseline").at("held_out_rmse_m"), res.at("held_out_rms_before_m"));
  EXPECT_NEAR(rms_before, res.at("held_out_rms_before_m").get<double>(), 0.01 * rms_before);
  EXPECT_NEAR(rms_after, res.at("held_out_rms_after_m").get<double>(), 0.01 * rms_after);
  EXPECT_LT(rms_after, 0.5 * rms_before);
  EXPECT_GT(std::count_if(slip.begin(), slip.end(), [](double s) { return std::isfinite(s); }), 50);
  const std::string html = read_text(folder + "/index.html");
  EXPECT_EQ(count_of(html, "<svg class=\"plot residual-plot\""), 2u);
  for (const char* label : {"time (s)", "position error (m)", "slip (1 - GPS speed / wheel speed)", "nominal geometry",
                            ">with per-side scale<", "held out"}) {
    EXPECT_NE(html.find(label), std::string::npos) << label;
  }
}

// The rover study's residual (RMS over channels in noise sigmas) before and
// after the named causes, against time and slip: on a run with 5 % larger
// wheels the residual after is a small part of the one before.
TEST(Report, RoverStudyResidualsBeforeAndAfterTheCausesArePlottedAgainstTimeAndSlip) {
  TempDir dir;
  const std::string log = dir.file("run.h5"), folder = dir.file("report");
  ASSERT_EQ(run_roverlab("simulate flat_60s --duration 30 --effect wheel-radius-scale=1.05 -o " + quote(log)).exit_code,
            0);
  const CommandResult r = run_roverlab("report " + quote(log) + " -o " + quote(folder));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(read_text(folder + "/metrics.json")).at("analyses").at("rover-discrepancy");
  ASSERT_FALSE(doc.at("causes").empty());
  const std::vector<double> t = values_of(doc.at("plot").at("time")), before = values_of(doc.at("plot").at("before")),
                            after = values_of(doc.at("plot").at("after"));
  ASSERT_GT(t.size(), 100u);
  const auto all = [](std::size_t) { return true; };
  EXPECT_LT(rms_where(after, all), 0.1 * rms_where(before, all));
  const std::string html = read_text(folder + "/index.html");
  EXPECT_EQ(count_of(html, "<svg class=\"plot residual-plot\""), 2u);
  for (const char* label : {"time (s)", "mean wheel slip (1)", "residual, RMS over channels (noise sigmas)",
                            "nominal model", "with wheel"}) {
    EXPECT_NE(html.find(label), std::string::npos) << label;
  }
  // Default plots chosen for what they show: the channel where the simulation disagrees most (RMSE in sigmas),
  // measured minus simulated, nominal and with the causes.
  std::string worst;
  double most = 0;
  for (const auto& c : doc.at("channels")) {
    const double sigmas = c.at("rmse").get<double>() / c.at("sigma").get<double>();
    if (sigmas > most) {
      most = sigmas;
      worst = c.at("stream").get<std::string>() + ":" + c.at("channel").get<std::string>();
    }
  }
  EXPECT_TRUE(fs::is_regular_file(folder + "/disagreement.png"));
  EXPECT_NE(html.find("largest RMSE in noise sigmas: " + worst + " (RMSE"), std::string::npos) << worst;
}
