// `roverlab campaign` run as a user runs it: the campaign file's checks, the
// dry run, a CI-sized campaign (the bundled log and four short simulated
// runs) that a second run leaves alone and that reruns only the run whose
// output was deleted, the campaign report's table against each run's JSON,
// and the same campaign twice giving the same numbers. Needs snakemake
// (scripts/install-deps); skipped, saying so, without it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace roverlab::test {
namespace {

using nlohmann::json;

const std::string kExe = ROVERLAB_EXE;

bool have_snakemake() { return run_command("command -v snakemake").exit_code == 0; }

// The bundled log and four short simulated runs: skid-steer drives on firm
// ground with and without an injected effect, and a flying-rover run at 100 Hz.
std::string ci_campaign(int flying_rate = 100) {
  return R"({"format": "roverlab-campaign", "version": 1, "name": "ci",
  "logs": [{"file": ")" +
         std::string(ROVERLAB_TEST_DATA) + R"(/test17run.mat", "mapping": "wvu_pathfinder"}],
  "simulations": [
    {"scenario": "skid-steer-slip", "seeds": [1], "effects": [{"slip": 0}, {"slip": 0, "left-radius-scale": 1.05},
                                                                {"slip": 0, "turning-track-factor": 1.3}]},
    {"scenario": "fl-bogie-rotation", "seeds": [1], "rate": )" +
         std::to_string(flying_rate) + R"(}]})";
}

json read_json(const fs::path& p) { return json::parse(read_text(p.string())); }

fs::file_time_type mtime(const fs::path& p) { return fs::last_write_time(p); }

// Drops wall-clock fields (wall_seconds) wherever they are.
json without_wall_clock(json j) {
  if (j.is_object()) {
    j.erase("wall_seconds");
    for (auto& [k, v] : j.items()) v = without_wall_clock(v);
  } else if (j.is_array()) {
    for (auto& v : j) v = without_wall_clock(v);
  }
  return j;
}

CommandResult campaign(const std::string& args) { return run_command(kExe + " campaign " + args); }

TEST(Campaign, ACampaignFileIsCheckedFieldByField) {
  TempDir dir;
  const auto check = [&](const std::string& text, const std::string& field, const std::string& why = "") {
    write_text(dir.file("c.json"), text);
    const CommandResult r = campaign(quote(dir.file("c.json")) + " -o " + quote(dir.file("out")));
    EXPECT_EQ(r.exit_code, 3) << text << "\n" << r.err;
    EXPECT_NE(r.err.find("c.json"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(field), std::string::npos) << "expected " << field << " in: " << r.err;
    EXPECT_NE(r.err.find(why), std::string::npos) << "expected " << why << " in: " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  };
  check(R"({"format": "roverlab-soil", "version": 1})", "roverlab-campaign");
  check(R"({"format": "roverlab-campaign", "version": 2, "simulations": []})", "version");
  check(R"({"format": "roverlab-campaign", "version": 1, "simulations": [{"scenario": "moon-walk"}]})",
        "simulations[0].scenario");
  check(R"({"format": "roverlab-campaign", "version": 1, "simulations": [{"scenario": "skid-steer-slip",
        "seeds": [1, -2]}]})",
        "simulations[0].seeds[1]");
  check(R"({"format": "roverlab-campaign", "version": 1, "simulations": [{"scenario": "skid-steer-slip",
        "seeds": {"first": 1, "count": 1e9}}]})",
        "simulations[0].seeds.count");
  check(R"({"format": "roverlab-campaign", "version": 1, "simulations": [{"scenario": "skid-steer-slip",
        "effects": [{}, {"left-radius-scale": 50}]}]})",
        "simulations[0].effects[1]");
  check(R"({"format": "roverlab-campaign", "version": 1, "simulations": [{"scenario": "fl-bogie-rotation",
        "rate": 5}]})",
        "simulations[0].rate");
  // The steering manoeuvre's options (issue 33): the bounds of `roverlab scenario`'s --turn-radius (|R| >= 1 m),
  // --slip-angle (+-45 deg) and --slip-angle-from (within the run: flat-turn lasts 30 s), and only for the
  // flying-rover scenarios.
  const std::string flat_turn = R"({"format": "roverlab-campaign", "version": 1, "simulations": [{"scenario": )"
                                R"("flat-turn", "seeds": [1], )";
  check(flat_turn + R"("turn_radius": 0.5}]})", "simulations[0].turn_radius", "at least 1 m");
  check(flat_turn + R"("turn_radius": -0.9}]})", "simulations[0].turn_radius", "at least 1 m");
  check(flat_turn + R"("slip_angle_deg": 46}]})", "simulations[0].slip_angle_deg", "+-45 deg");
  check(flat_turn + R"("slip_angle_deg": "2"}]})", "simulations[0].slip_angle_deg", "expected a number");
  check(flat_turn + R"("slip_angle_deg": 2, "slip_angle_from": 30}]})", "simulations[0].slip_angle_from",
        "within the run");
  check(flat_turn + R"("slip_angle_deg": 2, "slip_angle_from": -1}]})", "simulations[0].slip_angle_from",
        "within the run");
  // Without a slip angle the start has no effect (issue 47, F24).
  check(flat_turn + R"("slip_angle_from": 10}]})", "simulations[0].slip_angle_from", "needs slip_angle_deg");
  check(R"({"format": "roverlab-campaign", "version": 1, "simulations": [{"scenario": "skid-steer-slip",
        "slip_angle_deg": 2}]})",
        "simulations[0].slip_angle_deg", "skid-steer-slip has no slip_angle_deg option");
  check(R"({"format": "roverlab-campaign", "version": 1, "simulations": [{"simulate": "flat_60s",
        "turn_radius": 2}]})",
        "simulations[0].turn_radius", "only flying-rover scenarios take a turn_radius");
  check(R"({"format": "roverlab-campaign", "version": 1, "logs": [{"file": "nowhere.mat"}]})", "logs[0].file");
  check(R"({"format": "roverlab-campaign", "version": 1, "logs": [{"folder": "."}], "mapping": "x"})", "mapping");
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
  // Usage errors: no input, no output.
  EXPECT_EQ(campaign("-o " + quote(dir.file("out"))).exit_code, 2);
  EXPECT_EQ(campaign(quote(dir.file("c.json"))).exit_code, 2);
}

