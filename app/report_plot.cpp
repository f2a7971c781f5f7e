#include "app/report_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace roverlab::app {

namespace {

constexpr double kWidth = 540, kHeight = 320;
constexpr double kLeft = 70, kRight = 14, kTop = 46, kBottom = 50;

std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string tick_text(double v, double step) {
  if (std::abs(v) < step * 1e-6) v = 0.0;
  char b[32];
  std::snprintf(b, sizeof b, "%.*g", std::abs(v) >= 1e5 || std::abs(v) < 1e-3 ? 2 : 6, v);
  return b;
}

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return !(hi >= lo); }
};

// The data's ranges (y as log10 on a log axis), widened when flat.
void data_ranges(const PlotSpec& spec, Range& x, Range& y) {
  for (const auto& s : spec.series) {
    for (std::size_t k = 0; k < s.x.size() && k < s.y.size(); ++k) {
      if (!std::isfinite(s.x[k]) || !std::isfinite(s.y[k]) || (spec.log_y && s.y[k] <= 0)) continue;
      x.add(s.x[k]);
      y.add(spec.log_y ? std::log10(s.y[k]) : s.y[k]);
    }
  }
  for (Range* r : {&x, &y}) {
    if (r->empty()) *r = {0.0, 1.0};
    if (r->hi - r->lo < 1e-12 * std::max(1.0, std::abs(r->hi))) {
      r->lo -= 0.5;
      r->hi += 0.5;
    }
  }
  if (spec.log_y) {
    y.lo = std::floor(y.lo);
    y.hi = std::max(std::ceil(y.hi), y.lo + 1.0);
  }
}

class Canvas {
 public:
  Canvas(Range x, Range y) : x_(x), y_(y) {}
  double px(double x) const { return kLeft + (x - x_.lo) / (x_.hi - x_.lo) * (kWidth - kLeft - kRight); }
  double py(double y) const { return kHeight - kBottom - (y - y_.lo) / (y_.hi - y_.lo) * (kHeight - kTop - kBottom); }

 private:
  Range x_, y_;
};

void axes(std::ostringstream& s, const PlotSpec& spec, const Canvas& c, const std::vector<double>& xt,
          const std::vector<double>& yt) {
  const double x0 = kLeft, x1 = kWidth - kRight, y0 = kHeight - kBottom, y1 = kTop;
  s << "<rect x=\"" << x0 << "\" y=\"" << y1 << "\" width=\"" << x1 - x0 << "\" height=\"" << y0 - y1
    << "\" fill=\"none\" stroke=\"#444\"/>";
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1.0, ystep = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  for (const double v : xt) {
    s << "<line x1=\"" << c.px(v) << "\" y1=\"" << y0 << "\" x2=\"" << c.px(v) << "\" y2=\"" << y0 + 5
      << "\" stroke=\"#444\"/><text class=\"tick\" x=\"" << c.px(v) << "\" y=\"" << y0 + 18
      << "\" text-anchor=\"middle\" font-size=\"11\">" << tick_text(v, xstep) << "</text>";
  }
  for (const double v : yt) {
    const std::string label = spec.log_y ? tick_text(std::pow(10.0, v), std::pow(10.0, v)) : tick_text(v, ystep);
    s << "<line x1=\"" << x0 << "\" y1=\"" << c.py(v) << "\" x2=\"" << x1 << "\" y2=\"" << c.py(v)
      << "\" stroke=\"#e4e4e4\"/><text class=\"tick\" x=\"" << x0 - 6 << "\" y=\"" << c.py(v) + 4
      << "\" text-anchor=\"end\" font-size=\"11\">" << label << "</text>";
  }
  s << "<text class=\"x-title\" x=\"" << (x0 + x1) / 2 << "\" y=\"" << kHeight - 10
    << "\" text-anchor=\"middle\" font-size=\"12\">" << escape(spec.x_title) << "</text>"
    << "<text class=\"y-title\" transform=\"translate(16," << (y0 + y1) / 2
    << ") rotate(-90)\" text-anchor=\"middle\" font-size=\"12\">" << escape(spec.y_title) << "</text>"
    << "<text x=\"" << x0 << "\" y=\"15\" font-size=\"13\" font-weight=\"bold\">" << escape(spec.title) << "</text>";
}

