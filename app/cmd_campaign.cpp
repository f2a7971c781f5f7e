// `roverlab campaign INPUT -o DIR`: many logs and many simulated runs through
// one Snakemake workflow (workflows/Snakefile). INPUT is a campaign file
// (importers/campaign_file.h) or a folder of logs. The command checks INPUT,
// writes the runs it stands for to DIR/items.json and runs snakemake there;
// snakemake decides what is missing or out of date, so a second run does
// nothing and an interrupted one resumes. docs/campaigns.md.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <thread>

#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/simulation/flying_rover.h"
#include "core/simulation/rocker_bogie.h"
#include "core/simulation/skid_steer_scenario.h"
#include "importers/atomic_file.h"
#include "importers/campaign_file.h"
#include "importers/hdf5_log.h"
#include "importers/mapping.h"
#include "importers/rover_file.h"
#include "importers/scenario_file.h"
#include "views/x_display.h"

#ifndef ROVERLAB_VERSION
#define ROVERLAB_VERSION "unknown"
#endif

namespace roverlab::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct CampaignOptions {
  std::string input;
  std::optional<std::string> mapping;
  std::string output;
  int cores = 0;  // 0: the machine's
  bool dry_run = false;
  bool unlock = false;
  std::optional<std::string> profile;
};

// Letters, digits and . _ + - only, never starting with '.': an item's name
// is a folder (runs/NAME; "." and ".." would be the folder's parent) and a
// Snakemake wildcard.
std::string safe_name(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '_' || c == '+' || c == '-';
    out += keep && !(c == '.' && out.empty()) ? c : '_';
  }
  return out.empty() ? "run" : out;
}

std::string short_number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

// The runs of a campaign, as Snakemake's configuration: name -> what to run.
class ItemList {
 public:
  explicit ItemList(std::string file) : file_(std::move(file)) {}

  void add_logs(const io::CampaignLogs& e) {
    std::optional<std::string> mapping;
    if (e.mapping) mapping = about_mapping(e, *e.mapping);
    std::vector<fs::path> files;
    if (!e.file.empty()) {
      files.emplace_back(e.file);
    } else {
      for (const auto& entry : fs::directory_iterator(e.folder)) {
        std::string ext = entry.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
        if (entry.is_regular_file() &&
            (ext == ".h5" || ext == ".hdf5" || ext == ".mat" || ext == ".csv" || ext == ".bag" || ext == ".mcap")) {
          files.push_back(entry.path());
        }
      }
      std::sort(files.begin(), files.end());
      if (files.empty()) {
        const std::string field = e.where.rfind("--", 0) == 0 ? "" : "field '" + e.where + ".folder': ";
        throw InputError(file_, field + "no .h5, .hdf5, .mat, .csv, .bag or .mcap log in " + e.folder);
      }
    }
    for (const auto& f : files) {
      // Snakemake reads braces in a path as a pattern ({item}): refused before it starts.
      if (f.string().find_first_of("{}") != std::string::npos) {
        throw InputError(f.string(), "a log path with braces ({ or }) cannot run in a campaign; rename the file");
      }
      if (!mapping) refuse_without_mapping(e, f);
      json args = {"convert", f.string(), "{output}"};
      json inputs = {f.string()};
      if (mapping) {
        args.push_back("--mapping");
        args.push_back(*mapping);
        inputs.push_back(*mapping);
      }
      std::string name = safe_name(f.stem().string());
      for (int n = 2; items_.contains(name); ++n) name = safe_name(f.stem().string()) + "-" + std::to_string(n);
      items_[name] = {
          {"kind", "log"},   {"source", f.string()},      {"mapping", mapping ? json(*mapping) : json(nullptr)},
          {"seed", nullptr}, {"effects", json::object()}, {"scenario", nullptr},
          {"args", args},    {"inputs", inputs}};
    }
  }

