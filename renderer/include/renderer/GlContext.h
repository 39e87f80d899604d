#pragma once
// A headless OpenGL 4.5 core context behind a small interface (as filament's platform layer):
// one implementation per backend (EGL device, EGL surfaceless, OSMesa), picked at run time.
// One context per thread; a context is made current on the thread that renders with it.
#include <memory>
#include <string>

#include "hlod/Result.h"
#include "renderer/GlFunctions.h"

namespace renderer {

enum class Backend { Auto, Egl, OsMesa };

struct ContextInfo {
  std::string backend;   // "egl-device", "egl-surfaceless" or "osmesa"
  std::string version;   // GL_VERSION
  std::string renderer;  // GL_RENDERER
  std::string vendor;    // GL_VENDOR
  std::string skipped;   // why earlier backends were skipped ("" if none)
  // Whether GL_TIME_ELAPSED queries time the GPU's work on the commands between them (false on
  // a software rasteriser: see timerQueriesTimeTheGpu).
  bool gpuTimers = false;
};

// Whether a context whose GL_RENDERER is `renderer` times its passes with GL_TIME_ELAPSED. Not on
// Mesa's software rasterisers (llvmpipe, softpipe, swrast, and zink on lavapipe): llvmpipe runs a
// query's begin and end as commands of every screen tile, timestamped by the rasteriser thread
// that runs the tile, and reports the latest end less the earliest begin of each thread's last
// tile. Vertex work and binning run on the calling thread at the draw call, outside it, and so
// does every tile but the last: the result is a sliver of the pass (0.00 ms for 487 k
// triangles), or, where a thread's begin was never stamped, the clock's reading since boot.
// There the wall time through glFinish is the frame's only time.
bool timerQueriesTimeTheGpu(const std::string& renderer);

// Keeps freed memory in the process (glibc): blocks up to 8 MB come from the heap, and up to
// 32 MB of free heap is kept instead of being given back to the kernel. A software rasteriser
// (llvmpipe) allocates and frees its working memory at every draw; with glibc's defaults the
// heap's top is given back after each free and the next draw faults every page of it in again,
// which was most of a frame's time. Called for every software context; process-wide.
void keepFreedHeap();

class GlContext {
 public:
  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  virtual bool makeCurrent() = 0;
  virtual void releaseCurrent() = 0;
  virtual void* getProcAddress(const char* name) = 0;

  const GlFunctions& gl() const { return gl_; }
  const ContextInfo& info() const { return info_; }
  void finish() { gl_.Finish(); }

 protected:
  GlContext() = default;

 private:
  // Filled once by the shared start-up check after a backend made the context current.
  friend hlod::Status initialiseContext(GlContext& context, std::string backend,
                                        std::string skipped);
  friend hlod::Result<std::unique_ptr<GlContext>> createContext(Backend backend);
  GlFunctions gl_;
  ContextInfo info_;
};

// Parses HLODR_GL_BACKEND ("egl", "osmesa", "" or "auto"); an unknown value is an Error.
hlod::Result<Backend> backendFromEnvironment();

// Creates a context and makes it current. Auto: EGL (device platform when a driver offers a
// hardware device, else Mesa surfaceless), then OSMesa. A forced backend that fails is an Error.
hlod::Result<std::unique_ptr<GlContext>> createContext(Backend backend);

// One log line: backend, GL version, renderer, and why other backends were skipped.
std::string describe(const ContextInfo& info);

}  // namespace renderer
