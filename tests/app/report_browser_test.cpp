// Reports opened in a real browser (Debian's headless Chromium), as a reader
// opens them: a copy of the page gets a small script that, once the page has
// loaded, writes what the browser measured into the title (the page's scroll
// width against the window's, every image's natural width, where the summary
// ends); `--dump-dom` prints it. At 1400x900: no horizontal overflow, no
// broken image, the summary (each study's verdict) inside the first screen.
// Skipped, with the reason, where chromium is not installed (CI installs it:
// scripts/install-deps).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.h"

using namespace roverlab;
using namespace roverlab::test;
namespace fs = std::filesystem;

namespace {

const std::string kExe = ROVERLAB_EXE;
const std::string kData = ROVERLAB_TEST_DATA;

CommandResult run_roverlab(const std::string& args) { return run_command(quote(kExe) + " " + args); }

bool have_chromium() { return run_command("command -v chromium").exit_code == 0; }

// Writes what the browser measured into the title, once everything has loaded.
const char* const kProbe =
    "<script>window.addEventListener('load',function(){"
    "var d=document.documentElement,r={scroll_width:d.scrollWidth,client_width:d.clientWidth,images:[],"
    "summary_bottom:-1,verdicts_bottom:-1};"
    "for(var i=0;i<document.images.length;i++){var m=document.images[i];"
    "r.images.push({src:m.getAttribute('src'),natural_width:m.naturalWidth});}"
    "var hs=document.getElementsByTagName('h2');for(var k=0;k<hs.length;k++){"
    "if(hs[k].textContent=='Summary'){var e=hs[k].nextElementSibling;"
    "r.summary_bottom=hs[k].getBoundingClientRect().bottom;"
    "if(e)r.verdicts_bottom=e.getBoundingClientRect().bottom;}}"
    "document.title='PROBE'+JSON.stringify(r);});</script>";

std::string unescape(std::string s) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"&quot;", "\""},
                                 {"&lt;", "<"},
                                 {"&gt;", ">"},
                                 {"&#39;", "'"},
                                 {"&amp;", "&"}}) {
    for (auto at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
      s.replace(at, from.size(), to);
  }
  return s;
}

// Opens `page` (with its pictures beside it) in headless Chromium at 1400x900;
// the browser's measurements. A screenshot goes to `screenshot` when given.
nlohmann::json open_in_chromium(const std::string& page, const std::string& screenshot = {}) {
  const fs::path folder = fs::path(page).parent_path();
  std::string html = read_text(page);
  const auto body = html.rfind("</body>");
  html.insert(body == std::string::npos ? html.size() : body, kProbe);
  const fs::path probe = folder / "browser_probe.html";
  write_text(probe.string(), html);
  const std::string profile = (folder / "chromium_profile").string();
  const std::string chromium =
      "timeout 120 chromium --headless --no-sandbox --disable-gpu --hide-scrollbars "
      "--window-size=1400,900 --user-data-dir=" +
      quote(profile) + " ";
  const CommandResult r = run_command(chromium + "--dump-dom " + quote("file://" + probe.string()));
  if (!screenshot.empty()) {
    run_command(chromium + "--screenshot=" + quote(screenshot) + " " + quote("file://" + fs::absolute(page).string()));
  }
  fs::remove(probe);
  fs::remove_all(profile);
  const auto open = r.out.find("<title>PROBE"), close = r.out.find("</title>", open);
  if (open == std::string::npos || close == std::string::npos) {
    ADD_FAILURE() << "chromium gave no measurement for " << page << ": " << r.err.substr(0, 400);
    return nlohmann::json::object();
  }
  const std::string text = unescape(r.out.substr(open + 12, close - open - 12));
  return nlohmann::json::parse(text);
}