  // A MATLAB file, or an HDF5 file that is not a RoverLab log, is read only
  // through a mapping: refused here, before the workflow starts, not as a
  // failed step after it.
  void refuse_without_mapping(const io::CampaignLogs& e, const fs::path& f) const {
    std::string ext = f.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    const bool mapped = ext == ".mat" || ((ext == ".h5" || ext == ".hdf5") && !io::is_roverlab_hdf5(f.string()));
    if (!mapped) return;
    const std::string how =
        e.where.rfind("--", 0) == 0 ? "give --mapping NAME|FILE" : "give field '" + e.where + ".mapping'";
    throw InputError(f.string(), "needs a mapping to be read (a " + ext.substr(1) +
                                     " file that is not a RoverLab log): " + how +
                                     " (e.g. wvu_pathfinder; `roverlab mappings` lists them)");
  }

  void add_simulations(const io::CampaignSimulations& e) {
    std::string scenario_file;
    std::string label = e.scenario;
    if (e.command == "simulate") {
      scenario_file = about_field(e.where + ".simulate",
                                  [&] { return io::find_scenario(e.scenario, resource_subfolders("scenarios")).file; });
      label = fs::path(e.scenario).stem().string();
      if (scenario_file.find_first_of("{}") != std::string::npos) {
        throw InputError(scenario_file,
                         "a scenario path with braces ({ or }) cannot run in a campaign; rename the file");
      }
    }
    for (std::size_t k = 0; k < e.effects.size(); ++k) check_effects(e, k);
    check_steering_manoeuvre(e);
    for (const unsigned seed : e.seeds) {
      for (const auto& effects : e.effects) {
        std::string name = label + "-seed" + std::to_string(seed);
        json args = {e.command};
        if (e.command == "scenario") {
          args.push_back(e.scenario);
        } else {
          args.push_back(scenario_file);
        }
        args.push_back("--seed");
        args.push_back(std::to_string(seed));
        if (e.rate) args.insert(args.end(), {"--rate", short_number(*e.rate)});
        // The manoeuvre's options name the run (a sweep of slip angles is one run each); the rate does not.
        for (const auto& f : io::kFlyingRoverFields) {
          const std::optional<double>& value = e.*f.value;
          if (!value) continue;
          name += "-" + std::string(f.option + 2) + short_number(*value);
          args.insert(args.end(), {f.option, short_number(*value)});
        }
        if (e.duration) args.insert(args.end(), {"--duration", short_number(*e.duration)});
        json fx = json::object();
        for (const auto& [effect, value] : effects) {
          name += "-" + effect + short_number(value);
          args.insert(args.end(), {"--effect", effect + "=" + short_number(value)});
          fx[effect] = value;
        }
        args.insert(args.end(), {"-o", "{output}"});
        name = safe_name(name);
        if (items_.contains(name)) throw InputError(file_, "field '" + e.where + "': run " + name + " is listed twice");
        items_[name] = {{"kind", e.command},
                        {"scenario", label},
                        {"source", scenario_file.empty() ? json(nullptr) : json(scenario_file)},
                        {"mapping", nullptr},
                        {"seed", seed},
                        {"effects", fx},
                        {"args", args},
                        {"inputs", scenario_file.empty() ? json::array() : json::array({scenario_file})}};
      }
    }
  }

  const json& items() const { return items_; }

 private:
  template <class Work>
  auto about_field(const std::string& where, Work&& work) -> decltype(work()) {
    try {
      return work();
    } catch (const InputError& e) {
      throw InputError(file_, place(where) + e.what());
    } catch (const DataError& e) {
      throw InputError(file_, place(where) + e.what());
    }
  }

  // "field 'logs[0].mapping': ", or "--mapping: " for a folder given on the command line.
  static std::string place(const std::string& where) {
    if (where.rfind("--", 0) == 0) return where.substr(0, where.find('.')) + ": ";
    return "field '" + where + "': ";
  }

