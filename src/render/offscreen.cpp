// Off-screen OpenGL without a display: a Mesa EGL context on the surfaceless platform, handed to a
// vtkGenericOpenGLRenderWindow (docs/rendering.md, "How off-screen rendering works").

#include "detail/offscreen.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkSmartPointer.h>
#include <vtkWindowToImageFilter.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <dlfcn.h>
#include <link.h>
#include <unistd.h>

namespace geartopo::render::detail {

std::mutex& render_mutex() {
  static std::mutex m;
  return m;
}

namespace {

std::string egl_error_text(EGLint code) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "0x%04X", static_cast<unsigned>(code));
  return buffer;
}

/// The surfaceless EGL display, initialised once per process (terminated at exit with the shared context).
struct Display {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLConfig config = nullptr;
  bool no_config = false; // EGL_KHR_no_config_context used instead of a config
  std::string error;
};

Display open_display() {
  Display d;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (client == nullptr || std::strstr(client, "EGL_MESA_platform_surfaceless") == nullptr) {
    d.error = "the EGL library does not offer the surfaceless platform (EGL_MESA_platform_surfaceless); "
              "install Mesa's EGL (libegl1, libegl-mesa0)";
    return d;
  }
  const auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) {
    d.error = "eglGetPlatformDisplayEXT is not available";
    return d;
  }
  d.display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0;
  EGLint minor = 0;
  if (d.display == EGL_NO_DISPLAY || eglInitialize(d.display, &major, &minor) != EGL_TRUE) {
    d.error = "eglInitialize failed on the surfaceless platform (EGL error " + egl_error_text(eglGetError()) + ")";
    d.display = EGL_NO_DISPLAY;
    return d;
  }
  // clang-format off
  const EGLint attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                               EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                               EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8,
                               EGL_DEPTH_SIZE, 24,
                               EGL_NONE};
  // clang-format on
  EGLint count = 0;
  if (eglChooseConfig(d.display, attributes, &d.config, 1, &count) != EGL_TRUE || count < 1) {
    const char* display_ext = eglQueryString(d.display, EGL_EXTENSIONS);
    if (display_ext != nullptr && std::strstr(display_ext, "EGL_KHR_no_config_context") != nullptr) {
      d.no_config = true;
    } else {
      d.error = "no suitable EGL config for desktop OpenGL";
      return d;
    }
  }
  return d;
}

const Display& surfaceless_display() {
  static const Display d = open_display();
  return d;
}

/// The process's one OpenGL context and the one render window on it, made on first use and kept until the process
/// exits. Every figure borrows them under render_mutex(): a fresh context per figure made Mesa's llvmpipe compile
/// every shader again (LLVM was ~30 % of a `geartopo run`); a kept window keeps VTK's shader cache, and the context
/// keeps llvmpipe's compiled variants. Made current on the borrowing thread and released from it when the figure is
/// done, so any thread may borrow next.
struct SharedContext {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  vtkSmartPointer<vtkGenericOpenGLRenderWindow> window;
};

SharedContext& shared_context() {
  static SharedContext* c = new SharedContext; // not a static object: its end is release_at_exit's, in order
  return *c;
}

/// Keeps the loaded DRI drivers (Mesa's swrast_dri.so) mapped for the rest of the process. eglTerminate unloads the
/// driver; blocks it allocated and still points to from its own globals then look unreferenced, and LeakSanitizer's
/// exit check reported them as leaks (240 bytes, in an "unknown module"). The names are collected first: dlopen is
/// not called from inside dl_iterate_phdr.
void keep_dri_drivers_loaded() {
  std::vector<std::string> drivers;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* found) -> int {
        if (info->dlpi_name != nullptr && std::strstr(info->dlpi_name, "/dri/") != nullptr)
          static_cast<std::vector<std::string>*>(found)->emplace_back(info->dlpi_name);
        return 0;
      },
      &drivers);
  for (const std::string& driver : drivers) dlopen(driver.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
}

/// At exit (std::atexit, registered when the context is first made, so it runs before the static destructors of
/// VTK and Mesa that were constructed before it): the window's OpenGL resources released while its context is
/// current, the context destroyed and the display terminated, which ends llvmpipe's threads. Left alive, those
/// threads and the context outlived main, and LeakSanitizer's exit check crashed beside them. A figure being drawn
/// on another thread (render_mutex() held) keeps everything as it is: the process ends around it; so does a child
/// forked after the context was made (its copy has no llvmpipe threads to end).
pid_t context_owner = 0;

