#pragma once
// Error types shared by every layer. The CLI maps them to exit codes:
// InputError -> 3 (bad input), anything else -> 4 (internal failure).

#include <stdexcept>
#include <string>

namespace roverlab {

// Data that violates the log model's rules (non-finite or non-increasing time,
// channel length different from its time base, unknown unit, ...).
class DataError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A problem with an input file, with the file named. what() is one line:
// "<file>: <problem>".
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& problem)
      : std::runtime_error(one_line(file + ": " + problem)), file_(file), problem_(problem) {}
  const std::string& file() const { return file_; }
  const std::string& problem() const { return problem_; }

 private:
  static std::string one_line(std::string text) {
    for (char& c : text) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    return text;
  }
  std::string file_;
  std::string problem_;
};

}  // namespace roverlab
