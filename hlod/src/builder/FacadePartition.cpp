#include "builder/FacadePartition.h"

#include <limits>

#include "hlod/parry/Faces.h"

namespace hlod {

SlabPartition partitionIntoFacades(const Mesh& mesh, UpAxis up, std::size_t minTriangles) {
  const FaceSegmentation seg = segmentFaces(mesh);
  const std::vector<std::uint32_t> facade = facadesOf(mesh, seg, up);
  std::vector<std::vector<std::uint32_t>> parts(kFacadeCount);
  std::vector<glm::dvec3> mean(kFacadeCount, glm::dvec3(0.0));
  for (std::uint32_t t = 0; t < seg.faceOf.size(); ++t) {
    const std::uint32_t f = facade[seg.faceOf[t]];
    parts[f].push_back(t);
    mean[f] += centroid(mesh, t);
  }
  for (std::size_t f = 0; f < kFacadeCount; ++f)
    if (!parts[f].empty()) mean[f] /= double(parts[f].size());
  // Small facades, smallest first, into the nearest other facade that is not empty.
  for (;;) {
    std::size_t small = kFacadeCount;
    for (std::size_t f = 0; f < kFacadeCount; ++f)
      if (!parts[f].empty() && parts[f].size() < minTriangles &&
          (small == kFacadeCount || parts[f].size() < parts[small].size()))
        small = f;
    if (small == kFacadeCount) break;
    std::size_t into = kFacadeCount;
    double best = std::numeric_limits<double>::max();
    for (std::size_t f = 0; f < kFacadeCount; ++f) {
      const double d = glm::length(mean[f] - mean[small]);
      if (f != small && !parts[f].empty() && d < best) best = d, into = f;
    }
    if (into == kFacadeCount) break;  // the only facade left
    const double n = double(parts[into].size()), m = double(parts[small].size());
    mean[into] = (mean[into] * n + mean[small] * m) / (n + m);
    parts[into].insert(parts[into].end(), parts[small].begin(), parts[small].end());
    parts[small].clear();
  }
  SlabPartition out;
  out.axis = -1;
  for (auto& p : parts)
    if (!p.empty()) out.triangles.push_back(std::move(p));
  return out;
}

}  // namespace hlod
