#pragma once
// What third-party libraries print on their own (Ceres through glog): silent
// by default, every message on stderr when the user asks with --verbose.
// RoverLab's own errors are one line each and never go through here.

namespace roverlab {

void route_library_messages(bool verbose);
// The choice made by route_library_messages (false before it is called), for
// the libraries routed elsewhere (Qt's messages, in the GUI).
bool library_messages_verbose();

}  // namespace roverlab
