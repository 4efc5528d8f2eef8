// PNG input/output as plain pixels, and image statistics for checks.

#include "geartopo/render/image.hpp"
#include "geartopo/core/atomic_file.hpp"
#include "detail/offscreen.hpp"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

namespace geartopo::render {

namespace detail {

void write_vtk_png(vtkImageData* image, const std::filesystem::path& png) {
  // Written to a temporary beside it and renamed when complete: a full disk leaves no half PNG under the final name.
  output::write_atomically_via_path(png, [&](const std::filesystem::path& tmp) {
    {
      // vtkPNGWriter only logs when it cannot open the file: find out first, with a clear message.
      std::ofstream probe(tmp, std::ios::binary | std::ios::trunc);
      if (!probe) throw output::OutputError(png, "cannot create a temporary file beside it");
    }
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputData(image);
    writer->Write();
    if (writer->GetErrorCode() != 0) throw output::OutputError(png, "the PNG writer failed (a full disk?)");
  });
}

} // namespace detail

Image read_png(const std::filesystem::path& png) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(png, ec)) throw std::runtime_error("render: no PNG file at " + png.string());
  vtkNew<vtkPNGReader> reader;
  if (reader->CanReadFile(png.c_str()) == 0) throw std::runtime_error("render: not a PNG file: " + png.string());
  reader->SetFileName(png.c_str());
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  int dims[3] = {0, 0, 0};
  data->GetDimensions(dims);
  const int channels = data->GetNumberOfScalarComponents();
  if (dims[0] < 1 || dims[1] < 1 || data->GetScalarType() != VTK_UNSIGNED_CHAR || channels < 1 || channels > 4)
    throw std::runtime_error("render: unsupported PNG (8-bit grey/RGB with optional alpha only): " + png.string());
  Image image;
  image.width = dims[0];
  image.height = dims[1];
  image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
  const auto* src = static_cast<const unsigned char*>(data->GetScalarPointer());
  for (int y = 0; y < image.height; ++y) {
    const unsigned char* row = src + static_cast<std::size_t>(image.height - 1 - y) * image.width * channels;
    for (int x = 0; x < image.width; ++x) {
      const unsigned char* p = row + static_cast<std::size_t>(x) * channels;
      Rgb& out = image.pixels[static_cast<std::size_t>(y) * image.width + x];
      out = channels >= 3 ? Rgb{p[0], p[1], p[2]} : Rgb{p[0], p[0], p[0]};
    }
  }
  return image;
}

void write_png(const Image& image, const std::filesystem::path& png) {
  if (image.width < 1 || image.height < 1 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height)
    throw std::invalid_argument("render: write_png of an empty or inconsistent image");
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* dst = static_cast<unsigned char*>(data->GetScalarPointer());
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const Rgb& c = image.at(x, y);
      unsigned char* p = dst + (static_cast<std::size_t>(image.height - 1 - y) * image.width + x) * 3;
      p[0] = c.r;
      p[1] = c.g;
      p[2] = c.b;
    }
  detail::write_vtk_png(data, png);
}

namespace {
bool near(const Rgb& a, const Rgb& b, int tolerance) {
  return std::abs(a.r - b.r) <= tolerance && std::abs(a.g - b.g) <= tolerance && std::abs(a.b - b.b) <= tolerance;
}
} // namespace

ImageStats image_stats(const Image& image, Rgb background, int tolerance) {
  ImageStats s;
  s.width = image.width;
  s.height = image.height;
  if (image.pixels.empty()) return s;
  double sum = 0.0;
  double sum2 = 0.0;
  std::size_t foreground = 0;
  for (const Rgb& c : image.pixels) {
    const double grey = 0.299 * c.r + 0.587 * c.g + 0.114 * c.b;
    sum += grey;
    sum2 += grey * grey;
    if (!near(c, background, tolerance)) ++foreground;
  }
  const double n = static_cast<double>(image.pixels.size());
  s.variance = std::max(0.0, sum2 / n - (sum / n) * (sum / n));
  s.non_background_share = static_cast<double>(foreground) / n;
  return s;
}

ImageStats image_stats(const std::filesystem::path& png, Rgb background, int tolerance) {
  return image_stats(read_png(png), background, tolerance);
}

std::size_t count_colour(const Image& image, Rgb colour, int tolerance) {
  std::size_t n = 0;
  for (const Rgb& c : image.pixels)
    if (near(c, colour, tolerance)) ++n;
  return n;
}

bool contains_colour(const Image& image, Rgb colour, int tolerance, std::size_t min_pixels) {
  return count_colour(image, colour, tolerance) >= min_pixels;
}

} // namespace geartopo::render
