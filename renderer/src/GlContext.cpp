#include "renderer/GlContext.h"

#include <cstdlib>
#include <cstring>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "ContextBackends.h"

namespace renderer {

hlod::Status initialiseContext(GlContext& context, std::string backend, std::string skipped) {
  GlFunctions& gl = context.gl_;
  const std::string missing =
      gl.load([&](const char* name) { return context.getProcAddress(name); });
  if (!missing.empty())
    return hlod::makeError(backend + ": GL entry point " + missing + " missing");
  auto str = [&](GLenum e) {
    const auto* s = reinterpret_cast<const char*>(gl.GetString(e));
    return std::string(s ? s : "?");
  };
  GLint major = 0, minor = 0;
  gl.GetIntegerv(GL_MAJOR_VERSION, &major);
  gl.GetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 45)
    return hlod::makeError(backend + ": GL " + std::to_string(major) + "." + std::to_string(minor) +
                           " is below the 4.5 hlodr needs (glClipControl)");
  context.info_ = ContextInfo{std::move(backend), str(GL_VERSION), str(GL_RENDERER), str(GL_VENDOR),
                              std::move(skipped)};
  context.info_.gpuTimers = timerQueriesTimeTheGpu(context.info_.renderer);
  if (!context.info_.gpuTimers) keepFreedHeap();
  return hlod::Ok{};
}

void keepFreedHeap() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 8 << 20);
  mallopt(M_TRIM_THRESHOLD, 32 << 20);
#endif
}

bool timerQueriesTimeTheGpu(const std::string& renderer) {
  for (const char* software : {"llvmpipe", "softpipe", "swrast", "Software Rasterizer"})
    if (renderer.find(software) != std::string::npos) return false;
  return true;
}

hlod::Result<Backend> backendFromEnvironment() {
  const char* v = std::getenv("HLODR_GL_BACKEND");
  if (!v || !*v || !std::strcmp(v, "auto")) return Backend::Auto;
  if (!std::strcmp(v, "egl")) return Backend::Egl;
  if (!std::strcmp(v, "osmesa")) return Backend::OsMesa;
  return hlod::makeError(std::string("HLODR_GL_BACKEND='") + v +
                         "' is not one of egl, osmesa, auto");
}

hlod::Result<std::unique_ptr<GlContext>> createContext(Backend backend) {
  if (backend == Backend::Egl) {
    auto c = createEglContext();
    if (!c) return hlod::makeError("HLODR_GL_BACKEND=egl: " + c.message());
    return c;
  }
  if (backend == Backend::OsMesa) {
    auto c = createOsMesaContext();
    if (!c) return hlod::makeError("HLODR_GL_BACKEND=osmesa: " + c.message());
    return c;
  }
  auto egl = createEglContext();
  if (egl) return egl;
  auto osmesa = createOsMesaContext();
  if (!osmesa)
    return hlod::makeError("no GL backend works: egl: " + egl.message() +
                           "; osmesa: " + osmesa.message());
  (*osmesa)->info_.skipped = "egl: " + egl.message();
  return osmesa;
}

std::string describe(const ContextInfo& info) {
  std::string line = "GL backend " + info.backend + ": " + info.version + ", " + info.renderer;
  if (!info.skipped.empty()) line += " (skipped: " + info.skipped + ")";
  return line;
}

}  // namespace renderer
