#include "views/offscreen.h"

#include <vtkImageData.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <cstring>
#include <stdexcept>

#include "core/common/error.h"

namespace roverlab::views {

vtkSmartPointer<vtkRenderWindow> make_offscreen_window(int width, int height) {
  if (width < 16 || height < 16 || width > 8192 || height > 8192) {
    throw DataError("image size " + std::to_string(width) + "x" + std::to_string(height) + " outside 16..8192");
  }
  auto w = vtkSmartPointer<vtkRenderWindow>::New();
  w->SetOffScreenRendering(1);
  w->SetMultiSamples(0);
  w->SetSize(width, height);
  return w;
}

Image capture(vtkRenderWindow* window) {
  // Twice: a chart lays its plots out with the margins its last render's tick labels needed (TimeSeriesChart).
  window->Render();
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* data = grab->GetOutput();
  int dims[3];
  data->GetDimensions(dims);
  Image img;
  img.width = dims[0];
  img.height = dims[1];
  img.rgb.resize(static_cast<std::size_t>(3) * img.width * img.height);
  auto* scalars = static_cast<unsigned char*>(data->GetScalarPointer());
  // VTK's rows go bottom-up.
  for (int y = 0; y < img.height; ++y) {
    std::memcpy(&img.rgb[3 * static_cast<std::size_t>(y) * img.width],
                scalars + 3 * static_cast<std::size_t>(img.height - 1 - y) * img.width,
                3 * static_cast<std::size_t>(img.width));
  }
  return img;
}

void route_vtk_messages(bool verbose) {
  vtkObject::SetGlobalWarningDisplay(verbose ? 1 : 0);
  vtkLogger::SetStderrVerbosity(verbose ? vtkLogger::VERBOSITY_WARNING : vtkLogger::VERBOSITY_OFF);
}

void write_png(const Image& img, const std::string& path) {
  vtkNew<vtkImageData> data;
  data->SetDimensions(img.width, img.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* out = static_cast<unsigned char*>(data->GetScalarPointer());
  for (int y = 0; y < img.height; ++y) {
    std::memcpy(out + 3 * static_cast<std::size_t>(img.height - 1 - y) * img.width,
                &img.rgb[3 * static_cast<std::size_t>(y) * img.width], 3 * static_cast<std::size_t>(img.width));
  }
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(data);
  writer->Write();
  if (writer->GetErrorCode() != 0) throw DataError("could not write PNG " + path);
}

Image read_png(const std::string& path) {
  vtkNew<vtkPNGReader> reader;
  if (!reader->CanReadFile(path.c_str())) throw DataError(path + ": not a PNG file");
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  int dims[3];
  data->GetDimensions(dims);
  const int comps = data->GetNumberOfScalarComponents();
  Image img;
  img.width = dims[0];
  img.height = dims[1];
  img.rgb.resize(static_cast<std::size_t>(3) * img.width * img.height);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const auto* p = static_cast<unsigned char*>(data->GetScalarPointer(x, img.height - 1 - y, 0));
      for (int c = 0; c < 3; ++c)
        img.rgb[3 * (static_cast<std::size_t>(y) * img.width + x) + c] = p[comps >= 3 ? c : 0];
    }
  }
  return img;
}

}  // namespace roverlab::views
