// glewInit wrapper — why this file exists (docs/rendering.md, "The glewInit wrapper").
//
// Debian's VTK 9.1 links the system GLEW, which is built for GLX only. VTK calls glewInit() whenever it sets up a
// context. Under our surfaceless EGL context glewInit() loads every OpenGL entry point and then fails in its GLX part
// with GLEW_ERROR_NO_GLX_DISPLAY (4), because there is no X display. VTK then logs "GLEW could not be initialized"
// on every render and skips part of its set-up. This definition interposes on GLEW's: it calls the real glewInit
// (the next definition in the lookup order, found with dlsym(RTLD_NEXT)) and reports success for error 4 while an
// EGL context is current, since the OpenGL functions are loaded by then. Any other result passes through unchanged.
//
// Interposition needs the symbol in the executable's dynamic symbol table: geartopo_render adds the INTERFACE link
// option LINKER:--export-dynamic-symbol=glewInit to every executable linking it. The empty anchor function below is
// called by offscreen.cpp so that this object file is always linked from the static library.

#include "detail/offscreen.hpp"

#include <EGL/egl.h>
#include <dlfcn.h>

namespace {
constexpr unsigned int glew_ok = 0;
constexpr unsigned int glew_error_no_glx_display = 4;
using GlewInitFn = unsigned int (*)();
} // namespace

extern "C" __attribute__((visibility("default"))) unsigned int glewInit() {
  static const auto real = reinterpret_cast<GlewInitFn>(dlsym(RTLD_NEXT, "glewInit"));
  if (real == nullptr) return glew_error_no_glx_display;
  const unsigned int result = real();
  if (result == glew_error_no_glx_display && eglGetCurrentContext() != EGL_NO_CONTEXT) return glew_ok;
  return result;
}

namespace geartopo::render::detail {
void link_glew_init_wrapper() {}
} // namespace geartopo::render::detail