// A folder of logs that need a mapping, given without one, is refused before
// the workflow starts (issue 30), in one line naming the file and the option;
// a campaign file's log names its field.
TEST(Campaign, LogsThatNeedAMappingAreRefusedBeforeTheWorkflowStarts) {
  TempDir dir;
  fs::create_directories(dir.path() / "logs");
  fs::copy_file(std::string(ROVERLAB_TEST_DATA) + "/test17run.mat", dir.path() / "logs" / "run1.mat");
  const CommandResult folder = campaign(quote(dir.file("logs")) + " -o " + quote(dir.file("out")));
  EXPECT_EQ(folder.exit_code, 3) << folder.err;
  EXPECT_NE(folder.err.find("run1.mat"), std::string::npos) << folder.err;
  EXPECT_NE(folder.err.find("--mapping"), std::string::npos) << folder.err;
  EXPECT_EQ(std::count(folder.err.begin(), folder.err.end(), '\n'), 1) << folder.err;
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "Snakefile.json")) << "the workflow was prepared";
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "runs"));
  write_text(dir.file("c.json"), R"({"format": "roverlab-campaign", "version": 1, "logs": [{"file": ")" +
                                     dir.file("logs/run1.mat") + R"("}]})");
  const CommandResult file = campaign(quote(dir.file("c.json")) + " -o " + quote(dir.file("out2")));
  EXPECT_EQ(file.exit_code, 3) << file.err;
  EXPECT_NE(file.err.find("logs[0].mapping"), std::string::npos) << file.err;
  // With the mapping the folder passes the check (a dry run lists its run).
  const CommandResult mapped =
      campaign(quote(dir.file("logs")) + " --mapping wvu_pathfinder --dry-run -o " + quote(dir.file("out3")));
  EXPECT_EQ(mapped.err.find("needs a mapping"), std::string::npos) << mapped.err;
}

