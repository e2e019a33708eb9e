// HeadlessGL on EGL without a window system: the first EGL device (a GPU
// where there is one; EGL_EXT_platform_device), else Mesa's surfaceless
// platform (EGL_MESA_platform_surfaceless, llvmpipe here). No surface: the
// picture is a framebuffer object of ours, read back with glReadPixels. The
// GL functions come from eglGetProcAddress, never from a GL library, so
// this lives beside OSMesa in one executable (method.md §7.4).
#include "headless_gl_context.hpp"

#include "loosehair/render/gl_loader.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <cstring>
#include <stdexcept>
#include <string>

namespace loosehair::app {

namespace {

template <class F>
F proc(const char* name) {
  auto* f = reinterpret_cast<F>(eglGetProcAddress(name));
  if (!f) throw std::runtime_error(std::string("EGL: ") + name + " is missing");
  return f;
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = std::strstr(list, name); p; p = std::strstr(p + 1, name))
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

class EGLContextImpl final : public HeadlessGL::Context {
 public:
  EGLContextImpl(int width, int height) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!getPlatformDisplay) throw std::runtime_error("EGL: no eglGetPlatformDisplayEXT (EGL_EXT_platform_base)");
    // a device first (a GPU), else the surfaceless platform
    if (hasExtension(client, "EGL_EXT_platform_device")) {
      auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
      EGLDeviceEXT devices[8];
      EGLint count = 0;
      if (queryDevices && queryDevices(8, devices, &count) && count > 0) {
        for (EGLint k = 0; k < count && display_ == EGL_NO_DISPLAY; ++k) {
          EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[k], nullptr);
          if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) display_ = d;
        }
      }
    }
    if (display_ == EGL_NO_DISPLAY && hasExtension(client, "EGL_MESA_platform_surfaceless")) {
      EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) display_ = d;
    }
    if (display_ == EGL_NO_DISPLAY)
      throw std::runtime_error("EGL: neither a device nor the surfaceless platform can be opened");
    if (!hasExtension(eglQueryString(display_, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context")) {
      eglTerminate(display_);
      throw std::runtime_error("EGL: the display cannot make a context current without a surface");
    }
    const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint n = 0;
    if (!eglChooseConfig(display_, config_attribs, &config, 1, &n) || n < 1) {
      // some devices offer no pbuffer configs: any OpenGL one will do
      const EGLint any[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      if (!eglChooseConfig(display_, any, &config, 1, &n) || n < 1) {
        eglTerminate(display_);
        throw std::runtime_error("EGL: no OpenGL configuration");
      }
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
      eglTerminate(display_);
      throw std::runtime_error("EGL: the display has no desktop OpenGL");
    }
    const EGLint ctx_attribs[] = {
        EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, ctx_attribs);
    if (context_ == EGL_NO_CONTEXT || !eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
      eglTerminate(display_);
      throw std::runtime_error("EGL: cannot create and make current an OpenGL 3.3 core context");
    }
    render::loadGL([](const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); });
    // the picture: RGBA8 colour and a 24-bit depth buffer
    auto genFramebuffers = proc<PFNGLGENFRAMEBUFFERSPROC>("glGenFramebuffers");
    auto bindFramebuffer = proc<PFNGLBINDFRAMEBUFFERPROC>("glBindFramebuffer");
    auto genRenderbuffers = proc<PFNGLGENRENDERBUFFERSPROC>("glGenRenderbuffers");
    auto bindRenderbuffer = proc<PFNGLBINDRENDERBUFFERPROC>("glBindRenderbuffer");
    auto storage = proc<PFNGLRENDERBUFFERSTORAGEPROC>("glRenderbufferStorage");
    auto attach = proc<PFNGLFRAMEBUFFERRENDERBUFFERPROC>("glFramebufferRenderbuffer");
    auto status = proc<PFNGLCHECKFRAMEBUFFERSTATUSPROC>("glCheckFramebufferStatus");
    read_pixels_ = proc<PFNGLREADPIXELSPROC>("glReadPixels");
    finish_ = proc<PFNGLFINISHPROC>("glFinish");
    get_string_ = proc<PFNGLGETSTRINGPROC>("glGetString");
    bind_framebuffer_ = bindFramebuffer;
    genFramebuffers(1, &fbo_);
    bindFramebuffer(GL_FRAMEBUFFER, fbo_);
    genRenderbuffers(2, rbo_);
    bindRenderbuffer(GL_RENDERBUFFER, rbo_[0]);
    storage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    attach(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rbo_[0]);
    bindRenderbuffer(GL_RENDERBUFFER, rbo_[1]);
    storage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    attach(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rbo_[1]);
    if (status(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display_, context_);
      eglTerminate(display_);
      throw std::runtime_error("EGL: the picture's framebuffer is incomplete");
    }
  }
  ~EGLContextImpl() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }

  std::vector<std::uint8_t> pixels(int width, int height) const override {
    finish_();
    bind_framebuffer_(GL_READ_FRAMEBUFFER, fbo_);
    std::vector<std::uint8_t> flipped(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
    read_pixels_(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, flipped.data());
    bind_framebuffer_(GL_FRAMEBUFFER, fbo_);
    // GL's rows go bottom to top
    const std::size_t row = static_cast<std::size_t>(width) * 4;
    std::vector<std::uint8_t> out(flipped.size());
    for (int y = 0; y < height; ++y)
      std::memcpy(&out[static_cast<std::size_t>(y) * row], &flipped[static_cast<std::size_t>(height - 1 - y) * row],
                  row);
    return out;
  }

  std::string renderer() const override {
    const char* r = reinterpret_cast<const char*>(get_string_(GL_RENDERER));
    const char* v = reinterpret_cast<const char*>(get_string_(GL_VERSION));
    return std::string(r ? r : "?") + ", OpenGL " + (v ? v : "?") + " (EGL)";
  }

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  GLuint fbo_ = 0, rbo_[2] = {0, 0};
  PFNGLREADPIXELSPROC read_pixels_ = nullptr;
  PFNGLFINISHPROC finish_ = nullptr;
  PFNGLGETSTRINGPROC get_string_ = nullptr;
  PFNGLBINDFRAMEBUFFERPROC bind_framebuffer_ = nullptr;
};

}  // namespace

std::unique_ptr<HeadlessGL::Context> makeEGLContext(int width, int height) {
  return std::make_unique<EGLContextImpl>(width, height);
}

}  // namespace loosehair::app