// What a reader of any report at 1400x900 must get.
void expect_readable(const nlohmann::json& m, const std::string& what, bool summary = true) {
  ASSERT_TRUE(m.contains("scroll_width")) << what;
  EXPECT_EQ(m.at("client_width").get<int>(), 1400) << what;
  EXPECT_LE(m.at("scroll_width").get<int>(), m.at("client_width").get<int>()) << what << ": wider than the window";
  for (const auto& img : m.at("images")) {
    EXPECT_GT(img.at("natural_width").get<int>(), 0) << what << ": broken image " << img.at("src");
  }
  if (!summary) return;
  EXPECT_GT(m.at("summary_bottom").get<double>(), 0) << what << ": no summary";
  EXPECT_LE(m.at("verdicts_bottom").get<double>(), 900.0) << what << ": the summary runs past the first screen";
}

// Where screenshots are kept to look at (ROVERLAB_REPORT_SHOTS=<folder>), else none.
std::string shot(const std::string& name) {
  const char* folder = std::getenv("ROVERLAB_REPORT_SHOTS");
  return folder ? std::string(folder) + "/" + name : std::string();
}

}  // namespace

// The checker itself: a missing picture and a page wider than the window are seen.
TEST(ReportInBrowser, TheProbeSeesABrokenImageAndAnOverflow) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  TempDir dir;
  const std::string page = dir.file("page.html");
  write_text(page,
             "<!DOCTYPE html><html><head><title>t</title></head><body><h2>Summary</h2><ul><li>x</li></ul>"
             "<img src=\"missing.png\"><table><tr><td style=\"min-width:2000px\">wide</td></tr></table></body></html>");
  const nlohmann::json m = open_in_chromium(page);
  ASSERT_EQ(m.at("images").size(), 1u);
  EXPECT_EQ(m.at("images").at(0).at("natural_width").get<int>(), 0);
  EXPECT_GT(m.at("scroll_width").get<int>(), 2000);
  EXPECT_GT(m.at("verdicts_bottom").get<double>(), 0.0);
}

TEST(ReportInBrowser, TheWvuReportReadsAt1400x900) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  TempDir dir;
  const std::string folder = dir.file("wvu");
  const CommandResult r =
      run_roverlab("report " + quote(kData + "/test17run.mat") + " -m wvu_pathfinder -o " + quote(folder));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json m = open_in_chromium(folder + "/index.html", shot("report-wvu.png"));
  expect_readable(m, "WVU report");
  EXPECT_GE(m.at("images").size(), 3u);  // rover, map, plots (the default plot is the INS slip against its reference)
}

// A simulated skid-steer run with a hidden effect (the left wheels 4 % larger): the odometry study's verdict first.
TEST(ReportInBrowser, ASimulatedRunWithAHiddenEffectReadsAt1400x900) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  TempDir dir;
  const std::string log = dir.file("hidden.h5"), folder = dir.file("hidden");
  ASSERT_EQ(
      run_roverlab("scenario skid-steer-slip --effect left-radius-scale=1.04 --seed 3 -o " + quote(log)).exit_code, 0);
  const CommandResult r = run_roverlab("report " + quote(log) + " -o " + quote(folder));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(read_text(folder + "/index.html").find("What the wheel odometry gets wrong"), std::string::npos);
  expect_readable(open_in_chromium(folder + "/index.html", shot("report-hidden-effect.png")), "hidden-effect report");
}

TEST(ReportInBrowser, ABb2ScenarioReportReadsAt1400x900) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  TempDir dir;
  const std::string log = dir.file("bump.h5"), folder = dir.file("bump");
  ASSERT_EQ(run_roverlab("scenario bump-crossing --rate 100 -o " + quote(log)).exit_code, 0);
  ASSERT_EQ(run_roverlab("report " + quote(log) + " -o " + quote(folder)).exit_code, 0);
  expect_readable(open_in_chromium(folder + "/index.html", shot("report-bb2.png")), "BB2 report");
}

