#include "core/common/library_messages.h"

#include <glog/logging.h>

namespace roverlab {

void route_library_messages(bool verbose) {
  static const bool initialised = [] {
    google::InitGoogleLogging("roverlab");
    return true;
  }();
  (void)initialised;
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = verbose ? google::GLOG_INFO : google::GLOG_FATAL;
}

}  // namespace roverlab
