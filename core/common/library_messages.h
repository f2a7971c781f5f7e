#pragma once
// What third-party libraries print on their own (Ceres through glog): silent
// by default, every message on stderr when the user asks with --verbose.
// RoverLab's own errors are one line each and never go through here.

namespace roverlab {

void route_library_messages(bool verbose);

}  // namespace roverlab
