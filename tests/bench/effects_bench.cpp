// What each effect costs on the default city. Part 1: the same front (the SSE selector at a fixed
// pixel threshold, settled frames: the front does not depend on time) drawn under each effect
// combination: the frame time, each pass's time, and each effect's cost in ms and in % of the
// frame. Part 2: the Lakhia selector at a fixed budget, settled: as effects are added the frame
// time stays on budget and the selected triangle count drops.
//
// Run: ./effects_bench [STORE] [--frames N] [--size WxH] [--budget-ms MS]
// Without STORE the default city is generated and built under ./effects_bench_data (once).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "BenchCity.h"
#include "hlod/scene/SceneFile.h"
#include "service/Session.h"

namespace {

struct Combination {
  std::string name;
  hlod::SceneEffects effects;
};

// Each step adds one effect to the one before: the default city scene's, then shadows, SSAO
// and the outline.
std::vector<Combination> combinations() {
  std::vector<Combination> list;
  hlod::SceneEffects e;
  list.push_back({"unlit, no textures", e});
  e.textures = true;
  list.push_back({"+ textures", e});
  e.shading = hlod::Shading::Lambert;
  e.sun = hlod::SunLight{};
  list.push_back({"+ lambert, sun", e});
  e.background.sky = true;
  list.push_back({"+ sky", e});
  e.fog = hlod::FogEffect{0.00015};
  list.push_back({"+ fog (city.json)", e});
  e.shadows = hlod::ShadowEffect{2048};
  list.push_back({"+ shadows 2048", e});
  e.ssao = hlod::SsaoEffect{3.0, 12, 1.0f};
  list.push_back({"+ ssao (city-shadows)", e});
  e.outline = hlod::OutlineEffect{};
  list.push_back({"+ outline", e});
  return list;
}

hlod::CameraSample threeQuarterView() {
  // Over the south-west corner of the city looking across it: near streets and far blocks.
  hlod::CameraSample s;
  s.camera.position = {-150.0, -250.0, 220.0};
  s.camera.target = {400.0, 400.0, 0.0};
  s.camera.up = {0.0, 0.0, 1.0};
  s.camera.fovY = 50.0;
  return s;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Measured {
  double frameMs = 0.0;  // median drawMs
  std::map<std::string, double> passMs;
  double triangles = 0.0;
  double gpuMs = 0.0;  // median frame time (uploads included)
};

// One session per combination, all open at once, measured round-robin: a frame of each in
// turn, so that a change in the machine's load (it is shared) spreads over all of them instead
// of landing on one.
hlod::Result<std::vector<Measured>> measure(const std::filesystem::path& store,
                                            const std::vector<service::SessionOptions>& options,
                                            int frames) {
  std::vector<std::unique_ptr<service::Session>> sessions;
  const hlod::CameraSample cam = threeQuarterView();
  for (const auto& o : options) {
    auto session = service::Session::open(store, o);
    if (!session) return session.error();
    // Settle the front (and v_time for the budgeted run) before measuring.
    for (int i = 0; i < 12; ++i)
      if (auto r = (*session)->renderFrame(cam, hlod::FrameMode::Settled); !r) return r.error();
    sessions.push_back(std::move(*session));
  }
  struct Samples {
    std::vector<double> draw, gpu, tris;
    std::map<std::string, std::vector<double>> passes;
  };
  std::vector<Samples> samples(sessions.size());
  for (int i = 0; i < frames; ++i) {
    for (std::size_t k = 0; k < sessions.size(); ++k) {
      auto r = sessions[k]->renderFrame(cam, hlod::FrameMode::Settled);
      if (!r) return r.error();
      Samples& s = samples[k];
      s.draw.push_back(r->drawMs);
      s.gpu.push_back(r->gpuMs);
      s.tris.push_back(static_cast<double>(r->triangles));
      for (auto [name, ms] :
           std::initializer_list<std::pair<const char*, double>>{{"shadow", r->shadowMs},
                                                                 {"geometry", r->geometryMs},
                                                                 {"sky", r->skyMs},
                                                                 {"ssao", r->ssaoMs},
                                                                 {"ssao-blur", r->ssaoBlurMs},
                                                                 {"composite", r->compositeMs},
                                                                 {"outline", r->outlineMs}})
        s.passes[name].push_back(ms);
    }
  }
  std::vector<Measured> out;
  for (const Samples& s : samples) {
    Measured m;
    m.frameMs = median(s.draw);
    m.gpuMs = median(s.gpu);
    m.triangles = median(s.tris);
    for (const auto& [name, v] : s.passes) m.passMs[name] = median(v);
    out.push_back(m);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path given;
  int frames = 7, width = 1280, height = 720;
  double budgetMs = 0.0;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--frames") && i + 1 < argc)
      frames = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--size") && i + 1 < argc)
      std::sscanf(argv[++i], "%dx%d", &width, &height);
    else if (!std::strcmp(argv[i], "--budget-ms") && i + 1 < argc)
      budgetMs = std::atof(argv[++i]);
    else
      given = argv[i];
  }
  auto store = bench::storeOrDefaultCity(given, "effects_bench_data");
  if (!store) {
    std::fprintf(stderr, "effects_bench: %s\n", store.message().c_str());
    return 1;
  }
  const auto list = combinations();

  std::printf("Part 1: the same front (sse, 4 px, settled), %dx%d, median of %d frames\n", width,
              height, frames);
  std::printf("%-24s %9s %9s %8s %7s | %7s %8s %6s %6s %6s %6s %7s\n", "effects", "frame ms",
              "effect ms", "% frame", "Mtri", "shadow", "geometry", "sky", "ssao", "blur", "comp",
              "outline");
  std::vector<service::SessionOptions> sameFront;
  for (const Combination& c : list) {
    service::SessionOptions o;
    o.width = width;
    o.height = height;
    o.selector = "sse";
    o.selectorParams.ssePixels = 4.0;
    o.effects = c.effects;
    sameFront.push_back(o);
  }
  auto measured = measure(*store, sameFront, frames);
  if (!measured) {
    std::fprintf(stderr, "effects_bench: %s\n", measured.message().c_str());
    return 1;
  }
  double previous = 0.0;
  for (std::size_t k = 0; k < list.size(); ++k) {
    Measured& m = (*measured)[k];
    const double added = previous > 0.0 ? m.frameMs - previous : 0.0;
    std::printf("%-24s %9.1f %+9.1f %7.1f%% %7.2f | %7.1f %8.1f %6.1f %6.1f %6.1f %6.1f %7.1f\n",
                list[k].name.c_str(), m.frameMs, added,
                m.frameMs > 0.0 ? 100.0 * added / m.frameMs : 0.0, m.triangles * 1e-6,
                m.passMs["shadow"], m.passMs["geometry"], m.passMs["sky"], m.passMs["ssao"],
                m.passMs["ssao-blur"], m.passMs["composite"], m.passMs["outline"]);
    previous = m.frameMs;
    // The budget of part 2: what the default city scene's frame costs at this front.
    if (budgetMs <= 0.0 && list[k].name == "+ fog (city.json)") budgetMs = m.frameMs;
  }
  std::fflush(stdout);

  std::printf("\nPart 2: lakhia at a fixed budget of %.0f ms, settled, %dx%d\n", budgetMs, width,
              height);
  std::printf("%-24s %9s %9s %9s\n", "effects", "frame ms", "Mtri", "vs first");
  std::vector<service::SessionOptions> budgeted;
  for (const Combination& c : list) {
    service::SessionOptions o;
    o.width = width;
    o.height = height;
    o.budgetMs = budgetMs;
    o.effects = c.effects;
    budgeted.push_back(o);
  }
  auto onBudget = measure(*store, budgeted, frames);
  if (!onBudget) {
    std::fprintf(stderr, "effects_bench: %s\n", onBudget.message().c_str());
    return 1;
  }
  const double firstTriangles = (*onBudget)[0].triangles;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const Measured& m = (*onBudget)[k];
    std::printf("%-24s %9.1f %9.2f %8.0f%%\n", list[k].name.c_str(), m.gpuMs, m.triangles * 1e-6,
                100.0 * m.triangles / firstTriangles);
  }
  return 0;
}
