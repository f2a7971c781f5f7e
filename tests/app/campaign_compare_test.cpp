// The campaign report's comparisons (issue 45): each run's log against the
// baseline run's, linked from the run's row, with the channels that differ
// named in the table; run folders made here as a campaign leaves them
// (runs/NAME/log.h5, run.json, report/metrics.json).
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.h"

using namespace roverlab::test;

namespace {

CommandResult run_roverlab(const std::string& args) { return run_command(quote(ROVERLAB_EXE) + " " + args); }

// A run folder NAME holding a 20 s simulated run (seed, effect), or no log when seed is 0.
std::string run_folder(const TempDir& dir, const std::string& name, unsigned seed, const std::string& effect = "") {
  const fs::path run = fs::path(dir.path()) / "runs" / name;
  fs::create_directories(run / "report");
  write_text((run / "run.json").string(), R"({"format": "roverlab-campaign-run", "name": ")" + name + "\"}");
  write_text((run / "report" / "metrics.json").string(), R"({"analyses": {}})");
  if (seed > 0) {
    const CommandResult r =
        run_roverlab("simulate flat_60s --duration 20 --seed " + std::to_string(seed) +
                     (effect.empty() ? "" : " --effect " + effect) + " -o " + quote((run / "log.h5").string()));
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
  return run.string();
}

}  // namespace

TEST(CampaignCompare, EachRunLinksToItsComparisonWithTheBaselineAndNamesWhatDiffers) {
  TempDir dir;
  const std::string a = run_folder(dir, "a", 1), b = run_folder(dir, "b", 2),
                    c = run_folder(dir, "c", 3, "force-offset=0.5"), d = run_folder(dir, "d", 0);
  const std::string out = dir.file("campaign");
  const std::string runs = quote(a) + " " + quote(b) + " " + quote(c) + " " + quote(d);
  CommandResult r = run_roverlab("campaign report " + runs + " -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json doc = nlohmann::json::parse(read_text(out + "/campaign.json"));
  const auto& rows = doc.at("runs");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0]["comparison"], nlohmann::json({{"baseline", "a"}}));
  // Another seed: at most one of its ~50 channels by chance (1 % each), never a force.
  const std::vector<std::string> same = rows[1]["comparison"]["differing"];
  EXPECT_GE(rows[1]["comparison"]["channels"].get<int>(), 30);
  EXPECT_LE(same.size(), 1u);
  for (const auto& path : same) EXPECT_NE(path.rfind("forces/", 0), 0u) << path;
  // The hidden offset: the six force channels, named in the table and on the linked page.
  const std::vector<std::string> forced = rows[2]["comparison"]["differing"];
  const std::string html = read_text(out + "/index.html");
  const std::string page = read_text(out + "/" + rows[2]["comparison"]["page"].get<std::string>());
  for (const char* channel : {"load_1", "load_2", "load_3", "perpendicular_1", "perpendicular_2", "perpendicular_3"}) {
    const std::string path = std::string("forces/") + channel;
    EXPECT_NE(std::find(forced.begin(), forced.end(), path), forced.end()) << path;
    EXPECT_NE(page.find("<tr class=\"differs\"><td class=\"t\">" + path + "</td>"), std::string::npos) << path;
  }
  EXPECT_NE(html.find("href=\"compare-c.html\">" + std::to_string(forced.size()) + " of "), std::string::npos);
  EXPECT_NE(html.find("href=\"compare-b.html\""), std::string::npos);
  // A run without a log says so in its row.
  EXPECT_NE(rows[3]["comparison"]["note"].get<std::string>().find("no log"), std::string::npos);
  // Written again into its own folder (the pages are its own), with another baseline.
  r = run_roverlab("campaign report " + runs + " --baseline c -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json again = nlohmann::json::parse(read_text(out + "/campaign.json"));
  EXPECT_EQ(again["runs"][0]["comparison"]["baseline"], "c");
  EXPECT_GE(again["runs"][0]["comparison"]["differing"].size(), 6u);
  // A baseline that is not a run: one line naming the option, nothing written.
  r = run_roverlab("campaign report " + runs + " --baseline nope -o " + quote(dir.file("other")));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--baseline nope"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.file("other")));
}
