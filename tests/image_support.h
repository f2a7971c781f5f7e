#pragma once
// Pictures in tests: the pixels of a colour in a region, their count and
// centroid (the render, report and scene tests check content this way).

#include <functional>

#include "views/offscreen.h"

namespace roverlab::test {

struct Region {
  int count = 0;
  double mean_x = 0, mean_y = 0;
};

// Pixels in [x0, x1) x [y0, y1) matching `pred` (r, g, b): their count and centroid.
inline Region find_pixels(const views::Image& img, const std::function<bool(int, int, int)>& pred, int x0 = 0,
                          int x1 = -1, int y0 = 0, int y1 = -1) {
  Region r;
  if (x1 < 0) x1 = img.width;
  if (y1 < 0) y1 = img.height;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const unsigned char* p = img.pixel(x, y);
      if (pred(p[0], p[1], p[2])) {
        ++r.count;
        r.mean_x += x;
        r.mean_y += y;
      }
    }
  }
  if (r.count > 0) {
    r.mean_x /= r.count;
    r.mean_y /= r.count;
  }
  return r;
}

}  // namespace roverlab::test
