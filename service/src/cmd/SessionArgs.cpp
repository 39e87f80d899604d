#include "cmd/SessionArgs.h"

#include "service/Settings.h"

namespace service::cmd {

hlod::Result<SessionOptions> sessionFromArgs(const Args& args) {
  using settings::get;
  SessionOptions so;
  auto size = args.size(get("size"));
  if (!size) return size.error();
  so.width = size->width;
  so.height = size->height;
  auto budget = args.number(get("budgetMs"));
  auto memory = args.number(get("memoryMb"));
  for (const auto* r : {&budget, &memory})
    if (!*r) return r->error();
  so.budgetMs = *budget;
  so.memoryCapBytes = static_cast<std::uint64_t>(*memory * 1048576.0);
  auto selector = args.choice(get("selector"));
  if (!selector) return selector.error();
  so.selector = *selector;
  if (auto p = hlod::setSelectorParams(so.selectorParams, args.get("params", "")); !p)
    return hlod::makeError("--params: " + p.message());
  auto splats = args.choice(get("splats"));
  if (!splats) return splats.error();
  if (args.has("splats")) so.selectorParams.splats = *splats == "on";
  auto occlusion = args.choice(get("occlusion"));
  if (!occlusion) return occlusion.error();
  so.occlusion = *hlod::parseOcclusionMode(*occlusion);  // the table's choices parse
  auto gpu = args.number(get("gpuMb"));
  if (!gpu) return gpu.error();
  so.gpuBudgetBytes = static_cast<std::uint64_t>(*gpu * 1048576.0);
  so.showOcclusion = args.has("show-occlusion");
  return so;
}

}  // namespace service::cmd
