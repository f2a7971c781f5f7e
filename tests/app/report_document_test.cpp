// The report as a document (issue 32), run as a user runs it on the bundled
// WVU log and a simulated rocker-bogie run: the first section gives the run
// (rover, duration, distance, where) as an independent computation from the
// streams (`convert --stream` to CSV) finds it; the provenance block gives
// the program, the command, each analysis's settings and the inputs' SHA-256
// (checked against `sha256sum`); the study tables are the very cells
// Presentation::tables() gives the GUI; a raw log's default plot shows rates and
// speeds that follow the motion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/analysis.h"
#include "app/command_support.h"
#include "app/log_input.h"
#include "core/discrepancy/likelihood.h"
#include "test_support.h"
#include "views/timeseries_chart.h"

using namespace roverlab;
using namespace roverlab::test;
using nlohmann::json;

namespace {

const std::string kExe = ROVERLAB_EXE;
const std::string kData = ROVERLAB_TEST_DATA;
const std::string kPathfinder = kData + "/test17run.mat";

CommandResult run_roverlab(const std::string& args) { return run_command(quote(kExe) + " " + args); }

// A stream as `convert --stream` writes it: the header's names (without units) and the columns.
struct Csv {
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
  const std::vector<double>& operator[](const std::string& name) const {
    const auto at = std::find(names.begin(), names.end(), name);
    EXPECT_NE(at, names.end()) << name;
    return columns.at(static_cast<std::size_t>(at - names.begin()));
  }
};

Csv stream_csv(const std::string& log, const std::string& extra, const std::string& stream, const TempDir& dir) {
  const std::string out = dir.file("stream.csv");
  const CommandResult r = run_roverlab("convert " + quote(log) + " " + quote(out) + extra + " --stream " + stream);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::istringstream in(read_text(out));
  Csv csv;
  std::string line, cell;
  std::getline(in, line);
  std::istringstream header(line);
  while (std::getline(header, cell, ',')) csv.names.push_back(cell.substr(0, cell.find(" [")));
  csv.columns.resize(csv.names.size());
  while (std::getline(in, line)) {
    std::istringstream row(line);
    for (std::size_t k = 0; std::getline(row, cell, ','); ++k) csv.columns.at(k).push_back(std::stod(cell));
  }
  return csv;
}

// Path length of (a, b): the sum of the steps between samples.
double path_length(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0;
  for (std::size_t k = 1; k < a.size(); ++k) sum += std::hypot(a[k] - a[k - 1], b[k] - b[k - 1]);
  return sum;
}

std::string unescape(std::string s) {
  for (const auto& [from, to] :
       std::vector<std::pair<std::string, std::string>>{{"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}}) {
    for (std::size_t at; (at = s.find(from)) != std::string::npos;) s.replace(at, from.size(), to);
  }
  return s;
}

// The cells of the report's table captioned `title`, row by row (the heading row left out); empty when absent.
std::vector<std::vector<std::string>> html_table(const std::string& html, const std::string& title) {
  std::vector<std::vector<std::string>> rows;
  const auto start = html.find("<caption>" + app::ReportSection::escape(title) + "</caption>");
  if (start == std::string::npos) return rows;
  const std::string table = html.substr(start, html.find("</table>", start) - start);
  for (std::size_t tr = table.find("<tr"); tr != std::string::npos; tr = table.find("<tr", tr + 1)) {
    const std::string row = table.substr(tr, table.find("</tr>", tr) - tr);
    std::vector<std::string> cells;
    for (std::size_t td = row.find("<td"); td != std::string::npos; td = row.find("<td", td + 1)) {
      const auto open = row.find('>', td) + 1;
      cells.push_back(unescape(row.substr(open, row.find("</td>", open) - open)));
    }
    if (!cells.empty()) rows.push_back(cells);
  }
  return rows;
}

struct Report {
  std::string html;
  json metrics, provenance;
};

// Reports made once for all the tests: the WVU log and a simulated run with 5 % larger wheels.
class ReportDocument : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    sim_log_ = dir_->file("sim.h5");
    ASSERT_EQ(run_roverlab("simulate flat_60s --duration 30 --effect wheel-radius-scale=1.05 -o " + quote(sim_log_))
                  .exit_code,
              0);
    for (const auto& [name, args] : std::vector<std::pair<std::string, std::string>>{
             {"wvu", quote(kPathfinder) + " -m wvu_pathfinder"}, {"sim", quote(sim_log_)}}) {
      const std::string folder = dir_->file(name);
      const CommandResult r = run_roverlab("report " + args + " --size 640x400 -o " + quote(folder));
      ASSERT_EQ(r.exit_code, 0) << r.err;
      reports()[name] = {read_text(folder + "/index.html"), json::parse(read_text(folder + "/metrics.json")),
                         json::parse(read_text(folder + "/provenance.json"))};
    }
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::map<std::string, Report>& reports() {
    static std::map<std::string, Report> made;
    return made;
  }
  static const Report& report(const std::string& name) { return reports().at(name); }
  static TempDir* dir_;
  static std::string sim_log_;
};

TempDir* ReportDocument::dir_ = nullptr;
std::string ReportDocument::sim_log_;

}  // namespace

// The WVU log: rover, duration of the measured streams, the GPS track's path
// length, the first fix in degrees, all in the summary before any picture.
TEST_F(ReportDocument, TheFirstSectionGivesTheRunOfTheWvuLog) {
  const Report& r = report("wvu");
  const json& run = r.metrics.at("run");
  EXPECT_EQ(run.at("rover"), "wvu_pathfinder");
  TempDir dir;
  double start = HUGE_VAL, end = -HUGE_VAL;
  for (const char* s : {"imu", "wheels", "gps", "odometry"}) {
    const Csv c = stream_csv(kPathfinder, " -m wvu_pathfinder", s, dir);
    start = std::min(start, c["time"].front());
    end = std::max(end, c["time"].back());
  }
  EXPECT_NEAR(run.at("duration_s").get<double>(), end - start, 1e-9);
  const Csv gps = stream_csv(kPathfinder, " -m wvu_pathfinder", "gps", dir);
  const double distance = path_length(gps["east"], gps["north"]);
  EXPECT_GT(distance, 30.0);  // 34 m north, a few turns
  EXPECT_NEAR(run.at("distance_m").get<double>(), distance, 1e-9 * distance);
  EXPECT_EQ(run.at("distance_source"), "gps");  // no truth; GPS before the INS and the odometry
  EXPECT_NEAR(run.at("start").at("latitude_deg").get<double>(), gps["latitude"].front() * 180 / M_PI, 1e-9);
  EXPECT_NEAR(run.at("start").at("longitude_deg").get<double>(), gps["longitude"].front() * 180 / M_PI, 1e-9);
  char line[160];
  std::snprintf(line, sizeof line, "rover wvu_pathfinder; %.3g s; %.3g m travelled along the GPS track (stream gps)",
                end - start, distance);
  const auto at = r.html.find(line), summary = r.html.find("<h2>Summary</h2>");
  ASSERT_NE(at, std::string::npos) << line;
  EXPECT_GT(at, summary);
  EXPECT_LT(at, r.html.find("<img"));
  char where[64];
  std::snprintf(where, sizeof where, "starting at %.5f&deg; N, %.5f&deg; W", gps["latitude"].front() * 180 / M_PI,
                -gps["longitude"].front() * 180 / M_PI);
  EXPECT_NE(r.html.find(where), std::string::npos) << where;
}

// A simulated planar run: its truth's path length in x and z, the local frame.
TEST_F(ReportDocument, TheFirstSectionGivesTheRunOfASimulatedLog) {
  const Report& r = report("sim");
  const json& run = r.metrics.at("run");
  EXPECT_EQ(run.at("rover"), "kapvik_planar");
  TempDir dir;
  const Csv truth = stream_csv(sim_log_, "", "truth/pose", dir);
  const double distance = path_length(truth["x"], truth["z"]);
  EXPECT_GT(distance, 0.3);
  EXPECT_NEAR(run.at("distance_m").get<double>(), distance, 1e-9 * distance);
  EXPECT_EQ(run.at("distance_source"), "truth/pose");
  EXPECT_NEAR(run.at("duration_s").get<double>(), truth["time"].back() - truth["time"].front(), 1e-9);
  EXPECT_EQ(run.at("start"), "local frame");
  EXPECT_NE(r.html.find("m travelled along the simulated planar truth (stream truth/pose)"), std::string::npos);
  EXPECT_NE(r.html.find("local frame (no GPS fix)"), std::string::npos);
}

// The provenance block: the program as a stored result names it, the
// command, each analysis's settings and measurements, each input file's
// SHA-256 as sha256sum computes it.
TEST_F(ReportDocument, TheProvenanceBlockNamesTheProgramCommandSettingsAndChecksums) {
  // A fixture of known digest (FIPS 180-2, appendix B.1: "abc").
  TempDir dir;
  write_text(dir.file("abc"), "abc");
  EXPECT_EQ(app::sha256_of_file(dir.file("abc")), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(app::sha256_of_file(dir.file("no such file")), "");
  const Report& r = report("wvu");
  const json& made = r.provenance;
  ASSERT_EQ(made.at("inputs").size(), 2u);  // the log and the mapping
  for (const auto& input : made.at("inputs")) {
    const std::string path = input.at("path").get<std::string>();
    const CommandResult sum = run_command("sha256sum " + quote(path));
    ASSERT_EQ(sum.exit_code, 0) << sum.err;
    const std::string digest = sum.out.substr(0, 64);
    EXPECT_EQ(input.at("sha256"), digest) << path;
    EXPECT_NE(r.html.find("SHA-256 <code>" + digest + "</code>"), std::string::npos) << path;
  }
  EXPECT_EQ(made.at("inputs")[0].at("path"), kPathfinder);
  EXPECT_NE(made.at("inputs")[1].at("path").get<std::string>().find("wvu_pathfinder.json"), std::string::npos);
  // The program: its version and build, as each analysis's document names it.
  std::string version = run_roverlab("--version").out;
  version.erase(version.find_last_not_of(" \n") + 1);
  const std::string program = made.at("program").get<std::string>();
  EXPECT_EQ(program.rfind(version, 0), 0u) << program;
  EXPECT_NE(r.html.find("<th>RoverLab</th><td style=\"text-align:left\">" + program), std::string::npos);
  // The command as run, word for word.
  EXPECT_EQ(made.at("command_run").get<std::string>(),
            kExe + " report " + kPathfinder + " -m wvu_pathfinder --size 640x400 -o " + dir_->file("wvu"));
  // Every analysis's configuration and input, as its result document holds them.
  const json& analyses = r.metrics.at("analyses");
  ASSERT_EQ(made.at("analyses").size(), analyses.size());
  for (const auto& [name, doc] : analyses.items()) {
    EXPECT_EQ(made.at("analyses").at(name).at("configuration"), doc.at("configuration")) << name;
    EXPECT_EQ(made.at("analyses").at(name).at("input"), doc.at("input")) << name;
    EXPECT_EQ(doc.at("input").at("program"), program) << name;
  }
  EXPECT_NE(r.html.find("fit_fraction 0.5"), std::string::npos);  // the odometry study's setting
  // metrics.json names the program too; the checksums only in provenance.json (a log written twice differs).
  EXPECT_EQ(r.metrics.at("made_with").at("program"), program);
  const json files = r.metrics.at("files");
  EXPECT_NE(std::find(files.begin(), files.end(), "provenance.json"), files.end());
}

// The study tables in the report are Presentation::tables() cell for cell (one
// writer for the GUI and the report), candidates by evidence.
TEST_F(ReportDocument, StudyTablesAreTheGuiTablesCellForCellSortedByEvidence) {
  std::size_t compared = 0;
  for (const char* which : {"wvu", "sim"}) {
    const Report& r = report(which);
    for (const auto& [name, doc] : r.metrics.at("analyses").items()) {
      const std::unique_ptr<app::Analysis> a = app::make_analysis(name);
      ASSERT_NE(a, nullptr) << name;
      if (name != "odometry" && name != "rover-discrepancy") continue;
      const std::vector<app::ResultTable> tables = a->presentation().tables(doc);
      ASSERT_FALSE(tables.empty()) << name;
      for (const app::ResultTable& t : tables) {
        const auto cells = html_table(r.html, t.title);
        ASSERT_EQ(cells.size(), t.rows.size()) << t.title;
        for (std::size_t i = 0; i < t.rows.size(); ++i) {
          ASSERT_EQ(cells[i].size(), t.rows[i].size()) << t.title << " row " << i;
          for (std::size_t k = 0; k < t.rows[i].size(); ++k) {
            EXPECT_EQ(cells[i][k], t.rows[i][k].text) << t.title << " row " << i << " column " << k;
          }
        }
        ++compared;
      }
      // Candidates by evidence: delta BIC never falls after the nominal row.
      const app::ResultTable& candidates = tables.front();
      const auto column = static_cast<std::size_t>(
          std::find(candidates.columns.begin(), candidates.columns.end(), "delta BIC") - candidates.columns.begin());
      ASSERT_LT(column, candidates.columns.size());
      std::vector<double> delta;
      for (const auto& c : doc.at("candidates")) delta.push_back(c.at("delta_bic").get<double>());
      std::sort(delta.begin(), delta.end());
      ASSERT_EQ(candidates.rows.size(), delta.size() + 1);
      for (std::size_t i = 0; i < delta.size(); ++i) {
        EXPECT_EQ(candidates.rows[i + 1][column].text, analysis::format_delta_bic(delta[i])) << name << " " << i;
      }
      // Units in the headings.
      EXPECT_TRUE(std::any_of(candidates.columns.begin(), candidates.columns.end(),
                              [](const std::string& c) { return c.find('(') != std::string::npos; }));
    }
  }
  EXPECT_EQ(compared, 3u);  // the odometry candidates; the rover study's candidates and checks
}

// A raw log (no estimates): the default plot shows rates and speeds that
// follow the motion, never the raw IMU's specific force, a wheel angle or a
// position ramp. WVU: the odometry's forward speed and yaw rate and the
// gyro's yaw rate (the rover turns); the simulated run: its wheel rates and
// velocimeter.
TEST_F(ReportDocument, TheDefaultPlotOfARawLogShowsWhatFollowsTheMotion) {
  const auto names = [](const std::vector<views::ChannelRef>& cs) {
    std::vector<std::string> out;
    for (const auto& c : cs) out.push_back(c.stream + ":" + c.channel);
    return out;
  };
  const io::LoadedLog wvu = app::load_input(kPathfinder, std::string("wvu_pathfinder"));
  const std::vector<std::string> chosen = names(views::default_channels(wvu.log));
  EXPECT_EQ(chosen, (std::vector<std::string>{"odometry:forward_speed", "odometry:yaw_rate", "imu:angular_rate_z"}));
  const io::LoadedLog sim = app::load_input(sim_log_, std::nullopt);
  const std::vector<std::string> sim_chosen = names(views::default_channels(sim.log));
  EXPECT_NE(std::find(sim_chosen.begin(), sim_chosen.end(), "velocimeter:forward_speed"), sim_chosen.end());
  for (const auto* list : {&chosen, &sim_chosen}) {
    for (const auto& c : *list) {
      EXPECT_EQ(c.find("specific_force"), std::string::npos) << c;
      EXPECT_EQ(c.find("angle"), std::string::npos) << c;
      EXPECT_EQ(c.find("gps:"), std::string::npos) << c;
    }
  }
}
