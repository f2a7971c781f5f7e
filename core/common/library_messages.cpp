#include "core/common/library_messages.h"

#include <glog/logging.h>

namespace roverlab {

namespace {
bool g_verbose = false;
}  // namespace

bool library_messages_verbose() { return g_verbose; }

void route_library_messages(bool verbose) {
  g_verbose = verbose;
  static const bool initialised = [] {
    google::InitGoogleLogging("roverlab");
    return true;
  }();
  (void)initialised;
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = verbose ? google::GLOG_INFO : google::GLOG_FATAL;
}

}  // namespace roverlab
