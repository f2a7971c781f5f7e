#pragma once
// A plot for the HTML report as inline SVG: axes with round tick values, the
// quantity and unit on each axis, a legend above the data (never over it),
// series as lines or points, an optional vertical marker (where the held-out
// part starts). The discrepancy studies draw their residuals before and after
// the named cause with it.

#include <string>
#include <utility>
#include <vector>

namespace roverlab::app {

struct PlotSeries {
  PlotSeries() = default;
  PlotSeries(std::string name_, std::string colour_, std::vector<double> y_)
      : name(std::move(name_)), colour(std::move(colour_)), y(std::move(y_)) {}
  std::string name;    // in the legend
  std::string colour;  // CSS colour
  std::vector<double> x, y;
  bool points = false;  // dots (a scatter) rather than a line; NaN breaks a line
};

struct PlotSpec {
  PlotSpec() = default;
  PlotSpec(std::string title_, std::string x_title_, std::string y_title_, std::vector<PlotSeries> series_)
      : title(std::move(title_)),
        x_title(std::move(x_title_)),
        y_title(std::move(y_title_)),
        series(std::move(series_)) {}
  std::string title;
  std::string x_title, y_title;  // "time (s)", "position error (m)"
  std::vector<PlotSeries> series;
  bool log_y = false;  // decades on y (values <= 0 are left out)
  double marker_x = 0.0;
  std::string marker_label;  // drawn at marker_x when not empty
  std::string css_class = "plot";
};

// Round tick values covering [lo, hi]: steps of 1, 2 or 5 times a power of
// ten, about `count` of them.
std::vector<double> round_ticks(double lo, double hi, int count = 5);

// The plot as an <svg> element, 540 x 320 CSS pixels, scaling down with the page.
std::string plot_svg(const PlotSpec& spec);

}  // namespace roverlab::app
