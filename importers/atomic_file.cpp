#include "importers/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <system_error>

#include "core/common/error.h"

namespace roverlab::io {

namespace fs = std::filesystem;

namespace {

// Temporary files being written, removed by a signal handler when the
// program is interrupted (Ctrl-C, SIGTERM from a CI cancel or `timeout`), so
// an interrupted run leaves no hidden partial file behind. Fixed slots of
// plain characters: the handler may only call async-signal-safe functions.
constexpr std::size_t kSlots = 16, kPathBytes = 4096;
std::array<std::array<char, kPathBytes>, kSlots> g_temporaries{};
std::array<std::atomic<bool>, kSlots> g_used{};
std::once_flag g_handlers_installed;
struct sigaction g_previous[3];
constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGHUP};

extern "C" void remove_temporaries_and_reraise(int sig) {
  for (std::size_t k = 0; k < kSlots; ++k) {
    if (g_used[k].load()) ::unlink(g_temporaries[k].data());
  }
  for (std::size_t k = 0; k < 3; ++k) {
    if (kSignals[k] == sig) ::sigaction(sig, &g_previous[k], nullptr);
  }
  ::raise(sig);
}

void install_handlers() {
  for (std::size_t k = 0; k < 3; ++k) {
    struct sigaction current {};
    ::sigaction(kSignals[k], nullptr, &current);
    g_previous[k] = current;
    // Leave a program's own handling (the GUI's, a test runner's) alone.
    if (current.sa_handler != SIG_DFL) continue;
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_reraise;
    sigemptyset(&action.sa_mask);
    ::sigaction(kSignals[k], &action, nullptr);
  }
}

// Registers a temporary file for removal on interruption while alive.
class TemporaryRegistration {
 public:
  explicit TemporaryRegistration(const std::string& path) {
    std::call_once(g_handlers_installed, install_handlers);
    if (path.size() >= kPathBytes) return;
    for (std::size_t k = 0; k < kSlots; ++k) {
      bool expected = false;
      if (g_used[k].load() || !g_used[k].compare_exchange_strong(expected, true)) continue;
      // Written while marked used: an interrupt now unlinks a path being
      // written, which at worst names nothing yet.
      std::memcpy(g_temporaries[k].data(), path.c_str(), path.size() + 1);
      slot_ = static_cast<int>(k);
      return;
    }
  }
  ~TemporaryRegistration() {
    if (slot_ >= 0) g_used[static_cast<std::size_t>(slot_)].store(false);
  }
  TemporaryRegistration(const TemporaryRegistration&) = delete;
  TemporaryRegistration& operator=(const TemporaryRegistration&) = delete;

 private:
  int slot_ = -1;
};

// Where the content really goes: a symbolic link's target (the link stays).
fs::path destination_of(const fs::path& target) {
  std::error_code ec;
  if (!fs::is_symlink(target, ec)) return target;
  const fs::path resolved = fs::weakly_canonical(target, ec);
  return ec ? target : resolved;
}

}  // namespace

void write_atomically(const std::string& path, const std::function<void(const std::string& temporary_path)>& write) {
  static std::atomic<unsigned> counter{0};
  const fs::path target = destination_of(fs::path(path));
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (path.empty()) throw InputError("''", "cannot write: the output name is empty");
  const std::string name = target.filename().string();
  for (const char* extension : {".h5", ".hdf5", ".csv", ".png", ".html", ".json"}) {
    if (name == extension) throw InputError(path, "cannot write: the output has no name before its extension");
  }
  if (!fs::is_directory(folder, ec)) {
    throw InputError(path, "cannot write: folder '" + folder.string() + "' does not exist");
  }
  if (fs::is_directory(target, ec)) throw InputError(path, "cannot write: it is a folder");
  if (::access(folder.c_str(), W_OK) != 0) {
    throw InputError(path, "cannot write: folder '" + folder.string() + "' is not writable");
  }
  struct stat existing {};
  const bool exists = ::stat(target.c_str(), &existing) == 0;
  // The owner's word counts, also for root (who may write anything).
  if (exists && ((existing.st_mode & 0222) == 0 || ::access(target.c_str(), W_OK) != 0)) {
    throw InputError(path, "cannot write: the file is write-protected");
  }
  const fs::path temporary = folder / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                                       std::to_string(counter++));
  const TemporaryRegistration registration(temporary.string());
  // Tried first, so that a folder the system will not let us write in (read-only
  // mount, immutable, /proc) is named as such and not by a library's words.
  // 0666 less the umask, as any new file (a replaced file keeps its own mode, below).
  const int probe = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (probe < 0) {
    throw InputError(path, "cannot write in folder '" + folder.string() + "': " + std::strerror(errno));
  }
  ::close(probe);
  try {
    write(temporary.string());
    // A file replaced keeps its permissions (a private 600 log stays private).
    if (exists) ::chmod(temporary.c_str(), existing.st_mode & 07777);
  } catch (const InputError&) {
    fs::remove(temporary, ec);
    throw;
  } catch (const std::exception& e) {
    fs::remove(temporary, ec);
    // A writer's message names the user's file, never the hidden temporary one.
    std::string message = e.what();
    for (auto at = message.find(temporary.string()); at != std::string::npos; at = message.find(temporary.string())) {
      message.replace(at, temporary.string().size(), path);
    }
    if (message == e.what()) throw;
    throw DataError(message);
  } catch (...) {
    fs::remove(temporary, ec);
    throw;
  }
  fs::rename(temporary, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw InputError(path, "cannot write: " + ec.message());
  }
}

void write_text_atomically(const std::string& path, const std::string& text) {
  write_atomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path, "cannot write: cannot create a temporary file");
    out << text;
    out.flush();
    if (!out) throw InputError(path, "cannot write: write failed (disk full?)");
  });
}

}  // namespace roverlab::io
