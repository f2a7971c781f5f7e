#pragma once
// What every command shares: a progress line on stderr, the file a DataError
// is about, and writing a log with added streams (atomically, as every output).

#include <functional>
#include <memory>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "core/common/error.h"
#include "core/log/log.h"

namespace roverlab::app {

// The rover `roverlab scenario FLYING-ROVER-SCENARIO` simulates without --rover (a campaign's runs too).
inline constexpr const char* kFlyingRoverDefaultRover = "exomars_bb2";

// "\r<label> NN %" on stderr while work goes on, when stderr is a terminal;
// cleared when the line goes out of scope. When stderr is not a terminal and
// `roverlab --progress` was given (set_progress_lines), one line
// "<label>: NN % after T s" every kProgressLinePeriod seconds from a ticker
// thread (a study's own callbacks may be a minute apart), and
// "<label>: done in T s" at the end. callback() is empty otherwise, so batch
// runs and tests see no progress output.
class ProgressLine {
 public:
  enum class Style { percent, bar };
  explicit ProgressLine(std::string label, Style style = Style::percent);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;
  std::function<void(double)> callback() const;

 private:
  struct Ticker;
  std::string label_;
  Style style_;
  bool shown_ = false;
  std::shared_ptr<Ticker> ticker_;  // lines mode only
};

// Seconds between two progress lines when stderr is not a terminal.
inline constexpr double kProgressLinePeriod = 5.0;

// `roverlab --progress`: progress lines on stderr also when it is not a terminal.
void set_progress_lines(bool on);

// An option check: a finite number in [lo, hi] (CLI11's Range lets NaN through).
// A bad value is a usage error (exit 2) naming the option.
CLI::Validator finite_in(double lo, double hi);

// Runs `work`; a DataError it throws (a missing stream, a short log) becomes
// an InputError naming `file`.
template <class Work>
auto about_file(const std::string& file, Work&& work) -> decltype(work()) {
  try {
    return std::forward<Work>(work)();
  } catch (const DataError& e) {
    throw InputError(file, e.what());
  }
}

// A UsageError when `output` names the same file as `input` (through any
// path or link): writing would replace the very data being read.
void refuse_overwriting_input(const std::string& input, const std::string& output, const std::string& option);

// `text` from a file as a terminal shows it safely: control characters
// (escape sequences, newlines) as \xHH, cut to `max` characters.
std::string printable(const std::string& text, std::size_t max = 200);

// A UsageError unless `output` names an HDF5 log (OUT.h5 or OUT.hdf5): an
// HDF5 file is never written under a .csv or .txt name.
void require_log_output(const std::string& output, const std::string& option);

// The SHA-256 of a file's bytes, as 64 lower-case hex digits; empty when it cannot be read.
std::string sha256_of_file(const std::string& path);

// Writes `base` with the streams of `added` (and its metadata.extra entries)
// to `path` as a RoverLab HDF5 log, atomically.
void write_log_with(const log::Log& base, const log::Log& added, const std::string& path);

}  // namespace roverlab::app
