#include "loosehair/render/gl_loader.hpp"

#include "loosehair/render/gl_functions.hpp"
#include "loosehair/render/renderer.hpp"

#include <string>

namespace loosehair::render {

namespace {
bool loaded = false;
}

void loadGL(GetProcAddress get) {
  if (!get) throw RenderError("no get-proc-address function to load OpenGL with");
  if (const char* missing = gl::loadFunctions(get)) {
    loaded = false;
    throw RenderError(std::string("this OpenGL lacks ") + missing + ", which the renderer needs");
  }
  loaded = true;
}

bool openGLLoaded() { return loaded; }

bool softwareRenderer(const std::string& r) {
  return r.find("llvmpipe") != std::string::npos || r.find("softpipe") != std::string::npos ||
         r.find("swrast") != std::string::npos || r.find("Software") != std::string::npos;
}

}  // namespace loosehair::render
