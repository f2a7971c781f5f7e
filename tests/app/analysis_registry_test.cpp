// The analysis registry (app/analyses/analyses.def): every entry well formed,
// and the text, the report and --json all read the one result document.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

#include <CLI/CLI.hpp>

#include "app/analysis.h"
#include "app/resources.h"
#include "app/rover_scenario.h"
#include "core/simulation/rocker_bogie.h"
#include "core/simulation/skid_steer_scenario.h"
#include "importers/scenario_file.h"

namespace roverlab {
namespace {

TEST(AnalysisRegistry, EveryEntryIsWellFormedAndSaysWhatAnEmptyLogLacks) {
  const app::Analyses all = app::all_analyses();
  ASSERT_GE(all.size(), 3u);
  std::set<std::string> names, commands;
  const log::Log empty;
  for (const auto& a : all) {
    EXPECT_TRUE(names.insert(a->name()).second) << a->name();
    EXPECT_TRUE(commands.insert(a->identity().command).second) << a->identity().command;
    const std::string& command = a->identity().command;
    EXPECT_TRUE(command.rfind("estimate ", 0) == 0 || command.rfind("discrepancy ", 0) == 0) << command;
    EXPECT_FALSE(a->identity().title.empty());
    EXPECT_FALSE(a->missing(empty).empty()) << a->name();
    EXPECT_FALSE(a->runs_on_open(empty)) << a->name();
    EXPECT_EQ(app::make_analysis(a->name())->name(), a->name());
  }
  EXPECT_EQ(app::make_analysis("no-such-analysis"), nullptr);
}

TEST(AnalysisRegistry, TextAndReportAreWrittenFromTheResultDocument) {
  const log::Log lg = simulation::simulate_skid_steer(simulation::default_slip_scenario(2));
  const std::unique_ptr<app::Analysis> ins = app::make_analysis("ins-slip");
  ASSERT_TRUE(ins->missing(lg).empty()) << ins->missing(lg);
  ASSERT_TRUE(ins->runs_on_open(lg));
  const app::AnalysisResult r = ins->run({lg, "sim.h5", {}});
  EXPECT_NE(r.estimates.find_stream("estimate/ins/slip"), nullptr);
  ASSERT_TRUE(r.document.contains("slip_confusion"));
  const double accuracy = r.document.at("slip_confusion").at("accuracy").get<double>();
  char expected[64];
  std::snprintf(expected, sizeof expected, "overall accuracy %.1f %%", 100.0 * accuracy);
  EXPECT_NE(app::printed(*ins, r.document).find(expected), std::string::npos);
  // Change the document: the text follows it, not the estimator's internals.
  nlohmann::json edited = r.document;
  edited["duration_s"] = 1234.5;
  EXPECT_NE(app::printed(*ins, edited).find("1234.5 s of IMU data"), std::string::npos);
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "roverlab_analysis_registry_test";
  std::filesystem::create_directories(folder);
  app::ReportSection section(folder);
  ins->presentation().report(edited, section);
  EXPECT_NE(section.html.str().find("Slip classes"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(folder / "slip_confusion.csv"));
  std::filesystem::remove_all(folder);
  // The GUI's tables come from the document too: each confusion cell is the
  // column-normalised fraction in per cent, tinted by it.
  edited["slip_confusion"]["column_normalised"][1][2] = 0.4321;
  const std::vector<app::ResultTable> tables = ins->presentation().tables(edited);
  ASSERT_FALSE(tables.empty());
  const app::ResultTable& t = tables.front();
  EXPECT_EQ(t.columns.size(), edited.at("slip_confusion").at("classes").size());
  EXPECT_EQ(t.row_names, t.columns);
  ASSERT_EQ(t.rows.size(), t.columns.size());
  EXPECT_EQ(t.rows[1][2].text, "43.2 %");
  EXPECT_DOUBLE_EQ(t.rows[1][2].shade, 0.4321);
  nlohmann::json without = edited;
  without.erase("slip_confusion");
  without.erase("slip_confusion_moving");
  EXPECT_TRUE(ins->presentation().tables(without).empty());
}

// What an analysis adds and how it shows a result are stated apart from what
// it computes: every stream a run adds lies under a prefix its identity names
// (the views run it by those names), and its presentation gives one document
// the same text whatever settings its analysis ran with.
TEST(AnalysisRegistry, ItAddsOnlyTheStreamsItNamesAndShowsADocumentWhateverItsSettings) {
  for (const auto& a : app::all_analyses()) {
    for (const std::string& prefix : a->identity().estimate_streams)
      EXPECT_EQ(prefix.rfind("estimate/", 0), 0u) << a->name() << ": " << prefix;
  }
  const log::Log lg = simulation::simulate_skid_steer(simulation::default_slip_scenario(2));
  const std::unique_ptr<app::Analysis> ins = app::make_analysis("ins-slip");
  const app::AnalysisResult r = ins->run({lg, "sim.h5", {}});
  ASSERT_TRUE(ins->adds_streams());
  ASSERT_FALSE(r.estimates.streams().empty());
  const std::vector<std::string>& prefixes = ins->identity().estimate_streams;
  for (const auto& s : r.estimates.streams()) {
    EXPECT_TRUE(
        std::any_of(prefixes.begin(), prefixes.end(), [&](const std::string& p) { return s.name().rfind(p, 0) == 0; }))
        << s.name() << " is under none of the prefixes the analysis names";
  }
  const std::unique_ptr<app::Analysis> other = app::make_analysis("ins-slip");
  CLI::App options;
  other->declare(options);
  options.parse("--no-zupt --no-smoother", false);
  ASSERT_NE(other->configuration(), ins->configuration());
  EXPECT_EQ(app::printed(*other, r.document), app::printed(*ins, r.document));
  EXPECT_FALSE(app::make_analysis("odometry")->adds_streams());
}

// A campaign's columns come from the analyses: unique keys, and each numeric
// metric of the INS analysis found in a real result document.
TEST(AnalysisRegistry, KeyMetricsAreUniqueAndPointIntoTheResultDocument) {
  std::set<std::string> keys;
  for (const auto& analysis : app::all_analyses()) {
    for (const auto& m : analysis->presentation().key_metrics()) {
      EXPECT_TRUE(keys.insert(m.key).second) << "key metric " << m.key << " twice";
      EXPECT_EQ(m.pointer.rfind('/', 0), 0u) << m.pointer;
      EXPECT_EQ(m.key.find("wall"), std::string::npos) << "a wall-clock key metric: " << m.key;
    }
  }
  EXPECT_GE(keys.size(), 6u);
  const log::Log lg = simulation::simulate_skid_steer(simulation::default_slip_scenario(3));
  const std::unique_ptr<app::Analysis> ins = app::make_analysis("ins-slip");
  const app::AnalysisResult r = ins->run({lg, "sim.h5", {}});
  for (const auto& m : ins->presentation().key_metrics()) {
    const nlohmann::json::json_pointer at(m.pointer);
    ASSERT_TRUE(r.document.contains(at)) << m.pointer;
    EXPECT_TRUE(r.document.at(at).is_number()) << m.pointer;
  }
}

// A result stored with the log (estimate X -o) is reused only when the
// measurements and the settings are those it was made from, by this build:
// estimate streams added later do not matter, a changed sample or option or
// another build does.
TEST(AnalysisRegistry, AStoredResultIsReusedOnlyForTheSameMeasurementsAndSettings) {
  const log::Log measured = simulation::simulate_skid_steer(simulation::default_slip_scenario(4));
  const std::unique_ptr<app::Analysis> ins = app::make_analysis("ins-slip");
  app::AnalysisResult r = app::run_analysis(*ins, {measured, "sim.h5", {}});
  ASSERT_TRUE(r.document.contains("configuration"));
  EXPECT_EQ(r.document.at("configuration").at("smoother"), true);
  EXPECT_EQ(r.document.at("input").at("fingerprint"), app::log_fingerprint(measured));
  app::store_result(*ins, r.document, r.estimates);
  log::Log stored = measured;
  for (const auto& s : r.estimates.streams()) stored.add_stream(s);
  stored.metadata.results = r.estimates.metadata.results;
  EXPECT_EQ(app::log_fingerprint(stored), app::log_fingerprint(measured));  // estimate/ streams left out
  const std::optional<nlohmann::json> again = app::stored_result(*ins, stored);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(app::without_run_details(*again), app::without_run_details(r.document));

  // Another setting: run again.
  const std::unique_ptr<app::Analysis> other = app::make_analysis("ins-slip");
  CLI::App options;
  other->declare(options);
  options.parse("--no-zupt", false);
  EXPECT_FALSE(app::stored_result(*other, stored).has_value());
  // Another measurement (one IMU sample): run again.
  log::Log changed;
  changed.metadata = stored.metadata;
  for (const auto& s : stored.streams()) {
    log::Stream copy = s;
    if (s.name() == "imu") {
      log::Stream edited(s.name(), s.time());
      for (const auto& c : s.channels()) {
        std::vector<double> v = c.values;
        if (c.name == s.channels().front().name) v[v.size() / 2] += 1e-3;
        edited.add_channel(c.name, c.unit, v, c.description);
      }
      copy = edited;
    }
    changed.add_stream(copy);
  }
  EXPECT_NE(app::log_fingerprint(changed), app::log_fingerprint(stored));
  EXPECT_FALSE(app::stored_result(*ins, changed).has_value());
  // Made by another build of RoverLab (another candidate pool, another fix): run again.
  EXPECT_EQ(r.document.at("input").at("program"), app::program_identity());
  EXPECT_GT(app::program_identity().size(), std::string("0.1.0+").size());  // the build id is found
  nlohmann::json elsewhere = r.document;
  elsewhere["input"]["program"] = "0.1.0+0123456789abcdef";
  stored.metadata.results["ins-slip"] = elsewhere.dump();
  EXPECT_FALSE(app::stored_result(*ins, stored).has_value());
  // A damaged stored document: run again.
  stored.metadata.results["ins-slip"] = "{not json";
  EXPECT_FALSE(app::stored_result(*ins, stored).has_value());
}

// A 20 s flat run simulated from scenario NAME, its metadata as `simulate` writes it.
log::Log simulated_from(const std::string& name) {
  analysis::RoverScenarioModel model = app::load_rover_scenario(name);
  model.run.duration = 20;
  simulation::RockerBogieResult r = simulation::simulate_rocker_bogie(model.geometry, model.parameters, model.run);
  r.log.metadata.extra["scenario"] = name;
  r.log.metadata.extra["scenario_json"] = io::find_scenario(name, app::resource_subfolders("scenarios")).document;
  return std::move(r.log);
}

// The rover study with its options (empty: the scenario the log records).
std::unique_ptr<app::Analysis> rover_study(const std::string& options) {
  std::unique_ptr<app::Analysis> a = app::make_analysis("rover-discrepancy");
  CLI::App cmd;
  a->declare(cmd);
  cmd.parse(options, false);
  return a;
}

// Issue 46: settings are compared as they resolve, not as they were typed:
// a result stored by `discrepancy rover LOG --scenario flat_60s -o` is reused
// when the scenario is inferred from the log, and the other way round; a
// scenario file with the same content under another name and description is
// the same scenario; one with another speed is not.
TEST(AnalysisRegistry, AStoredResultIsReusedWhetherItsScenarioIsNamedOrInferred) {
  const log::Log measured = simulated_from("flat_60s");
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("roverlab_reuse_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  nlohmann::json content = nlohmann::json::parse(measured.metadata.extra.at("scenario_json"));
  content["name"] = "flat_again";
  content["description"] = "the same run, named otherwise";
  const std::string same = (dir / "flat_again.json").string(), faster = (dir / "faster.json").string();
  std::ofstream(same) << content.dump(2);
  content["desired_speed_mps"] = 0.03;
  std::ofstream(faster) << content.dump(2);

  const std::vector<std::string> forms = {"", "--scenario flat_60s"};
  for (const std::string& stored_by : forms) {
    std::unique_ptr<app::Analysis> writer = rover_study(stored_by);
    app::AnalysisResult r = app::run_analysis(*writer, {measured, "run.h5", {}});
    log::Log stored = measured;
    app::store_result(*writer, r.document, stored);
    for (const std::string& read_by : forms) {
      const std::optional<nlohmann::json> again = app::stored_result(*rover_study(read_by), stored);
      ASSERT_TRUE(again.has_value()) << "stored with '" << stored_by << "', read with '" << read_by << "'";
      EXPECT_EQ(app::without_run_details(*again), app::without_run_details(r.document));
    }
    EXPECT_TRUE(app::stored_result(*rover_study("--scenario " + same), stored).has_value()) << stored_by;
    EXPECT_FALSE(app::stored_result(*rover_study("--scenario " + faster), stored).has_value()) << stored_by;
    EXPECT_FALSE(app::stored_result(*rover_study("--scenario rolling_200s"), stored).has_value()) << stored_by;
    EXPECT_FALSE(app::stored_result(*rover_study("--scenario flat_60s --block 2"), stored).has_value()) << stored_by;
    // A scenario that cannot be found: not reused (running it says why), never thrown here.
    EXPECT_FALSE(app::stored_result(*rover_study("--scenario no_such_scenario"), stored).has_value()) << stored_by;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace roverlab
