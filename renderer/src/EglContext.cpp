// EGL backend: the device platform (EGL_EXT_platform_device) when a driver offers a hardware
// device, e.g. NVIDIA's, else Mesa's surfaceless platform (llvmpipe here). No window, no surface:
// hlodr renders into its own framebuffer objects.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <string>
#include <vector>

#include "ContextBackends.h"

namespace renderer {
namespace {

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

std::string eglErrorName(EGLint e) {
  switch (e) {
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default:
      return "EGL error 0x" + std::to_string(e);
  }
}

class EglContext final : public GlContext {
 public:
  EglContext(EGLDisplay display, EGLContext context) : display_(display), context_(context) {}
  ~EglContext() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    // The display is shared per device and may serve other contexts: not terminated here.
  }
  bool makeCurrent() override {
    return eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_TRUE;
  }
  void releaseCurrent() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  void* getProcAddress(const char* name) override {
    return reinterpret_cast<void*>(eglGetProcAddress(name));
  }

 private:
  EGLDisplay display_;
  EGLContext context_;
};

// Creates a GL 4.5 (else 4.3, 3.3) core context on an initialised display.
hlod::Result<EGLContext> createCoreContext(EGLDisplay display) {
  if (!eglBindAPI(EGL_OPENGL_API)) return hlod::makeError("eglBindAPI(OpenGL) failed");
  const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  const char* exts = eglQueryString(display, EGL_EXTENSIONS);
  if (!eglChooseConfig(display, configAttribs, &config, 1, &count) || count == 0) {
    if (!hasExtension(exts, "EGL_KHR_no_config_context"))
      return hlod::makeError("no EGL config with OpenGL support");
    config = nullptr;  // EGL_NO_CONFIG_KHR
  }
  if (!hasExtension(exts, "EGL_KHR_surfaceless_context"))
    return hlod::makeError("display lacks EGL_KHR_surfaceless_context");
  const EGLint versions[][2] = {{4, 5}, {4, 3}, {3, 3}};
  for (const auto& v : versions) {
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                              v[0],
                              EGL_CONTEXT_MINOR_VERSION,
                              v[1],
                              EGL_CONTEXT_OPENGL_PROFILE_MASK,
                              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_NONE};
    EGLContext ctx = eglCreateContext(display, config, EGL_NO_CONTEXT, attribs);
    if (ctx != EGL_NO_CONTEXT) return ctx;
  }
  return hlod::makeError("eglCreateContext failed: " + eglErrorName(eglGetError()));
}

hlod::Result<std::unique_ptr<GlContext>> finishContext(EGLDisplay display, std::string backend,
                                                       std::string skipped) {
  auto ctx = createCoreContext(display);
  if (!ctx) return ctx.error();
  auto context = std::make_unique<EglContext>(display, *ctx);
  if (!context->makeCurrent())
    return hlod::makeError("eglMakeCurrent failed: " + eglErrorName(eglGetError()));
  auto status = initialiseContext(*context, std::move(backend), std::move(skipped));
  if (!status) return status.error();
  return std::unique_ptr<GlContext>(std::move(context));
}

}  // namespace

hlod::Result<std::unique_ptr<GlContext>> createEglContext() {
  std::string skipped;
  const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!getPlatformDisplay) return hlod::makeError("EGL has no eglGetPlatformDisplayEXT");

  // 1. Device platform: a real GPU without a display server (NVIDIA, Mesa hardware drivers).
  auto queryDevices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (hasExtension(clientExts, "EGL_EXT_platform_device") && queryDevices && queryDeviceString) {
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    queryDevices(16, devices, &count);
    int software = 0;
    for (EGLint i = 0; i < count; ++i) {
      const char* devExts = queryDeviceString(devices[i], EGL_EXTENSIONS);
      // Mesa lists llvmpipe as a "software device": surfaceless serves it the same way.
      if (hasExtension(devExts, "EGL_MESA_device_software")) {
        ++software;
        continue;
      }
      EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
      EGLint major = 0, minor = 0;
      if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor)) {
        skipped += "egl-device " + std::to_string(i) + ": eglInitialize failed; ";
        continue;
      }
      auto ctx = finishContext(display, "egl-device", skipped);
      if (ctx) return ctx;
      skipped += "egl-device " + std::to_string(i) + ": " + ctx.message() + "; ";
    }
    if (count == software)
      skipped += "egl-device: no hardware device (" + std::to_string(software) + " software); ";
  } else {
    skipped += "egl-device: EGL_EXT_platform_device not offered; ";
  }

  // 2. Mesa surfaceless platform.
  if (!hasExtension(clientExts, "EGL_MESA_platform_surfaceless"))
    return hlod::makeError(skipped + "egl-surfaceless: EGL_MESA_platform_surfaceless not offered");
  EGLDisplay display =
      getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
    return hlod::makeError(skipped +
                           "egl-surfaceless: eglInitialize failed: " + eglErrorName(eglGetError()));
  auto ctx = finishContext(display, "egl-surfaceless", skipped);
  if (!ctx) return hlod::makeError(skipped + "egl-surfaceless: " + ctx.message());
  return ctx;
}

}  // namespace renderer
