#pragma once
// Rendering a view to an RGB image without a window on screen (Debian's VTK
// renders through GLX: an X server, e.g. Xvfb, must be reachable), and
// writing it as PNG.

#include <string>
#include <vector>

#include <vtkSmartPointer.h>

class vtkRenderWindow;

namespace roverlab::views {

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;  // row-major from the top, 3 bytes per pixel
  const unsigned char* pixel(int x, int y) const { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
};

// An offscreen render window of the given size (multisampling off, so that
// images repeat pixel for pixel on one machine).
vtkSmartPointer<vtkRenderWindow> make_offscreen_window(int width, int height);

// Renders the window and reads its pixels back.
Image capture(vtkRenderWindow* window);

// VTK's own warnings and error lines: off unless `verbose` (RoverLab says what
// went wrong in its own words).
void route_vtk_messages(bool verbose);

// Writes a PNG (to exactly `path`; callers make it atomic).
void write_png(const Image& image, const std::string& path);
Image read_png(const std::string& path);

}  // namespace roverlab::views
