// HeadlessGL on OSMesa: software OpenGL (llvmpipe) into a buffer of ours.
#include "headless_gl_context.hpp"

#include "loosehair/render/gl_loader.hpp"

#include <GL/osmesa.h>

#include <cstring>
#include <stdexcept>

namespace loosehair::app {

namespace {

class OSMesaContextImpl final : public HeadlessGL::Context {
 public:
  OSMesaContextImpl(int width, int height) {
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_STENCIL_BITS,
                           0,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           3,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           3,
                           0};
    ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx_) throw std::runtime_error("OSMesa cannot create an OpenGL 3.3 core context");
    buffer_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4, 0);
    if (!OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
      OSMesaDestroyContext(ctx_);
      throw std::runtime_error("OSMesa cannot make its context current");
    }
    render::loadGL([](const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); });
  }
  ~OSMesaContextImpl() override { OSMesaDestroyContext(ctx_); }

  std::vector<std::uint8_t> pixels(int width, int height) const override {
    glFinish();
    // OSMesa's rows go bottom to top.
    const std::size_t row = static_cast<std::size_t>(width) * 4;
    std::vector<std::uint8_t> out(buffer_.size());
    for (int y = 0; y < height; ++y)
      std::memcpy(&out[static_cast<std::size_t>(y) * row], &buffer_[static_cast<std::size_t>(height - 1 - y) * row],
                  row);
    return out;
  }

  std::string renderer() const override {
    const char* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const char* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return std::string(r ? r : "?") + ", OpenGL " + (v ? v : "?");
  }

 private:
  OSMesaContext ctx_ = nullptr;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace

std::unique_ptr<HeadlessGL::Context> makeOSMesaContext(int width, int height) {
  return std::make_unique<OSMesaContextImpl>(width, height);
}

}  // namespace loosehair::app
