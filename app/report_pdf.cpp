#include "app/report_pdf.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "core/common/error.h"
#include "importers/atomic_file.h"
#include "views/x_display.h"

namespace roverlab::app {

namespace {

namespace fs = std::filesystem;

// "file://" and the path with every byte but A-Z a-z 0-9 - . _ ~ / as %XX
// (RFC 3986): a folder named "pdf%41B" or "run#3" is that folder, not "pdfAB"
// or "run" with a fragment.
std::string file_url(const fs::path& path) {
  static const char* const kHex = "0123456789ABCDEF";
  std::string url = "file://";
  for (const char c : path.string()) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) != 0 || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      url += c;
    } else {
      url += '%';
      url += kHex[u >> 4];
      url += kHex[u & 15];
    }
  }
  return url;
}

std::string find_program(const std::string& name) {
  const char* path = std::getenv("PATH");
  const std::string p = path != nullptr ? path : "/usr/bin:/bin";
  for (std::size_t a = 0; a <= p.size();) {
    std::size_t b = p.find(':', a);
    if (b == std::string::npos) b = p.size();
    const fs::path candidate = fs::path(p.substr(a, b - a)) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    a = b + 1;
  }
  return {};
}

// Runs argv with its output to /dev/null, ended after `limit`; its exit status
// (-1 when it timed out or could not start).
int run_quietly(const std::vector<std::string>& argv, std::chrono::seconds limit) {
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));  // NOLINT: execv takes char* const*
  args.push_back(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // the browser ends with RoverLab
    if (::getppid() != parent) ::_exit(127);
    ::setpgid(0, 0);  // its own group: a timeout ends its helper processes too
    const int devnull = ::open("/dev/null", O_RDWR);
    if (devnull >= 0) {
      ::dup2(devnull, 0);
      ::dup2(devnull, 1);
      ::dup2(devnull, 2);
    }
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + limit;
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) return -1;
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(-pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool starts_with_pdf_magic(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  char head[5] = {};
  in.read(head, 5);
  return in.gcount() == 5 && std::string(head, 5) == "%PDF-";
}

}  // namespace

std::string report_pdf_printer() {
  std::string chromium = find_program("chromium");
  if (chromium.empty()) {
    throw views::EnvironmentError(
        "--pdf: the report is printed by Chromium, which is not on PATH (apt-get install chromium, or "
        "scripts/install-deps)");
  }
  return chromium;
}

void print_report_pdf(const std::string& html_file, const std::string& pdf_file) {
  const std::string chromium = report_pdf_printer();
  std::error_code ec;
  const fs::path page = fs::absolute(html_file, ec);
  io::write_atomically(pdf_file, [&](const std::string& temporary) {
    // A profile of its own, removed after: nothing of the user's browser is read or changed.
    const fs::path profile = fs::path(temporary + ".profile");
    struct stat created {};
    const bool have_mode = ::stat(temporary.c_str(), &created) == 0;
    const std::vector<std::string> argv = {chromium,
                                           "--headless",
                                           "--no-sandbox",
                                           "--disable-gpu",
                                           "--no-first-run",
                                           "--user-data-dir=" + profile.string(),
                                           "--no-pdf-header-footer",
                                           "--print-to-pdf=" + temporary,
                                           file_url(page)};
    const int status = run_quietly(argv, std::chrono::seconds(180));
    std::error_code ignored;
    fs::remove_all(profile, ignored);
    if (status != 0 || !starts_with_pdf_magic(temporary)) {
      throw InputError(pdf_file,
                       status < 0 ? "Chromium did not print the report within 180 s"
                                  : "Chromium could not print the report (exit status " + std::to_string(status) + ")");
    }
    // The mode the umask gave the temporary file, whatever the browser's own writer does.
    if (have_mode) ::chmod(temporary.c_str(), created.st_mode & 07777);
  });
}

}  // namespace roverlab::app