  std::string about_mapping(const io::CampaignLogs& e, const std::string& mapping) {
    return about_field(e.where + ".mapping", [&] {
      const std::string path = io::find_mapping(mapping, resource_subfolders("mappings"));
      (void)io::load_mapping(path);
      return fs::absolute(path).lexically_normal().string();
    });
  }

  // The simulators say which effects they know and which values they take.
  void check_effects(const io::CampaignSimulations& e, std::size_t k) {
    about_field(e.where + ".effects[" + std::to_string(k) + "]", [&] {
      for (const auto& [name, value] : e.effects[k]) {
        if (e.command == "simulate") {
          simulation::RockerBogieEffects fx;
          simulation::set_effect(fx, name, value);
        } else if (e.scenario == "skid-steer-slip") {
          simulation::SkidSteerScenario s = simulation::default_slip_scenario(1);
          simulation::set_effect(s, name, value);
        } else {
          throw DataError("scenario " + e.scenario + " takes no effects");
        }
      }
      return 0;
    });
  }

  // The values of turn_radius, slip_angle_deg and slip_angle_from, checked as
  // `roverlab scenario` checks its options: by the simulator, on the scenario
  // with its default rover (each field alone, so the message names the right one).
  void check_steering_manoeuvre(const io::CampaignSimulations& e) {
    if (!e.turn_radius && !e.slip_angle_deg && !e.slip_angle_from) return;
    const io::RoverDescription d = io::find_rover(kFlyingRoverDefaultRover, resource_subfolders("rovers"));
    if (!d.dh) throw InputError(d.file, "rover '" + d.name + "' is not described by a DH table");
    const simulation::FlyingRoverScenario base = simulation::flying_rover_scenario(e.scenario, *d.dh);
    const auto check = [&](const char* field, const std::optional<double>& value, auto set) {
      if (!value) return;
      about_field(e.where + "." + field, [&] {
        simulation::FlyingRoverScenario s = base;
        set(s, *value);
        simulation::check_steering_manoeuvre(s);
        return 0;
      });
    };
    check("turn_radius", e.turn_radius, [](auto& s, double v) { s.turn_radius = v; });
    check("slip_angle_deg", e.slip_angle_deg, [](auto& s, double v) { s.slip_angle = v * M_PI / 180.0; });
    check("slip_angle_from", e.slip_angle_from, [](auto& s, double v) { s.slip_angle_from = v; });
  }

  std::string file_;
  json items_ = json::object();
};

fs::path own_executable() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find the roverlab executable (/proc/self/exe)");
  return exe;
}

// workflows/Snakefile: $ROVERLAB_WORKFLOWS, <prefix>/share/roverlab/workflows, the source tree's.
fs::path find_workflows() {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("ROVERLAB_WORKFLOWS"); env != nullptr && *env != '\0') candidates.emplace_back(env);
  candidates.push_back(own_executable().parent_path().parent_path() / "share" / "roverlab" / "workflows");
  candidates.emplace_back(ROVERLAB_SOURCE_WORKFLOWS);
  std::error_code ec;
  for (const auto& c : candidates) {
    if (fs::is_regular_file(c / "Snakefile", ec)) return c;
  }
  throw std::runtime_error("cannot find workflows/Snakefile (set ROVERLAB_WORKFLOWS to its folder)");
}

std::optional<fs::path> find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string rest = path != nullptr ? path : "/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= rest.size()) {
    const std::size_t end = std::min(rest.find(':', start), rest.size());
    const fs::path candidate = fs::path(rest.substr(start, end - start)) / program;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return std::nullopt;
}