// Legend in one row between the title and the data.
void legend(std::ostringstream& s, const PlotSpec& spec) {
  double at = kLeft;
  for (const auto& series : spec.series) {
    s << "<rect x=\"" << at << "\" y=\"25\" width=\"14\" height=\"8\" fill=\"" << series.colour
      << "\"/><text class=\"legend\" x=\"" << at + 18 << "\" y=\"33\" font-size=\"11\">" << escape(series.name)
      << "</text>";
    at += 30 + 6.2 * static_cast<double>(series.name.size());
  }
}

void draw_series(std::ostringstream& s, const PlotSpec& spec, const PlotSeries& series, const Canvas& c) {
  std::string path;
  bool pen_down = false;
  for (std::size_t k = 0; k < series.x.size() && k < series.y.size(); ++k) {
    const double x = series.x[k], y = series.y[k];
    const bool ok = std::isfinite(x) && std::isfinite(y) && (!spec.log_y || y > 0);
    if (!ok) {
      pen_down = false;
      continue;
    }
    const double px = c.px(x), py = c.py(spec.log_y ? std::log10(y) : y);
    char b[64];
    if (series.points) {
      std::snprintf(b, sizeof b, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"1.6\"/>", px, py);
      path += b;
    } else {
      std::snprintf(b, sizeof b, "%s%.1f %.1f ", pen_down ? "L" : "M", px, py);
      path += b;
      pen_down = true;
    }
  }
  if (series.points) {
    s << "<g class=\"series\" fill=\"" << series.colour << "\" fill-opacity=\"0.7\">" << path << "</g>";
  } else if (!path.empty()) {
    s << "<path class=\"series\" d=\"" << path << "\" fill=\"none\" stroke=\"" << series.colour
      << "\" stroke-width=\"1.4\"/>";
  }
}

}  // namespace

std::vector<double> round_ticks(double lo, double hi, int count) {
  std::vector<double> ticks;
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo) || count < 1) return ticks;
  const double raw = (hi - lo) / count, power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * power;
    if (step >= raw) break;
  }
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step) ticks.push_back(v);
  return ticks;
}

std::string plot_svg(const PlotSpec& spec) {
  Range x, y;
  data_ranges(spec, x, y);
  std::vector<double> yt;
  if (spec.log_y) {
    for (double d = y.lo; d <= y.hi + 1e-9; d += std::max(1.0, std::ceil((y.hi - y.lo) / 6))) yt.push_back(d);
  } else {
    yt = round_ticks(y.lo, y.hi);
    // The axis ends on ticks, so no curve touches the frame unlabelled.
    if (!yt.empty() && yt.size() > 1) {
      const double step = yt[1] - yt[0];
      if (yt.front() > y.lo + 1e-12) yt.insert(yt.begin(), yt.front() - step);
      if (yt.back() < y.hi - 1e-12) yt.push_back(yt.back() + step);
      y = {yt.front(), yt.back()};
    }
  }
  const Canvas c(x, y);
  std::ostringstream s;
  s << "<svg class=\"" << escape(spec.css_class) << "\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << kWidth
    << " " << kHeight << "\" width=\"" << kWidth << "\" height=\"" << kHeight
    << "\" style=\"max-width:100%;height:auto\" font-family=\"sans-serif\">";
  axes(s, spec, c, round_ticks(x.lo, x.hi), yt);
  legend(s, spec);
  for (const auto& series : spec.series) draw_series(s, spec, series, c);
  if (!spec.marker_label.empty() && spec.marker_x > x.lo && spec.marker_x < x.hi) {
    const double m = c.px(spec.marker_x);
    s << "<line x1=\"" << m << "\" y1=\"" << kTop << "\" x2=\"" << m << "\" y2=\"" << kHeight - kBottom
      << "\" stroke=\"#888\" stroke-dasharray=\"4 3\"/><text x=\"" << m + 3 << "\" y=\"" << kTop + 12
      << "\" font-size=\"10\" fill=\"#555\">" << escape(spec.marker_label) << "</text>";
  }
  s << "</svg>";
  return s.str();
}

}  // namespace roverlab::app
