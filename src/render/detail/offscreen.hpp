#pragma once
// Internal: an off-screen OpenGL context (Mesa EGL, surfaceless platform: no X, no DISPLAY) with a VTK render
// window on it. Forward declarations only: VTK and EGL headers stay in the .cpp files.

#include <filesystem>
#include <memory>
#include <mutex>

class vtkGenericOpenGLRenderWindow;
class vtkImageData;

namespace geartopo::render::detail {

/// Serialises all VTK work of this library: VTK's font cache and object factories are process-wide singletons.
std::mutex& render_mutex();

/// A figure's borrow of the process's one OpenGL context and render window (kept between figures, so that shaders are
/// compiled once per process, not per figure). Construct it BEFORE any VTK object of the figure and let it die after
/// them (declare it first): the figure's renderers leave the window, releasing their OpenGL resources, while the
/// context is still current. Holds render_mutex() for its lifetime. Throws std::runtime_error when no EGL/OpenGL
/// context can be made.
class Offscreen {
public:
  Offscreen(int width, int height);
  ~Offscreen();
  Offscreen(const Offscreen&) = delete;
  Offscreen& operator=(const Offscreen&) = delete;

  vtkGenericOpenGLRenderWindow* window() const;
  /// Renders the window and writes its pixels (RGB) to `png`.
  void save_png(const std::filesystem::path& png);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes an 8-bit RGB vtkImageData to `png` (rows bottom-up, as VTK stores them). Throws output::OutputError when the
/// file cannot be written, std::invalid_argument for another pixel format.
void write_vtk_png(vtkImageData* image, const std::filesystem::path& png);

/// Defined in glew_init_wrapper.cpp; called from Offscreen so that a static link always pulls that file in.
void link_glew_init_wrapper();

} // namespace geartopo::render::detail
