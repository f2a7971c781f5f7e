// One command per registered analysis (app/analyses/analyses.def):
// `estimate ins-slip`, `estimate contact-angle`, `discrepancy odometry`, ...
// Each loads LOG, runs the analysis with a progress line, optionally writes the
// log with its streams, and prints its result document as JSON or text.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <optional>

#include "app/analysis.h"
#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/log_input.h"

namespace roverlab::app {

namespace {

class AnalysisCommand : public Command {
 public:
  explicit AnalysisCommand(std::unique_ptr<Analysis> analysis) : analysis_(std::move(analysis)) {}
  std::string path() const override { return analysis_->identity().command; }
  std::string help() const override { return analysis_->identity().help; }

  void declare(CLI::App& cmd) override {
    cmd.add_option("LOG", file_, analysis_->identity().log_help)->required();
    cmd.add_option("--mapping,-m", mapping_, "Mapping NAME or FILE for .mat/HDF5 input (e.g. wvu_pathfinder)");
    analysis_->declare(cmd);
    if (analysis_->adds_streams()) {
      cmd.add_option("--output,-o", output_, "Write the log with the estimate streams to OUT.h5");
    }
    cmd.add_flag("--json", json_, "Print JSON");
  }

  int run() override {
    analysis_->check_options();
    if (output_) {
      require_log_output(*output_, "--output");
      refuse_overwriting_input(file_, *output_, "--output");
    }
    const log::Log lg = load_input(file_, mapping_).log;
    AnalysisResult r;
    {
      const ProgressLine progress(analysis_->name());
      r = run_analysis(*analysis_, {lg, file_, progress.callback()});
    }
    if (output_) {
      // Kept with its streams: render, report and the GUI reuse it (app/analysis.h).
      store_result(*analysis_, r.document, r.estimates);
      write_log_with(lg, r.estimates, *output_);
    }
    if (json_) {
      if (output_) r.document["output"] = *output_;
      std::cout << r.document.dump(2) << "\n";
      return kSuccess;
    }
    std::fflush(stdout);
    analysis_->presentation().print(r.document, stdout);
    std::fputs(configuration_text(r.document).c_str(), stdout);
    if (output_) std::printf("\nwrote %s\n", output_->c_str());
    return kSuccess;
  }

 private:
  std::unique_ptr<Analysis> analysis_;
  std::string file_;
  std::optional<std::string> mapping_, output_;
  bool json_ = false;
};

}  // namespace

Commands make_analyses_commands() {
  Commands commands;
  for (auto& a : all_analyses()) commands.push_back(std::make_unique<AnalysisCommand>(std::move(a)));
  return commands;
}

}  // namespace roverlab::app
