// The analysis registry (app/analyses/analyses.def): every entry well formed,
// and the text, the report and --json all read the one result document.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "app/analysis.h"
#include "core/simulation/skid_steer_scenario.h"

namespace roverlab {
namespace {

TEST(AnalysisRegistry, EveryEntryIsWellFormedAndSaysWhatAnEmptyLogLacks) {
  const app::Analyses all = app::all_analyses();
  ASSERT_GE(all.size(), 3u);
  std::set<std::string> names, commands;
  const log::Log empty;
  for (const auto& a : all) {
    EXPECT_TRUE(names.insert(a->name()).second) << a->name();
    EXPECT_TRUE(commands.insert(a->command()).second) << a->command();
    EXPECT_TRUE(a->command().rfind("estimate ", 0) == 0 || a->command().rfind("discrepancy ", 0) == 0) << a->command();
    EXPECT_FALSE(a->title().empty());
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
  ins->report(edited, section);
  EXPECT_NE(section.html.str().find("Slip classes"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(folder / "slip_confusion.csv"));
  std::filesystem::remove_all(folder);
}

// A campaign's columns come from the analyses: unique keys, and each numeric
// metric of the INS analysis found in a real result document.
TEST(AnalysisRegistry, KeyMetricsAreUniqueAndPointIntoTheResultDocument) {
  std::set<std::string> keys;
  for (const auto& analysis : app::all_analyses()) {
    for (const auto& m : analysis->key_metrics()) {
      EXPECT_TRUE(keys.insert(m.key).second) << "key metric " << m.key << " twice";
      EXPECT_EQ(m.pointer.rfind('/', 0), 0u) << m.pointer;
      EXPECT_EQ(m.key.find("wall"), std::string::npos) << "a wall-clock key metric: " << m.key;
    }
  }
  EXPECT_GE(keys.size(), 6u);
  const log::Log lg = simulation::simulate_skid_steer(simulation::default_slip_scenario(3));
  const std::unique_ptr<app::Analysis> ins = app::make_analysis("ins-slip");
  const app::AnalysisResult r = ins->run({lg, "sim.h5", {}});
  for (const auto& m : ins->key_metrics()) {
    const nlohmann::json::json_pointer at(m.pointer);
    ASSERT_TRUE(r.document.contains(at)) << m.pointer;
    EXPECT_TRUE(r.document.at(at).is_number()) << m.pointer;
  }
}

}  // namespace
}  // namespace roverlab
