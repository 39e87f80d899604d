#pragma once
// The importers' fuzz targets: the input is written as a model file (plus a companion file after
// a separator line, for formats that refer to one) and read through hlod::importModel, the entry
// point `hlodr build` uses. Any input must give a Model or an Error; what importModel promises
// of a Model (finite coordinates in range, indices in range, at least one triangle) is checked.
#include <cmath>
#include <cstdlib>
#include <string>

#include "FuzzSupport.h"
#include "hlod/import/Import.h"

namespace fuzz {

inline void checkModel(const hlod::Model& model) {
  std::size_t triangles = 0;
  for (const auto& mesh : model.meshes) {
    if (mesh.indices.size() % 3 != 0) std::abort();
    for (const auto& p : mesh.positions)
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite(p[c]) || std::abs(p[c]) > hlod::kMaxCoordinate) std::abort();
    for (auto i : mesh.indices)
      if (i >= mesh.positions.size()) std::abort();
    if (!mesh.texCoords.empty() && mesh.texCoords.size() != mesh.positions.size()) std::abort();
    triangles += mesh.indices.size() / 3;
  }
  if (triangles == 0) std::abort();
}

// Imports `main` saved as model.EXT, with `companion` saved beside it as companionName (when
// given); removes the companion afterwards so that the next input starts without it.
inline void importAndCheck(const std::string& ext, std::string_view main,
                           const std::string& companionName = {}, std::string_view companion = {},
                           bool withCompanion = false) {
  if (withCompanion) writeFile(companionName, companion);
  const auto path = writeFile("model." + ext, main);
  auto model = hlod::importModel(path);
  report("importModel", model);
  if (model.ok()) checkModel(*model);
  if (withCompanion) removeFile(companionName);
}

}  // namespace fuzz
