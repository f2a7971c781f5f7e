#include "app/command_support.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <thread>

#include <QCryptographicHash>
#include <QFile>

#include "app/commands.h"

#include "importers/hdf5_log.h"

namespace roverlab::app {

namespace {
bool g_progress_lines = false;
}  // namespace

void set_progress_lines(bool on) { g_progress_lines = on; }

// Lines mode: the last fraction reported, printed every kProgressLinePeriod
// seconds by a thread of its own until the ProgressLine goes out of scope.
struct ProgressLine::Ticker {
  std::atomic<double> fraction{0.0};
  std::mutex mutex;
  std::condition_variable wake;
  bool stop = false;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  std::thread thread;

  double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); }
  void run(const std::string& label) {
    std::unique_lock<std::mutex> lock(mutex);
    const auto period = std::chrono::duration<double>(kProgressLinePeriod);
    while (!wake.wait_for(lock, period, [this] { return stop; })) {
      std::fprintf(stderr, "%s: %d %% after %.0f s\n", label.c_str(), static_cast<int>(100 * fraction.load()),
                   elapsed());
      std::fflush(stderr);
    }
  }
};

ProgressLine::ProgressLine(std::string label, Style style)
    : label_(std::move(label)), style_(style), shown_(isatty(2) != 0) {
  if (shown_ || !g_progress_lines) return;
  ticker_ = std::make_shared<Ticker>();
  ticker_->thread = std::thread([t = ticker_.get(), label = label_] { t->run(label); });
}

ProgressLine::~ProgressLine() {
  if (shown_) std::fprintf(stderr, "\r%*s\r", static_cast<int>(label_.size()) + 48, "");
  if (!ticker_) return;
  {
    const std::lock_guard<std::mutex> lock(ticker_->mutex);
    ticker_->stop = true;
  }
  ticker_->wake.notify_all();
  ticker_->thread.join();
  std::fprintf(stderr, "%s: done in %.1f s\n", label_.c_str(), ticker_->elapsed());
}

std::function<void(double)> ProgressLine::callback() const {
  if (ticker_) {
    return [t = ticker_](double f) { t->fraction.store(f); };
  }
  if (!shown_) return {};
  if (style_ == Style::bar) {
    return [label = label_](double f) {
      const int n = static_cast<int>(40 * f);
      std::fprintf(stderr, "\r%s [%-40s] %3d %%", label.c_str(), std::string(static_cast<std::size_t>(n), '#').c_str(),
                   static_cast<int>(100 * f));
    };
  }
  return [label = label_](double f) { std::fprintf(stderr, "\r%s %3d %%", label.c_str(), static_cast<int>(100 * f)); };
}

CLI::Validator finite_in(double lo, double hi) {
  char range[96];
  std::snprintf(range, sizeof range, "a finite number in [%g, %g]", lo, hi);
  const std::string expected = range;
  return CLI::Validator(
      [lo, hi, expected](std::string& text) -> std::string {
        double v = 0;
        std::size_t used = 0;
        try {
          v = std::stod(text, &used);
        } catch (const std::exception&) {
          return "'" + text + "' is not a number";
        }
        if (used != text.size() || !std::isfinite(v) || v < lo || v > hi) return "'" + text + "': expected " + expected;
        return {};
      },
      expected);
}

void refuse_overwriting_input(const std::string& input, const std::string& output, const std::string& option) {
  std::error_code ec;
  if (std::filesystem::equivalent(input, output, ec) && !ec) {
    throw UsageError(option + " " + output + ": that is the input file; write to another file");
  }
}

std::string printable(const std::string& text, std::size_t max) {
  std::string out;
  for (const char c : text) {
    if (out.size() >= max) return out + "...";
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char b[8];
      std::snprintf(b, sizeof b, "\\x%02x", u);
      out += b;
    } else {
      out += c;
    }
  }
  return out;
}

void require_log_output(const std::string& output, const std::string& option) {
  const std::filesystem::path path(output);
  const std::string ext = path.extension().string(), name = path.filename().string();
  if (name == ".h5" || name == ".hdf5") return;  // the writer says: "no name before its extension"
  if (ext != ".h5" && ext != ".hdf5") {
    throw UsageError(option + " " + output + ": a log is written as OUT.h5 or OUT.hdf5 (RoverLab HDF5)");
  }
}

void write_log_with(const log::Log& base, const log::Log& added, const std::string& path) {
  io::write_hdf5_log(base, added, path);  // no copy of the (possibly large) input log
}

std::string sha256_of_file(const std::string& path) {
  QFile file(QFile::decodeName(QByteArray::fromStdString(path)));
  if (!file.open(QIODevice::ReadOnly)) return {};
  QCryptographicHash hash(QCryptographicHash::Sha256);
  if (!hash.addData(&file)) return {};
  return hash.result().toHex().toStdString();
}

}  // namespace roverlab::app
