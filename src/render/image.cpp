// PNG input/output as plain pixels, and image statistics for checks.

#include "geartopo/render/image.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "detail/offscreen.hpp"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <set>
#include <thread>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

namespace geartopo::render {

namespace detail {

namespace {

/// Writes `height` rows of `width` RGB pixels, top row first, to `png` with libpng: no row filter (these figures are
/// flat colours, lines and text, which filters make larger) at zlib level 5 — about half the time of vtkPNGWriter's
/// adaptive filters, and smaller files. Through a temporary beside it, renamed when complete: a full disk leaves no
/// half PNG under the final name.
void encode_png(int width, int height, const std::function<const unsigned char*(int row)>& row_of,
                const std::filesystem::path& png) {
  output::write_atomically_via_path(png, [&](const std::filesystem::path& tmp) {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (f == nullptr) throw output::OutputError(png, "cannot create a temporary file beside it");
    png_structp writer = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = writer ? png_create_info_struct(writer) : nullptr;
    bool ok = writer != nullptr && info != nullptr;
    if (ok && setjmp(png_jmpbuf(writer)) == 0) { // libpng reports its errors by longjmp to here
      png_init_io(writer, f);
      png_set_IHDR(writer, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGB,
                   PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
      png_set_filter(writer, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
      png_set_compression_level(writer, 5);
      png_write_info(writer, info);
      for (int y = 0; y < height; ++y) png_write_row(writer, row_of(y));
      png_write_end(writer, info);
    } else {
      ok = false;
    }
    png_destroy_write_struct(writer ? &writer : nullptr, info ? &info : nullptr);
    const bool closed = std::fclose(f) == 0;
    if (!ok || !closed) throw output::OutputError(png, "the PNG writer failed (a full disk?)");
  });
}

/// The queue of BackgroundPngWrites: packed top-down RGB buffers and their files, one worker thread.
struct PngQueue {
  struct Job {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb; ///< width × height × 3, top row first
    std::filesystem::path png;
  };
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<Job> jobs;
  std::set<std::filesystem::path> pending; ///< queued or being written
  std::exception_ptr first_error;
  bool stop = false;
  std::thread worker{[this] { run(); }};

  void run() {
    std::unique_lock lock(mutex);
    for (;;) {
      changed.wait(lock, [&] { return stop || !jobs.empty(); });
      if (jobs.empty()) return; // stop, and nothing left
      Job job = std::move(jobs.front());
      jobs.pop_front();
      lock.unlock();
      std::exception_ptr error;
      try {
        const std::size_t stride = static_cast<std::size_t>(job.width) * 3;
        encode_png(job.width, job.height, [&](int y) { return job.rgb.data() + static_cast<std::size_t>(y) * stride; }, job.png);
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      if (error && !first_error) first_error = error;
      pending.erase(job.png);
      changed.notify_all();
    }
  }
  void wait_for(const std::filesystem::path& png) {
    std::unique_lock lock(mutex);
    changed.wait(lock, [&] { return pending.count(png) == 0; });
  }
  void drain() {
    {
      const std::lock_guard lock(mutex);
      stop = true;
    }
    changed.notify_all();
    if (worker.joinable()) worker.join();
  }
};

std::mutex queue_mutex;      // guards `active_queue` (the pointer, not the queue)
PngQueue* active_queue = nullptr;

PngQueue* current_queue() {
  const std::lock_guard lock(queue_mutex);
  return active_queue;
}

/// Writes now, or queues a copy of the rows when a BackgroundPngWrites is alive.
void write_rgb_png(int width, int height, const std::function<const unsigned char*(int row)>& row_of,
                   const std::filesystem::path& png) {
  PngQueue* q = current_queue();
  if (q == nullptr) return encode_png(width, height, row_of, png);
  PngQueue::Job job{width, height, {}, png};
  const std::size_t stride = static_cast<std::size_t>(width) * 3;
  job.rgb.resize(stride * static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) std::memcpy(job.rgb.data() + static_cast<std::size_t>(y) * stride, row_of(y), stride);
  q->wait_for(png); // the same file written twice: in order
  {
    const std::lock_guard lock(q->mutex);
    q->pending.insert(png);
    q->jobs.push_back(std::move(job));
  }
  q->changed.notify_all();
}

} // namespace

void write_vtk_png(vtkImageData* image, const std::filesystem::path& png) {
  int dims[3] = {0, 0, 0};
  image->GetDimensions(dims);
  if (dims[0] < 1 || dims[1] < 1 || image->GetScalarType() != VTK_UNSIGNED_CHAR || image->GetNumberOfScalarComponents() != 3)
    throw std::invalid_argument("render: write_vtk_png of an image that is not 8-bit RGB");
  const auto* pixels = static_cast<const unsigned char*>(image->GetScalarPointer());
  const std::size_t stride = static_cast<std::size_t>(dims[0]) * 3;
  const int height = dims[1];
  // VTK stores rows bottom-up; PNG top-down.
  write_rgb_png(dims[0], height, [&](int y) { return pixels + static_cast<std::size_t>(height - 1 - y) * stride; }, png);
}

} // namespace detail

Image read_png(const std::filesystem::path& written) {
  if (detail::PngQueue* q = detail::current_queue()) q->wait_for(written); // a figure's panel still being written
  const std::filesystem::path png = output::current_location(written); // staged until its output folder commits
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
  static_assert(sizeof(Rgb) == 3, "Image rows are passed to libpng as packed RGB");
  detail::write_rgb_png(image.width, image.height, [&](int y) {
    return reinterpret_cast<const unsigned char*>(&image.pixels[static_cast<std::size_t>(y) * image.width]);
  }, png);
}

BackgroundPngWrites::BackgroundPngWrites() {
  const std::lock_guard lock(detail::queue_mutex);
  if (detail::active_queue != nullptr) throw std::logic_error("render: a BackgroundPngWrites is already alive");
  detail::active_queue = new detail::PngQueue;
}

void BackgroundPngWrites::finish() {
  detail::PngQueue* q = nullptr;
  {
    const std::lock_guard lock(detail::queue_mutex);
    std::swap(q, detail::active_queue); // writes from now on are direct
  }
  if (q == nullptr) return;
  q->drain();
  const std::exception_ptr error = q->first_error;
  delete q;
  if (error) std::rethrow_exception(error);
}

BackgroundPngWrites::~BackgroundPngWrites() {
  try {
    finish();
  } catch (...) { // an exception is already on its way, or finish() was not called: the files are written all the same
  }
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