json campaign_items(const CampaignOptions& o) {
  std::error_code ec;
  if (fs::is_directory(o.input, ec)) {
    io::CampaignLogs folder;
    folder.folder = fs::absolute(o.input).lexically_normal().string();
    folder.mapping = o.mapping;
    folder.where = "--mapping";
    ItemList list(o.input);
    list.add_logs(folder);
    return list.items();
  }
  if (o.mapping) throw UsageError("--mapping goes with a folder of logs; a campaign file names its mappings");
  const io::CampaignFile c = io::read_campaign_file(o.input);
  ItemList list(o.input);
  for (const auto& e : c.logs) list.add_logs(e);
  for (const auto& e : c.simulations) list.add_simulations(e);
  return list.items();
}

// Replaces the file only when its text changes, so its date stays put.
void write_if_changed(const fs::path& path, const std::string& text) {
  std::ifstream in(path);
  const std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (old != text) io::write_text_atomically(path.string(), text);
}

// Snakemake's lines, shortened: the progress ("N of M steps (P%) done") as a
// progress line on a terminal, errors and summaries as they are; the
// per-job blocks (rule, input, output, jobid, ...) and scheduler chatter are
// left out (they stay in DIR/.snakemake/log/). A dry run shows everything.
class SnakemakeOutput {
 public:
  explicit SnakemakeOutput(bool everything) : everything_(everything), terminal_(isatty(STDERR_FILENO) != 0) {}
  ~SnakemakeOutput() {
    if (progress_shown_) std::fputc('\n', stderr);
  }
  SnakemakeOutput(const SnakemakeOutput&) = delete;
  SnakemakeOutput& operator=(const SnakemakeOutput&) = delete;

  void line(const std::string& text) {
    if (everything_) {
      std::fprintf(stderr, "%s\n", text.c_str());
      return;
    }
    if (text.find(" steps (") != std::string::npos && text.find("done") != std::string::npos) {
      std::fprintf(stderr, terminal_ ? "\rcampaign: %s" : "campaign: %s\n", text.c_str());
      progress_shown_ = terminal_;
      return;
    }
    if (text.rfind("Error in rule", 0) == 0) {
      in_error_ = true;
      in_block_ = false;
    } else if (text.empty()) {
      in_error_ = in_block_ = false;
      return;
    } else if (!in_error_ && (in_block_ || starts_block(text) || chatter(text))) {
      in_block_ = in_block_ || starts_block(text);
      return;
    }
    if (progress_shown_) std::fputc('\n', stderr);
    progress_shown_ = false;
    std::fprintf(stderr, "%s\n", text.c_str());
  }

 private:
  // A job's block (time stamp, rule, its indented fields) or the job table, up to a blank line.
  static bool starts_block(const std::string& text) {
    for (const char* c : {"[", "rule ", "localrule ", "checkpoint ", "Job stats:"}) {
      if (text.rfind(c, 0) == 0) return true;
    }
    return false;
  }
  static bool chatter(const std::string& text) {
    for (const char* c : {"Select jobs to execute", "Building DAG of jobs", "Using shell:", "Provided cores:",
                          "Rules claiming more threads", "Finished job ", "Complete log:"}) {
      if (text.rfind(c, 0) == 0) return true;
    }
    return false;
  }

  bool everything_, terminal_;
  bool in_error_ = false, in_block_ = false, progress_shown_ = false;
};

