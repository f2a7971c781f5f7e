#pragma once
// An X display for VTK's GLX rendering when none is set: a private Xvfb,
// started on a free display number and stopped when the process exits, also
// when it is killed or crashes (the kernel stops Xvfb with its parent).

#include <stdexcept>
#include <string>

namespace roverlab::views {

// Returns the DISPLAY in use. Throws EnvironmentError (one line, says how to
// run headless) when DISPLAY is unset and Xvfb cannot be started.
std::string ensure_display();

// The private Xvfb's process id, -1 when none was started. Call
// ensure_display from the main thread: Xvfb stops when the thread that
// started it ends.
int private_xvfb_pid();

class EnvironmentError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace roverlab::views