TEST(Campaign, WithoutSnakemakeItSaysSoInOneLine) {
  TempDir dir;
  write_text(dir.file("c.json"), ci_campaign());
  const CommandResult r = run_command("PATH=" + dir.path().string() + " " + kExe + " campaign " +
                                      quote(dir.file("c.json")) + " -o " + quote(dir.file("out")));
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("snakemake not found"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(Campaign, ADryRunListsWhatWouldRunAndRunsNothing) {
  if (!have_snakemake()) GTEST_SKIP() << "snakemake is not installed (scripts/install-deps installs it)";
  TempDir dir;
  write_text(dir.file("c.json"), ci_campaign());
  const CommandResult r = campaign(quote(dir.file("c.json")) + " -o " + quote(dir.file("out")) + " --dry-run");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string all = r.out + r.err;
  for (const char* rule : {"prepare_log", "report", "provenance", "campaign_report"}) {
    EXPECT_NE(all.find(rule), std::string::npos) << rule << " in:\n" << all;
  }
  EXPECT_NE(all.find("skid-steer-slip-seed1-left-radius-scale1.05-slip0"), std::string::npos) << all;
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "runs"));
}

// flat-turn and the steering manoeuvre (issue 33): two slip angles of one
// seed are two runs, each named by and run with its options; bump-crossing
// (45 s) takes a slip angle from 40 s that flat-turn (30 s) would refuse.
std::string manoeuvre_campaign() {
  return R"({"format": "roverlab-campaign", "version": 1, "name": "slip-angle",
  "simulations": [
    {"scenario": "flat-turn", "seeds": [1], "rate": 20, "turn_radius": 1.5, "slip_angle_deg": 2, "slip_angle_from": 10},
    {"scenario": "flat-turn", "seeds": [1], "rate": 20, "turn_radius": -2, "slip_angle_deg": -3},
    {"scenario": "bump-crossing", "seeds": [1], "rate": 20, "slip_angle_deg": 1, "slip_angle_from": 40}]})";
}

TEST(Campaign, AFlatTurnCampaignGivesEachRunItsManoeuvre) {
  if (!have_snakemake()) GTEST_SKIP() << "snakemake is not installed (scripts/install-deps installs it)";
  TempDir dir;
  write_text(dir.file("c.json"), manoeuvre_campaign());
  const CommandResult r = campaign(quote(dir.file("c.json")) + " -o " + quote(dir.file("out")) + " --dry-run");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const json items = read_json(dir.path() / "out" / "items.json").at("items");
  const std::map<std::string, std::vector<std::string>> expected = {
      {"flat-turn-seed1-turn-radius1.5-slip-angle2-slip-angle-from10",
       {"scenario", "flat-turn", "--seed", "1", "--rate", "20", "--turn-radius", "1.5", "--slip-angle", "2",
        "--slip-angle-from", "10", "-o", "{output}"}},
      {"flat-turn-seed1-turn-radius-2-slip-angle-3",
       {"scenario", "flat-turn", "--seed", "1", "--rate", "20", "--turn-radius", "-2", "--slip-angle", "-3", "-o",
        "{output}"}},
      {"bump-crossing-seed1-slip-angle1-slip-angle-from40",
       {"scenario", "bump-crossing", "--seed", "1", "--rate", "20", "--slip-angle", "1", "--slip-angle-from", "40",
        "-o", "{output}"}}};
  ASSERT_EQ(items.size(), expected.size()) << items.dump(1);
  for (const auto& [name, args] : expected) {
    ASSERT_TRUE(items.contains(name)) << name << " in " << items.dump(1);
    EXPECT_EQ(items.at(name).at("args").get<std::vector<std::string>>(), args) << name;
    EXPECT_NE((r.out + r.err).find("runs/" + name + "/log.h5"), std::string::npos) << name;
  }
}

