// The renderer calls OpenGL through a table of functions loaded from the
// context's own get-proc-address (method.md §7.4): OSMesaGetProcAddress,
// eglGetProcAddress or glfwGetProcAddress. So one executable can draw with
// OSMesa or with EGL (a GPU where there is one). Call loadGL once a context
// is current, before creating a Renderer or an OverlayRenderer.
#pragma once

#include <string>

namespace loosehair::render {

using GetProcAddress = void* (*)(const char* name);

/// Loads every function the renderer uses; throws RenderError naming the
/// first one `get` does not provide.
void loadGL(GetProcAddress get);
/// Whether loadGL has succeeded.
bool openGLLoaded();
/// Whether a GL_RENDERER string names a software rasteriser (Mesa's
/// llvmpipe, softpipe, swrast, or one that says "Software").
bool softwareRenderer(const std::string& gl_renderer);

}  // namespace loosehair::render