// Runs snakemake with `argv`, its output shortened; its exit status.
int run_snakemake(const std::vector<std::string>& argv, bool everything) {
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));  // NOLINT: execv takes char* const*
  args.push_back(nullptr);
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("cannot start snakemake (pipe failed)");
  std::fflush(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("cannot start snakemake (fork failed)");
  if (pid == 0) {
    // Snakemake dies with RoverLab, even killed by SIGKILL. Not by SIGTERM: Snakemake 7.21's handler takes
    // the scheduler's lock, which the main thread it interrupts may hold (scheduler.py, exit_gracefully), and
    // then it never exits (3 of 22 kills here, docs/robustness.md). The steps it was running finish on their own;
    // a rerun does again those left incomplete.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(1);
    close(fds[0]);
    dup2(fds[1], STDOUT_FILENO);
    dup2(fds[1], STDERR_FILENO);
    close(fds[1]);
    execv(args[0], args.data());
    std::fprintf(stderr, "roverlab: cannot run %s\n", args[0]);
    _exit(127);
  }
  close(fds[1]);
  // Ctrl-C reaches snakemake too (same process group): let it stop its jobs
  // and mark what is incomplete, then report its status.
  struct sigaction ignore {};
  struct sigaction old_int {};
  ignore.sa_handler = SIG_IGN;
  sigaction(SIGINT, &ignore, &old_int);
  {
    SnakemakeOutput out(everything);
    std::string pending;
    char buffer[4096];
    for (;;) {
      const ssize_t n = read(fds[0], buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      pending.append(buffer, static_cast<std::size_t>(n));
      for (std::size_t nl = pending.find('\n'); nl != std::string::npos; nl = pending.find('\n')) {
        out.line(pending.substr(0, nl));
        pending.erase(0, nl + 1);
      }
    }
    if (!pending.empty()) out.line(pending);
  }
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  sigaction(SIGINT, &old_int, nullptr);
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

// The campaign folder's lock, DIR/.roverlab-campaign.lock, held while a run
// lasts. An flock: the kernel frees it when this process ends, however it
// ends, so a killed run leaves no lock behind (Snakemake's own lock, files in
// DIR/.snakemake/locks, stayed when Snakemake was killed; it runs with
// --nolock). Close-on-exec: Snakemake, which dies with this process, does not
// hold it.
class CampaignFolderLock {
 public:
  explicit CampaignFolderLock(const fs::path& folder) {
    const fs::path file = folder / ".roverlab-campaign.lock";
    fd_ = open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd_ < 0)
      throw InputError(file.string(), std::string("cannot open the campaign's lock: ") + std::strerror(errno));
    while (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      if (errno == EINTR) continue;
      const int e = errno;
      close(fd_);
      if (e == EWOULDBLOCK) {
        throw InputError(folder.string(), "another `roverlab campaign` is running in this folder; wait for it to end");
      }
      throw InputError(file.string(), std::string("cannot lock the campaign folder: ") + std::strerror(e));
    }
  }
  ~CampaignFolderLock() { close(fd_); }
  CampaignFolderLock(const CampaignFolderLock&) = delete;
  CampaignFolderLock& operator=(const CampaignFolderLock&) = delete;

 private:
  int fd_ = -1;
};

int run_campaign(const CampaignOptions& o) {
  if (o.output.empty()) throw UsageError("--output: the campaign folder's name is empty");
  std::error_code ec;
  if (!fs::exists(o.input, ec)) throw InputError(o.input, "no such campaign file or folder of logs");
  const json items = campaign_items(o);
  const std::optional<fs::path> snakemake = find_on_path("snakemake");
  if (!snakemake) {
    std::fprintf(stderr,
                 "roverlab: snakemake not found on PATH: campaigns run on Snakemake (Debian: apt-get install "
                 "snakemake, or scripts/install-deps)\n");
    return kInternalFailure;
  }
  const fs::path workflows = find_workflows();
  fs::create_directories(o.output, ec);
  if (ec || !fs::is_directory(o.output)) {
    throw InputError(o.output, "cannot create the campaign folder" + (ec ? ": " + ec.message() : std::string()));
  }
  // Before items.json is written: a second run would change it under the first.
  std::optional<CampaignFolderLock> folder_lock;
  if (!o.unlock) folder_lock.emplace(o.output);
  const json config = {{"format", "roverlab-campaign-items"},
                       {"campaign", fs::absolute(o.input).lexically_normal().string()},
                       {"roverlab", own_executable().string()},
                       {"version", ROVERLAB_VERSION},
                       {"items", items}};
  write_if_changed(fs::path(o.output) / "items.json", config.dump(1) + "\n");
  const unsigned machine = std::max(1U, std::thread::hardware_concurrency());
  const int cores = o.cores > 0 ? o.cores : static_cast<int>(machine);
  std::vector<std::string> argv = {snakemake->string(),  "--snakefile", (workflows / "Snakefile").string(),
                                   "--directory",        o.output,      "--config",
                                   "items=items.json",   "--cores",     std::to_string(cores),
                                   "--rerun-incomplete", "--keep-going"};
  if (o.profile) {
    const fs::path named = workflows / "profiles" / *o.profile;
    if (!fs::is_directory(named, ec) && !fs::is_directory(*o.profile, ec)) {
      std::string known;
      for (const auto& entry : fs::directory_iterator(workflows / "profiles", ec)) {
        if (entry.is_directory()) known += (known.empty() ? "" : ", ") + entry.path().filename().string();
      }
      throw UsageError("--profile " + *o.profile + ": no such profile (known: " + known +
                       "; or a folder holding config.yaml)");
    }
    argv.insert(argv.end(), {"--profile", fs::is_directory(named, ec) ? named.string() : *o.profile});
  }
  if (o.dry_run) argv.emplace_back("--dry-run");
  if (o.unlock) {
    argv.emplace_back("--unlock");
    const int status = run_snakemake(argv, true);
    if (status != 0) return kInternalFailure;
    std::printf("campaign: %s unlocked\n", o.output.c_str());
    return kSuccess;
  }
  argv.emplace_back("--nolock");  // the folder's lock is RoverLab's (CampaignFolderLock)
  // One private Xvfb (when DISPLAY is unset) for every report the steps
  // render, not one each; cluster jobs start their own on their node.
  if (!o.profile && !o.dry_run) views::ensure_display();
  std::printf("campaign: %zu runs in %s, %d cores%s\n", items.size(), o.output.c_str(), cores,
              o.dry_run ? " (dry run: what would run)" : "");
  const int status = run_snakemake(argv, o.dry_run);
  if (status != 0) {
    std::fprintf(stderr,
                 "roverlab: the campaign stopped (snakemake exit %d): see the failed steps above and their logs in "
                 "%s/runs/NAME/*.txt; run again to resume\n",
                 status, o.output.c_str());
    return kInternalFailure;
  }
  if (!o.dry_run) std::printf("campaign report: %s\n", (fs::path(o.output) / "report" / "index.html").c_str());
  return kSuccess;
}

}  // namespace