// The campaign's log is the manoeuvre it asked for: the truth the scenario
// records (turn radius, slip angle, its start) and the wheels' true side-slip
// angle, 0 before 10 s and 2 deg = 0.0349 rad after.
TEST(Campaign, AFlatTurnRunSimulatesTheSlipAngleItWasGiven) {
  if (!have_snakemake()) GTEST_SKIP() << "snakemake is not installed (scripts/install-deps installs it)";
  TempDir dir;
  write_text(dir.file("c.json"), R"({"format": "roverlab-campaign", "version": 1, "simulations": [{"scenario": )"
                                 R"("flat-turn", "rate": 20, "turn_radius": 1.5, "slip_angle_deg": 2, )"
                                 R"("slip_angle_from": 10}]})");
  const fs::path out = dir.path() / "out";
  const CommandResult r = campaign(quote(dir.file("c.json")) + " -o " + quote(out.string()) + " --cores 2");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const fs::path run = out / "runs" / "flat-turn-seed1-turn-radius1.5-slip-angle2-slip-angle-from10";
  const std::string command = read_json(run / "run.json").at("commands").at(0).get<std::string>();
  EXPECT_NE(command.find("--turn-radius 1.5 --slip-angle 2 --slip-angle-from 10"), std::string::npos) << command;
  const CommandResult info = run_command(kExe + " info --json " + quote((run / "log.h5").string()));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const json log = json::parse(info.out);
  const json& truth = log.at("metadata").at("extra");
  EXPECT_DOUBLE_EQ(std::stod(truth.at("truth/turn_radius_m").get<std::string>()), 1.5);
  EXPECT_DOUBLE_EQ(std::stod(truth.at("truth/slip_angle_deg").get<std::string>()), 2.0);
  EXPECT_DOUBLE_EQ(std::stod(truth.at("truth/slip_angle_from_s").get<std::string>()), 10.0);
  int wheels = 0;
  for (const auto& stream : log.at("streams")) {
    if (stream.at("name") != "truth/wheels") continue;
    for (const auto& channel : stream.at("channels")) {
      if (channel.at("name").get<std::string>().rfind("side_slip_", 0) != 0) continue;
      EXPECT_NEAR(channel.at("min").get<double>(), 0.0, 1e-9) << channel.dump();
      EXPECT_NEAR(channel.at("max").get<double>(), 2.0 * M_PI / 180.0, 1e-6) << channel.dump();
      ++wheels;
    }
  }
  EXPECT_EQ(wheels, 6) << info.out.substr(0, 2000);
  EXPECT_TRUE(fs::exists(run / "report" / "metrics.json"));
}

class CampaignRun : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_snakemake()) GTEST_SKIP() << "snakemake is not installed (scripts/install-deps installs it)";
  }
  CommandResult run(const fs::path& out, int flying_rate = 100) {
    write_text(dir.file("c.json"), ci_campaign(flying_rate));
    return campaign(quote(dir.file("c.json")) + " -o " + quote(out.string()) + " --cores 2");
  }
  TempDir dir;
};

// The campaign report's table holds each run's numbers as its metrics.json and run.json say.
void expect_table_matches_runs(const fs::path& out) {
  const json report = read_json(out / "report" / "campaign.json");
  const std::string csv = read_text((out / "report" / "campaign.csv").string());
  const std::string html = read_text((out / "report" / "index.html").string());
  ASSERT_EQ(report.at("runs").size(), 5U);
  const std::map<std::string, std::pair<std::string, std::string>> pointers = {
      {"ins_final_error_m", {"ins-slip", "/ins/final_position_error_m"}},
      {"odometry_held_out_rmse_m", {"odometry", "/baseline/held_out_rmse_m"}},
      {"odometry_cause", {"odometry", "/cause"}},
      {"slip_class_accuracy", {"ins-slip", "/slip_confusion/accuracy"}}};
  int compared = 0;
  for (const auto& row : report.at("runs")) {
    const std::string name = row.at("name").get<std::string>();
    const fs::path run = out / "runs" / name;
    const json metrics = read_json(run / "report" / "metrics.json").at("analyses");
    const json provenance = read_json(run / "run.json");
    EXPECT_EQ(row.at("seed"), provenance.at("seed")) << name;
    EXPECT_EQ(row.at("effects"), provenance.at("effects")) << name;
    EXPECT_TRUE(fs::exists(out / "report" / row.at("report").get<std::string>())) << name;
    const std::size_t tr = html.find("<tr id=\"run-" + name + "\">");
    ASSERT_NE(tr, std::string::npos) << name;
    const std::string html_row = html.substr(tr, html.find("</tr>", tr) - tr);
    EXPECT_NE(csv.find("\n" + name + ","), std::string::npos) << name;
    for (const auto& [key, where] : pointers) {
      const json& cell = row.at("metrics").at(key);
      const json::json_pointer ptr(where.second);
      if (!metrics.contains(where.first) || !metrics.at(where.first).contains(ptr)) {
        EXPECT_TRUE(cell.is_null()) << name << " " << key;
        continue;
      }
      const json& truth = metrics.at(where.first).at(ptr);
      EXPECT_EQ(cell, truth.is_null() ? json(nullptr) : truth) << name << " " << key;
      if (truth.is_number()) {
        char shown[32];
        std::snprintf(shown, sizeof shown, "<td>%.4g</td>", truth.get<double>());
        EXPECT_NE(html_row.find(shown), std::string::npos) << name << " " << key << " " << shown;
        ++compared;
      } else if (truth.is_string()) {
        EXPECT_NE(html_row.find(truth.get<std::string>()), std::string::npos) << name << " " << key;
      }
    }
    // Provenance: version, the commands, the seed and the inputs' checksums.
    std::string version = run_command(kExe + " --version").out;
    version.erase(version.find_last_not_of(" \n") + 1);
    EXPECT_EQ(provenance.at("roverlab_version"), version);
    EXPECT_EQ(provenance.at("commands").size(), 2U);
    for (const auto& input : provenance.at("inputs")) EXPECT_EQ(input.at("sha256").get<std::string>().size(), 64U);
  }
  EXPECT_GE(compared, 10);
  // The skid-steer runs on firm ground make the named-vs-injected table.
  const json& confusion = report.at("confusion");
  EXPECT_EQ(confusion.at("injected").size(), 3U) << confusion.dump();
  EXPECT_NE(html.find("id=\"confusion\""), std::string::npos);
  // Bold has one meaning, said under the table (issue 48).
  EXPECT_NE(html.find("Bold: the cell where the named cause is the expected one"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "report" / "hist_ins_final_error_m.svg"));
}

