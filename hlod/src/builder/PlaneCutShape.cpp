// The hierarchy the plane cuts make of a model, without simplifying (HlodBuilder.h,
// planeCutShape): for comparing it with the object hierarchy on the criteria of Manocha sec.
// 2.1.1.
#include <algorithm>
#include <map>

#include "builder/MaterialKey.h"
#include "builder/SlabPartition.h"
#include "hlod/builder/HlodBuilder.h"

namespace hlod {

namespace {

// A piece waiting to become a node: its triangles' centroids as a mesh of points (one vertex per
// triangle, repeated three times: the slab partition sees only centroids) and their numbers in
// the group.
struct Piece {
  Mesh centroids;
  std::vector<std::uint32_t> ids;
  double s = 0.0;
};

}  // namespace

HierarchyShape planeCutShape(const Model& model, const BuildOptions& options) {
  HierarchyShape shape;
  // Each triangle's object.
  std::vector<std::vector<std::uint32_t>> objectOf(model.meshes.size());
  for (std::size_t m = 0; m < model.meshes.size(); ++m)
    objectOf[m].assign(model.meshes[m].triangleCount(), 0);
  for (const ObjectRun& r : model.objectRuns)
    for (std::uint32_t t = r.firstTriangle; t < r.firstTriangle + r.triangleCount; ++t)
      objectOf[r.mesh][t] = r.object;
  shape.leavesPerObject.assign(model.objectCount(), 0);
  // Grouped by material, as cutIntoBlocks groups them.
  std::map<MaterialKey, std::vector<std::pair<std::uint32_t, std::uint32_t>>> groups;
  for (std::uint32_t m = 0; m < model.meshes.size(); ++m)
    for (std::uint32_t t = 0; t < model.meshes[m].triangleCount(); ++t)
      groups[materialKeyOf(model.meshes[m])].emplace_back(m, t);
  const auto triangleBox = [&](std::pair<std::uint32_t, std::uint32_t> mt) {
    const Mesh& mesh = model.meshes[mt.first];
    Aabb b;
    for (int k = 0; k < 3; ++k)
      b.extend(mesh.positions[mesh.indices[3 * std::size_t(mt.second) + k]]);
    return b;
  };
  for (const auto& [key, triangles] : groups) {
    std::vector<glm::dvec3> centroids(triangles.size());
    std::vector<std::uint32_t> all(triangles.size());
    for (std::uint32_t i = 0; i < triangles.size(); ++i) {
      all[i] = i;
      const Mesh& mesh = model.meshes[triangles[i].first];
      const std::size_t t = triangles[i].second;
      centroids[i] =
          (mesh.positions[mesh.indices[3 * t]] + mesh.positions[mesh.indices[3 * t + 1]] +
           mesh.positions[mesh.indices[3 * t + 2]]) /
          3.0;
    }
    std::vector<std::vector<std::uint32_t>> blocks;
    halveUntilSmall(centroids, std::move(all), std::max<std::size_t>(1, options.maxBlockTriangles),
                    0, blocks);
    for (std::vector<std::uint32_t>& block : blocks) {
      // buildBlockHierarchy's division, breadth-first.
      const auto base = std::uint32_t(shape.nodes.size());
      std::vector<Piece> pieces(1);
      pieces[0].ids = std::move(block);
      for (std::uint32_t id : pieces[0].ids) {
        const auto v = std::uint32_t(pieces[0].centroids.positions.size());
        pieces[0].centroids.positions.push_back(centroids[id]);
        pieces[0].centroids.indices.insert(pieces[0].centroids.indices.end(), {v, v, v});
      }
      pieces[0].s = double(pieces[0].ids.size()) / std::max<std::uint32_t>(1, options.desiredTri);
      shape.nodes.emplace_back();
      for (std::size_t i = 0; i < pieces.size(); ++i) {
        Piece piece = std::move(pieces[i]);
        pieces[i] = Piece{};
        const std::uint32_t node = base + std::uint32_t(i);
        SlabPartition slabs;
        if (piece.s > 1.0 &&
            piece.ids.size() >= std::size_t(options.levelFactor) * options.minLeafTri)
          slabs = divideIntoSlabs(piece.centroids, options.levelFactor, options.minLeafTri);
        if (slabs.triangles.size() < 2) {
          // A leaf: its box and objects from its triangles.
          HierarchyNode& n = shape.nodes[node];
          n.triangles = piece.ids.size();
          std::vector<std::uint32_t> objects;
          for (std::uint32_t id : piece.ids) {
            n.box.extend(triangleBox(triangles[id]));
            objects.push_back(objectOf[triangles[id].first][triangles[id].second]);
          }
          std::sort(objects.begin(), objects.end());
          objects.erase(std::unique(objects.begin(), objects.end()), objects.end());
          for (std::uint32_t o : objects) ++shape.leavesPerObject[o];
          continue;
        }
        shape.nodes[node].firstChild = base + std::uint32_t(pieces.size());
        shape.nodes[node].childCount = std::uint32_t(slabs.triangles.size());
        for (const std::vector<std::uint32_t>& slab : slabs.triangles) {
          Piece child;
          child.centroids = subMesh(piece.centroids, slab);
          for (std::uint32_t t : slab) child.ids.push_back(piece.ids[t]);
          child.s = piece.s / double(options.levelFactor);
          pieces.push_back(std::move(child));
          shape.nodes.emplace_back();
          shape.nodes.back().parent = node;
        }
      }
      // Inner boxes from their children's, children after parents.
      for (std::size_t i = shape.nodes.size(); i-- > base;) {
        const HierarchyNode& n = shape.nodes[i];
        if (n.parent != 0xffffffffu) shape.nodes[n.parent].box.extend(n.box);
      }
    }
  }
  return shape;
}

}  // namespace hlod