extern "C" void release_at_exit() {
  std::unique_lock lock(render_mutex(), std::try_to_lock);
  if (!lock.owns_lock()) return;
  SharedContext& c = shared_context();
  if (c.context == EGL_NO_CONTEXT || ::getpid() != context_owner) return;
  if (eglBindAPI(EGL_OPENGL_API) == EGL_TRUE &&
      eglMakeCurrent(c.display, EGL_NO_SURFACE, EGL_NO_SURFACE, c.context) == EGL_TRUE) {
    c.window->Finalize();
    c.window = nullptr;
    eglMakeCurrent(c.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  eglDestroyContext(c.display, c.context);
  c.context = EGL_NO_CONTEXT;
  keep_dri_drivers_loaded();
  eglTerminate(c.display);
  eglReleaseThread();
}

void make_current_or_throw(EGLDisplay display, EGLContext context) {
  // The bound API is per thread (the default is OpenGL ES): bind desktop OpenGL on the calling thread.
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE)
    throw std::runtime_error("render: eglBindAPI(EGL_OPENGL_API) failed: desktop OpenGL is not available through EGL");
  if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE)
    throw std::runtime_error("render: eglMakeCurrent without a surface failed, EGL error " + egl_error_text(eglGetError()));
}

/// Makes the shared context (creating it and its window the first time) current on this thread. Throws
/// std::runtime_error when no EGL/OpenGL context can be made (and then tries again next time).
void acquire(SharedContext& c) {
  if (c.context != EGL_NO_CONTEXT) {
    make_current_or_throw(c.display, c.context);
    return;
  }
  const Display& d = surfaceless_display();
  if (!d.error.empty()) throw std::runtime_error("render: no off-screen OpenGL: " + d.error);
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE)
    throw std::runtime_error("render: eglBindAPI(EGL_OPENGL_API) failed: desktop OpenGL is not available through EGL");
  // clang-format off
  const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3,
                                       EGL_CONTEXT_MINOR_VERSION, 2,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                       EGL_NONE};
  // clang-format on
  const EGLContext context =
      eglCreateContext(d.display, d.no_config ? EGL_NO_CONFIG_KHR : d.config, EGL_NO_CONTEXT, context_attributes);
  if (context == EGL_NO_CONTEXT)
    throw std::runtime_error("render: eglCreateContext (OpenGL 3.2 core) failed, EGL error " + egl_error_text(eglGetError()));
  try {
    make_current_or_throw(d.display, context);
  } catch (...) {
    eglDestroyContext(d.display, context);
    throw;
  }
  auto window = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  window->SetOffScreenRendering(1);
  window->SetOwnContext(false);
  window->SetIsDirect(true);
  window->SetSupportsOpenGL(true);
  window->SetIsCurrent(true);
  window->SetReadyForRendering(true);
  window->SetMapped(1);
  window->SetMultiSamples(8);
  if (!window->InitializeFromCurrentContext()) {
    window->Finalize();
    eglMakeCurrent(d.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(d.display, context);
    throw std::runtime_error("render: VTK could not use the EGL OpenGL context (OpenGL 3.2 needed)");
  }
  c.display = d.display;
  c.context = context;
  c.window = window;
  context_owner = ::getpid();
  std::atexit(release_at_exit);
}

} // namespace

struct Offscreen::Impl {
  std::unique_lock<std::mutex> lock{render_mutex()};
  SharedContext& shared = shared_context();

  Impl(int width, int height) {
    link_glew_init_wrapper();
    if (width < 16 || height < 16 || width > 16384 || height > 16384)
      throw std::invalid_argument("render: image size " + std::to_string(width) + " x " + std::to_string(height) +
                                  " px is out of range (16 … 16384)");
    acquire(shared);
    vtkGenericOpenGLRenderWindow* w = shared.window;
    w->SetNumberOfLayers(1); // a figure sets its own layers
    w->SetSize(width, height);
  }

  /// The figure's renderers leave the window (releasing their graphics resources while the context is current; the
  /// window's shader cache stays), and the context is released from this thread.
  ~Impl() {
    vtkGenericOpenGLRenderWindow* w = shared.window;
    std::vector<vtkSmartPointer<vtkRenderer>> renderers;
    w->GetRenderers()->InitTraversal();
    while (vtkRenderer* r = w->GetRenderers()->GetNextItem()) renderers.emplace_back(r);
    for (const auto& r : renderers) w->RemoveRenderer(r);
    w->SetInteractor(nullptr);
    eglMakeCurrent(shared.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
};

Offscreen::Offscreen(int width, int height) : impl_(std::make_unique<Impl>(width, height)) {}
Offscreen::~Offscreen() = default;

vtkGenericOpenGLRenderWindow* Offscreen::window() const { return impl_->shared.window; }

void Offscreen::save_png(const std::filesystem::path& png) {
  impl_->shared.window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(impl_->shared.window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  write_vtk_png(grab->GetOutput(), png);
}

} // namespace geartopo::render::detail