// A campaign's table of runs has a column per key metric of every analysis:
// it was wider than the page. It scrolls inside its box; the page does not.
TEST(ReportInBrowser, ACampaignReportIsNoWiderThanTheWindow) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  TempDir dir;
  std::string runs;
  for (const char* name : {"first_run_with_a_long_name", "second_run_with_a_long_name"}) {
    const fs::path run = dir.path() / "runs" / name;
    fs::create_directories(run / "report");
    write_text((run / "run.json").string(), nlohmann::json{{"format", "roverlab-campaign-run"},
                                                           {"name", name},
                                                           {"kind", "simulate"},
                                                           {"scenario", "rolling_200s"},
                                                           {"seed", 3},
                                                           {"effects", {{"soil-strength", 2.5}, {"gyro-bias", 0.01}}},
                                                           {"roverlab_version", "test"}}
                                                .dump());
    const nlohmann::json metrics = {
        {"analyses", {{"net-traction", {{"summary", {{"drawbar_pull_rms_percent", 11.28}}}}}}}};
    write_text((run / "report" / "metrics.json").string(), metrics.dump());
    write_text((run / "report" / "index.html").string(), "<h1>RoverLab report</h1>");
    runs += " " + quote(run.string());
  }
  const std::string out = dir.file("campaign");
  const CommandResult r = run_roverlab("campaign report" + runs + " -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_readable(open_in_chromium(out + "/index.html", shot("campaign-report.png")), "campaign report", false);
}

namespace {

std::string collapse_spaces(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const bool space = c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\f';
    if (space && (out.empty() || out.back() == ' ')) continue;
    out += space ? ' ' : c;
  }
  return out;
}

}  // namespace

// `report --pdf`: the same document on A4 pages, printed by Chromium; with
// umask 022 it is 0644. Its text (pdftotext, poppler-utils) holds the study's
// verdict, and the pictures make it several pages.
TEST(ReportAsPdf, TheWvuReportPrintsWithItsVerdictOnSeveralPages) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  if (run_command("command -v pdftotext").exit_code != 0) GTEST_SKIP() << "pdftotext (poppler-utils) is missing";
  TempDir dir;
  const std::string folder = dir.file("wvu"), pdf = folder + "/report.pdf";
  const CommandResult r = run_command("umask 022 && " + quote(kExe) + " report " + quote(kData + "/test17run.mat") +
                                      " -m wvu_pathfinder --pdf -o " + quote(folder));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::is_regular_file(pdf));
  EXPECT_EQ(read_text(pdf).substr(0, 5), "%PDF-");
  EXPECT_EQ(static_cast<unsigned>(fs::status(pdf).permissions()) & 0777u, 0644u);
  const CommandResult info = run_command("pdfinfo " + quote(pdf));
  const auto pages_at = info.out.find("Pages:");
  ASSERT_NE(pages_at, std::string::npos) << info.err;
  EXPECT_GT(std::stoi(info.out.substr(pages_at + 6)), 1);
  const std::string text = collapse_spaces(run_command("pdftotext " + quote(pdf) + " -").out);
  const nlohmann::json metrics = nlohmann::json::parse(read_text(folder + "/metrics.json"));
  const std::string verdict = collapse_spaces(metrics.at("analyses").at("odometry").at("verdict").get<std::string>());
  ASSERT_GT(verdict.size(), 40u);
  EXPECT_NE(text.find(verdict.substr(0, 120)), std::string::npos) << "the verdict is not in the PDF's text";
  EXPECT_NE(text.find("Summary"), std::string::npos);
  const auto files = metrics.at("files");
  EXPECT_NE(std::find(files.begin(), files.end(), "report.pdf"), files.end());
}

// Without a browser to print it, --pdf is refused in one line before any work, and nothing is written.
TEST(ReportAsPdf, WithoutChromiumPdfIsRefusedAtOnce) {
  TempDir dir;
  const std::string bin = dir.file("bin"), folder = dir.file("out");
  fs::create_directories(bin);
  const CommandResult r = run_command("PATH=" + quote(bin) + " " + quote(kExe) + " report " +
                                      quote(kData + "/test17run.mat") + " -m wvu_pathfinder --pdf -o " + quote(folder));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("Chromium"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(folder + "/index.html"));
}
