// OSMesa backend: Mesa's off-screen software rasteriser, the fallback when EGL is not usable.
// libOSMesa is opened at run time so that hlodr starts on machines without it, and so that its
// own gl* symbols never mix with the EGL/GLVND ones.
// glcorearb.h (through ContextBackends.h) must come before osmesa.h, which pulls in gl.h.
#include "ContextBackends.h"

#include <GL/osmesa.h>
#include <dlfcn.h>

#include <mutex>

namespace renderer {
namespace {

struct OsMesaApi {
  void* lib = nullptr;
  decltype(&OSMesaCreateContextAttribs) createContextAttribs = nullptr;
  decltype(&OSMesaMakeCurrent) makeCurrent = nullptr;
  decltype(&OSMesaDestroyContext) destroyContext = nullptr;
  decltype(&OSMesaGetProcAddress) getProcAddress = nullptr;
};

// libOSMesa is opened once for the process (std::call_once: the server's render workers create
// their contexts on threads of their own, at the same time).
hlod::Result<const OsMesaApi*> osMesaApi() {
  static OsMesaApi api;
  static std::string error;
  static std::once_flag once;
  std::call_once(once, [] {
    for (const char* name : {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}) {
      // RTLD_LOCAL keeps OSMesa's gl* symbols out of the global namespace.
      if ((api.lib = dlopen(name, RTLD_NOW | RTLD_LOCAL))) break;
    }
    if (!api.lib) {
      error = "libOSMesa not found (install libosmesa6)";
    } else {
      api.createContextAttribs = reinterpret_cast<decltype(api.createContextAttribs)>(
          dlsym(api.lib, "OSMesaCreateContextAttribs"));
      api.makeCurrent =
          reinterpret_cast<decltype(api.makeCurrent)>(dlsym(api.lib, "OSMesaMakeCurrent"));
      api.destroyContext =
          reinterpret_cast<decltype(api.destroyContext)>(dlsym(api.lib, "OSMesaDestroyContext"));
      api.getProcAddress =
          reinterpret_cast<decltype(api.getProcAddress)>(dlsym(api.lib, "OSMesaGetProcAddress"));
      if (!api.createContextAttribs || !api.makeCurrent || !api.destroyContext ||
          !api.getProcAddress)
        error = "libOSMesa lacks OSMesaCreateContextAttribs (Mesa too old)";
    }
  });
  if (!error.empty()) return hlod::makeError(error);
  return &api;
}

class OsMesaContext final : public GlContext {
 public:
  OsMesaContext(const OsMesaApi& api, OSMesaContext context) : api_(api), context_(context) {}
  ~OsMesaContext() override { api_.destroyContext(context_); }
  bool makeCurrent() override {
    // OSMesa needs a colour buffer to be current; hlodr draws into its own FBOs, so 1x1 will do.
    return api_.makeCurrent(context_, buffer_, GL_UNSIGNED_BYTE, 1, 1) == GL_TRUE;
  }
  void releaseCurrent() override {}
  void* getProcAddress(const char* name) override {
    return reinterpret_cast<void*>(api_.getProcAddress(name));
  }

 private:
  const OsMesaApi& api_;
  OSMesaContext context_;
  unsigned char buffer_[4] = {};
};

}  // namespace

hlod::Result<std::unique_ptr<GlContext>> createOsMesaContext() {
  auto api = osMesaApi();
  if (!api) return api.error();
  const int versions[][2] = {{4, 5}, {4, 3}, {3, 3}};
  for (const auto& v : versions) {
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           0,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           v[0],
                           OSMESA_CONTEXT_MINOR_VERSION,
                           v[1],
                           0};
    OSMesaContext ctx = (*api)->createContextAttribs(attribs, nullptr);
    if (!ctx) continue;
    auto context = std::make_unique<OsMesaContext>(**api, ctx);
    if (!context->makeCurrent()) return hlod::makeError("OSMesaMakeCurrent failed");
    auto status = initialiseContext(*context, "osmesa", "");
    if (!status) return status.error();
    return std::unique_ptr<GlContext>(std::move(context));
  }
  return hlod::makeError("OSMesaCreateContextAttribs failed for GL 4.5/4.3/3.3 core");
}

}  // namespace renderer
