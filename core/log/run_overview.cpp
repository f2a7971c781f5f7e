#include "core/log/run_overview.h"
#include "core/log/conventions.h"

#include <cmath>
#include <limits>
#include <vector>

namespace roverlab::analysis {

namespace {

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// Sum of the steps between consecutive finite points (a, b).
double path_length(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0, pa = NAN, pb = NAN;
  for (std::size_t k = 0; k < a.size() && k < b.size(); ++k) {
    if (!std::isfinite(a[k]) || !std::isfinite(b[k])) continue;
    if (std::isfinite(pa)) sum += std::hypot(a[k] - pa, b[k] - pb);
    pa = a[k];
    pb = b[k];
  }
  return sum;
}

// Trapezoidal integral of the speed |(vx, vy, vz)| over time.
double integrated_speed(const log::Stream& s) {
  const auto& t = s.time();
  const auto* vx = s.find_channel("velocity_x");
  const auto* vy = s.find_channel("velocity_y");
  const auto* vz = s.find_channel("velocity_z");
  const auto speed = [&](std::size_t k) {
    const double x = vx->values[k], y = vy ? vy->values[k] : 0.0, z = vz ? vz->values[k] : 0.0;
    return std::sqrt(x * x + y * y + z * z);
  };
  double sum = 0;
  for (std::size_t k = 1; k < t.size(); ++k) {
    const double step = 0.5 * (speed(k - 1) + speed(k)) * (t[k] - t[k - 1]);
    if (std::isfinite(step)) sum += step;
  }
  return sum;
}

}  // namespace

RunOverview overview_of(const log::Log& lg, const std::vector<PoseSource>& sources) {
  RunOverview o;
  o.rover = lg.metadata.rover_id;
  double start = std::numeric_limits<double>::infinity(), end = -start;
  for (const auto& s : lg.streams()) {
    if (starts_with(s.name(), log::kEstimatePrefix) || s.empty()) continue;
    start = std::min(start, s.start_time());
    end = std::max(end, s.end_time());
  }
  if (std::isfinite(start) && std::isfinite(end)) {
    o.start_s = start;
    o.end_s = end;
    o.duration_s = end - start;
  }
  o.distance_m = NAN;
  for (const PoseSource& src : sources) {
    const log::Stream* s = lg.find_stream(src.stream);
    if (s == nullptr || s->size() < 2 || s->find_channel(src.a) == nullptr) continue;
    if (src.b == nullptr) {
      o.distance_m = integrated_speed(*s);
    } else {
      if (s->find_channel(src.b) == nullptr) continue;
      o.distance_m = path_length(s->channel(src.a).values, s->channel(src.b).values);
    }
    o.distance_source = src.stream;
    o.distance_method = src.method;
    break;
  }
  if (const log::Stream* gps = lg.find_stream("gps")) {
    const auto* lat = gps->find_channel("latitude");
    const auto* lon = gps->find_channel("longitude");
    for (std::size_t k = 0; lat != nullptr && lon != nullptr && k < gps->size(); ++k) {
      if (!std::isfinite(lat->values[k]) || !std::isfinite(lon->values[k])) continue;
      o.has_gps_fix = true;
      // SI: radians, unless the channel says degrees.
      o.start_latitude_deg = lat->values[k] * (lat->unit == "deg" ? 1.0 : 180.0 / M_PI);
      o.start_longitude_deg = lon->values[k] * (lon->unit == "deg" ? 1.0 : 180.0 / M_PI);
      break;
    }
  }
  return o;
}

}  // namespace roverlab::analysis
