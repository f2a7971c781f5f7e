#include "views/display_series.h"

#include <algorithm>
#include <cmath>

#include <vtkDoubleArray.h>
#include <vtkNew.h>

namespace roverlab::views {

DisplaySeries decimate_min_max(const std::vector<double>& time, const std::vector<double>& values, double t0, double t1,
                               std::size_t buckets) {
  DisplaySeries out;
  const auto begin = static_cast<std::size_t>(std::lower_bound(time.begin(), time.end(), t0) - time.begin());
  const auto end = static_cast<std::size_t>(std::upper_bound(time.begin(), time.end(), t1) - time.begin());
  if (end <= begin) return out;
  const std::size_t n = end - begin;
  buckets = std::max<std::size_t>(buckets, 1);
  if (n <= 2 * buckets) {
    for (std::size_t i = begin; i < end; ++i) {
      if (std::isnan(values[i])) continue;
      out.time.push_back(time[i]);
      out.value.push_back(values[i]);
    }
    return out;
  }
  out.time.reserve(2 * buckets);
  out.value.reserve(2 * buckets);
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::size_t lo = begin + n * b / buckets;
    const std::size_t hi = begin + n * (b + 1) / buckets;
    // NaN compares false both ways, so missing samples are skipped.
    std::size_t imin = hi, imax = hi;
    double vmin = HUGE_VAL, vmax = -HUGE_VAL;
    for (std::size_t i = lo; i < hi; ++i) {
      const double v = values[i];
      if (v < vmin) {
        vmin = v;
        imin = i;
      }
      if (v > vmax) {
        vmax = v;
        imax = i;
      }
    }
    if (imin == hi && imax == hi) continue;  // bucket of missing samples: a gap
    if (imin == hi) imin = imax;             // all equal to +inf
    if (imax == hi) imax = imin;
    const std::size_t first = std::min(imin, imax), second = std::max(imin, imax);
    out.time.push_back(time[first]);
    out.value.push_back(values[first]);
    if (second != first) {
      out.time.push_back(time[second]);
      out.value.push_back(values[second]);
    }
  }
  return out;
}

vtkSmartPointer<vtkTable> make_display_table(const log::Stream& stream, const std::string& channel, double t0,
                                             double t1, std::size_t buckets) {
  const log::Channel& c = stream.channel(channel);
  const DisplaySeries series = decimate_min_max(stream.time(), c.values, t0, t1, buckets);
  vtkNew<vtkDoubleArray> time;
  time->SetName("time");
  vtkNew<vtkDoubleArray> value;
  value->SetName(c.name.c_str());
  time->SetNumberOfValues(static_cast<vtkIdType>(series.time.size()));
  value->SetNumberOfValues(static_cast<vtkIdType>(series.value.size()));
  for (std::size_t i = 0; i < series.time.size(); ++i) {
    time->SetValue(static_cast<vtkIdType>(i), series.time[i]);
    value->SetValue(static_cast<vtkIdType>(i), series.value[i]);
  }
  vtkNew<vtkTable> table;
  table->AddColumn(time);
  table->AddColumn(value);
  return table;
}

}  // namespace roverlab::views