Commands make_campaign_commands() {
  Commands commands;
  commands.push_back(make_command<CampaignOptions>(
      "campaign",
      "Run many logs and simulated runs through the campaign workflow (Snakemake): per-run reports and a campaign "
      "report",
      [](CLI::App& cmd, CampaignOptions& o) {
        cmd.add_option("INPUT", o.input, "Campaign file (JSON, docs/campaigns.md) or a folder of logs");
        cmd.add_option("--mapping,-m", o.mapping, "Mapping NAME or FILE for the logs of a folder");
        cmd.add_option("--output,-o", o.output, "Campaign folder (created if missing; a rerun resumes it)");
        cmd.add_option("--cores,-j", o.cores, "Steps at once (default: the machine's cores)")
            ->check(CLI::Range(1, 1024));
        cmd.add_flag("--dry-run,-n", o.dry_run, "List what would run, run nothing");
        cmd.add_flag("--unlock", o.unlock,
                     "Remove Snakemake's lock from the folder (left by an earlier RoverLab, or by Snakemake run by "
                     "hand), run nothing");
        cmd.add_option("--profile", o.profile,
                       "Snakemake profile: slurm (workflows/profiles/slurm) or a profile folder");
      },
      [](const CampaignOptions& o) {
        if (o.input.empty()) throw UsageError("campaign: INPUT (a campaign file or a folder of logs) is required");
        if (o.output.empty()) throw UsageError("campaign: --output DIR is required");
        return run_campaign(o);
      }));
  return commands;
}

}  // namespace roverlab::app
