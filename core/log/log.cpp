#include "core/log/log.h"

#include "core/common/error.h"

namespace roverlab::log {

Stream& Log::add_stream(Stream stream) {
  if (find_stream(stream.name()) != nullptr) {
    throw DataError("stream '" + stream.name() + "' appears twice");
  }
  index_.emplace(stream.name(), streams_.size());
  streams_.push_back(std::move(stream));
  return streams_.back();
}

Stream& Log::replace_stream(Stream stream) {
  const auto it = index_.find(stream.name());
  if (it == index_.end()) return add_stream(std::move(stream));
  Stream& s = streams_[it->second];
  s = std::move(stream);
  return s;
}

const Stream* Log::find_stream(std::string_view name) const {
  const auto it = index_.find(std::string(name));
  return it == index_.end() ? nullptr : &streams_[it->second];
}

const Stream& Log::stream(std::string_view name) const {
  const Stream* s = find_stream(name);
  if (s == nullptr) throw DataError("log has no stream '" + std::string(name) + "'");
  return *s;
}

const Channel& Log::channel(std::string_view path) const {
  const std::size_t slash = path.rfind('/');
  if (slash == std::string_view::npos || slash == 0 || slash + 1 == path.size()) {
    throw DataError("channel path '" + std::string(path) + "' is not of the form stream/channel");
  }
  return stream(path.substr(0, slash)).channel(path.substr(slash + 1));
}

Log Log::slice(double t0, double t1) const {
  Log out;
  out.metadata = metadata;
  out.index_ = index_;
  for (const auto& s : streams_) out.streams_.push_back(s.slice(t0, t1));
  return out;
}

std::size_t Log::total_samples() const {
  std::size_t n = 0;
  for (const auto& s : streams_) n += s.size() * (s.channels().size() + 1);
  return n;
}

std::size_t Log::payload_bytes() const { return total_samples() * sizeof(double); }

}  // namespace roverlab::log