TEST_F(CampaignRun, RunsOnceResumesAndRerunsOnlyWhatADeletedOutputNeeds) {
  const fs::path out = dir.path() / "out";
  CommandResult r = run(out);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  expect_table_matches_runs(out);
  const std::string flying = "fl-bogie-rotation-seed1", pathfinder = "test17run";
  const std::string firm = "skid-steer-slip-seed1-slip0";
  const auto log_time = mtime(out / "runs" / firm / "log.h5");
  const auto metrics_time = mtime(out / "runs" / flying / "report" / "metrics.json");
  const auto pathfinder_time = mtime(out / "runs" / pathfinder / "report" / "metrics.json");

  // A second run does nothing.
  r = run(out);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find("Nothing to be done"), std::string::npos) << r.out << r.err;
  EXPECT_EQ(mtime(out / "runs" / flying / "report" / "metrics.json"), metrics_time);

  // Deleting one run's report reruns that report (not its log) and the campaign report only.
  fs::remove(out / "runs" / firm / "report" / "metrics.json");
  r = run(out);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(mtime(out / "runs" / firm / "log.h5"), log_time);
  EXPECT_TRUE(fs::exists(out / "runs" / firm / "report" / "metrics.json"));
  EXPECT_EQ(mtime(out / "runs" / flying / "report" / "metrics.json"), metrics_time);
  EXPECT_EQ(mtime(out / "runs" / pathfinder / "report" / "metrics.json"), pathfinder_time);
  expect_table_matches_runs(out);

  // A changed input (one run's settings in the campaign file) reruns that run alone.
  const auto firm_metrics_time = mtime(out / "runs" / firm / "report" / "metrics.json");
  r = run(out, 50);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(mtime(out / "runs" / flying / "report" / "metrics.json"), metrics_time);
  EXPECT_NE(read_text((out / "runs" / flying / "run.json").string()).find("--rate 50"), std::string::npos);
  EXPECT_EQ(mtime(out / "runs" / firm / "report" / "metrics.json"), firm_metrics_time);
  EXPECT_EQ(mtime(out / "runs" / pathfinder / "report" / "metrics.json"), pathfinder_time);
}

TEST_F(CampaignRun, TheSameCampaignTwiceGivesTheSameNumbers) {
  const fs::path a = dir.path() / "a", b = dir.path() / "b";
  ASSERT_EQ(run(a).exit_code, 0);
  ASSERT_EQ(run(b).exit_code, 0);
  // wall_seconds (the contact-angle estimator's wall-clock time) is left out.
  EXPECT_EQ(read_json(a / "report" / "campaign.json"), read_json(b / "report" / "campaign.json"));
  for (const auto& run : fs::directory_iterator(a / "runs")) {
    const fs::path other = b / "runs" / run.path().filename();
    EXPECT_EQ(without_wall_clock(read_json(run.path() / "report" / "metrics.json")),
              without_wall_clock(read_json(other / "report" / "metrics.json")))
        << run.path().filename();
    EXPECT_EQ(read_json(run.path() / "run.json"), read_json(other / "run.json")) << run.path().filename();
  }
}

}  // namespace
}  // namespace roverlab::test
