#include "core/estimation/reference_track.h"

#include <cmath>

#include "core/log/stream.h"

namespace roverlab::estimation {

ReferenceTrack reference_from_gps(const log::Log& lg, const std::string& name) {
  ReferenceTrack r;
  const log::Stream* gps = lg.find_stream(name);
  if (gps == nullptr || gps->find_channel("east") == nullptr || gps->find_channel("north") == nullptr) return r;
  r.present = gps->size() >= 3;
  r.time = gps->time();
  r.east = gps->channel("east").values;
  r.north = gps->channel("north").values;
  r.up = gps->find_channel("up") ? gps->channel("up").values : std::vector<double>(r.time.size(), 0.0);
  if (gps->find_channel("latitude") && gps->find_channel("longitude") && !gps->empty()) {
    r.latitude = gps->channel("latitude").values.front();
    r.longitude = gps->channel("longitude").values.front();
    r.height = gps->find_channel("height") ? gps->channel("height").values.front() : 0.0;
  }
  const std::size_t n = r.time.size();
  r.v_east.assign(n, 0.0);
  r.v_north.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t a = i, b = i;
    while (a > 0 && r.time[i] - r.time[a - 1] <= 0.5) --a;
    while (b + 1 < n && r.time[b + 1] - r.time[i] <= 0.5) ++b;
    if (b > a) {
      r.v_east[i] = (r.east[b] - r.east[a]) / (r.time[b] - r.time[a]);
      r.v_north[i] = (r.north[b] - r.north[a]) / (r.time[b] - r.time[a]);
    }
  }
  return r;
}

double initial_course(const ReferenceTrack& ref, double distance, std::size_t from) {
  if (from >= ref.time.size()) return NAN;
  std::size_t k = from;
  auto away = [&](std::size_t i) { return std::hypot(ref.east[i] - ref.east[from], ref.north[i] - ref.north[from]); };
  while (k + 1 < ref.time.size() && away(k) < distance) ++k;
  return away(k) > 1.0 ? std::atan2(ref.east[k] - ref.east[from], ref.north[k] - ref.north[from]) : NAN;
}

double course_at(const ReferenceTrack& ref, double t, double min_speed) {
  const double ve = log::interpolate_linear(ref.time, ref.v_east, t);
  const double vn = log::interpolate_linear(ref.time, ref.v_north, t);
  if (!(std::hypot(ve, vn) >= min_speed)) return NAN;
  return std::atan2(ve, vn);
}

std::vector<double> distance_along(const ReferenceTrack& ref, double step) {
  // Summing every 10 Hz increment would add the position noise to the
  // distance; count a segment only once it is `step` long.
  std::vector<double> d(ref.time.size(), 0.0);
  std::size_t anchor = 0;
  double total = 0.0;
  for (std::size_t i = 1; i < d.size(); ++i) {
    const double seg = std::hypot(ref.east[i] - ref.east[anchor], ref.north[i] - ref.north[anchor]);
    if (seg >= step) {
      total += seg;
      anchor = i;
    }
    d[i] = total;
  }
  return d;
}

}  // namespace roverlab::estimation
