// Manocha sec. 2.2's four stages for a model of many objects (hlod/builder/ObjectHierarchy.h).
#include "hlod/builder/ObjectHierarchy.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "builder/AabbHierarchy.h"
#include "builder/MstClustering.h"
#include "builder/ObjectPartition.h"

namespace hlod {

namespace {

// A centre's weight must be positive: a piece of degenerate triangles still has a place.
constexpr double kMinMass = 1e-300;

struct TriangleFacts {
  glm::dvec3 centroid;
  Aabb box;
  double area;
};

TriangleFacts triangleFacts(const Model& model, std::uint32_t mesh, std::uint32_t t) {
  const Mesh& m = model.meshes[mesh];
  const glm::dvec3& a = m.positions[m.indices[3 * std::size_t(t)]];
  const glm::dvec3& b = m.positions[m.indices[3 * std::size_t(t) + 1]];
  const glm::dvec3& c = m.positions[m.indices[3 * std::size_t(t) + 2]];
  TriangleFacts f;
  f.centroid = (a + b + c) / 3.0;
  f.box.extend(a);
  f.box.extend(b);
  f.box.extend(c);
  f.area = 0.5 * glm::length(glm::cross(b - a, c - a));
  return f;
}

// The facts of a piece of an object as a partition item (its box, centre of mass, area).
PartitionItem itemOf(const Model& model,
                     const std::vector<std::pair<std::uint32_t, std::uint32_t>>& triangles,
                     const std::vector<std::uint32_t>& subset) {
  PartitionItem item;
  item.triangles = subset.empty() ? triangles.size() : subset.size();
  glm::dvec3 weighted(0.0), plain(0.0);
  double area = 0.0;
  const auto add = [&](std::uint32_t t) {
    const TriangleFacts f = triangleFacts(model, triangles[t].first, triangles[t].second);
    item.box.extend(f.box);
    weighted += f.area * f.centroid;
    plain += f.centroid;
    area += f.area;
  };
  if (subset.empty())
    for (std::uint32_t t = 0; t < triangles.size(); ++t) add(t);
  else
    for (std::uint32_t t : subset) add(t);
  // Without area (degenerate triangles only), the plain mean of the centroids.
  item.centre =
      area > 0.0 ? weighted / area : plain / double(std::max<std::uint64_t>(1, item.triangles));
  item.mass = std::max(area, kMinMass);
  return item;
}

PartitionItem itemOf(const RedefinedObject& o) {
  PartitionItem item;
  item.centre = o.centre;
  item.box = o.box;
  item.mass = std::max(o.area, kMinMass);
  item.triangles = o.triangles;
  return item;
}

// The union of objects as one redefined object (its pieces in order).
RedefinedObject unite(std::vector<RedefinedObject>& from, const std::vector<std::uint32_t>& which) {
  RedefinedObject out;
  glm::dvec3 weighted(0.0);
  double mass = 0.0;
  for (std::uint32_t i : which) {
    RedefinedObject& o = from[i];
    out.box.extend(o.box);
    weighted += std::max(o.area, kMinMass) * o.centre;
    mass += std::max(o.area, kMinMass);
    out.area += o.area;
    out.triangles += o.triangles;
    for (ObjectPiece& p : o.pieces) out.pieces.push_back(std::move(p));
  }
  out.centre = weighted / mass;
  return out;
}

double medianDiagonal(const std::vector<PartitionItem>& items) {
  std::vector<double> d;
  for (const PartitionItem& it : items) d.push_back(glm::length(it.box.size()));
  if (d.empty()) return 0.0;
  std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace

HierarchyMode resolveHierarchy(HierarchyMode mode, const Model& model) {
  if (mode != HierarchyMode::Auto) return mode;
  if (model.cityObjects > 0) return HierarchyMode::Planes;
  return model.objectCount() >= kManyObjects ? HierarchyMode::Objects : HierarchyMode::Planes;
}

std::vector<std::vector<ObjectRun>> objectRunsByObject(const Model& model) {
  std::vector<std::vector<ObjectRun>> out;
  if (model.objectRuns.empty()) {
    out.emplace_back();
    for (std::uint32_t m = 0; m < model.meshes.size(); ++m)
      out.back().push_back({0, m, 0, std::uint32_t(model.meshes[m].triangleCount())});
    return out;
  }
  for (const ObjectRun& r : model.objectRuns) {
    if (r.object >= out.size()) out.resize(std::size_t(r.object) + 1);
    out[r.object].push_back(r);
  }
  return out;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> objectTriangles(
    const std::vector<ObjectRun>& runs) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (const ObjectRun& r : runs)
    for (std::uint32_t t = r.firstTriangle; t < r.firstTriangle + r.triangleCount; ++t)
      out.emplace_back(r.mesh, t);
  return out;
}

ObjectHierarchy buildObjectHierarchy(const Model& model, const ObjectHierarchyOptions& options) {
  assert(options.fanOut >= 2 && options.maxTriangles >= 1 && options.extentFactor > 0.0);
  ObjectHierarchy h;
  const std::vector<std::vector<ObjectRun>> byObject = objectRunsByObject(model);
  const Aabb scene = model.bounds();
  const std::uint64_t total = model.triangleCount();
  if (total == 0) return h;
  // maxExtent: the side of a cube of the scene holding maxTriangles, were they spread evenly.
  const double cells = std::max(1.0, double(total) / double(options.maxTriangles));
  h.maxExtent = options.extentFactor * glm::length(scene.size()) / std::cbrt(cells);
  if (!(h.maxExtent > 0.0)) h.maxExtent = std::numeric_limits<double>::infinity();
  const PartitionLimits limits{options.maxTriangles, h.maxExtent};

  // Stage 1: objects over the limits are split by their polygons.
  std::vector<RedefinedObject> pieces;
  for (std::uint32_t o = 0; o < byObject.size(); ++o) {
    const auto triangles = objectTriangles(byObject[o]);
    if (triangles.empty()) continue;
    ++h.inputObjects;
    const PartitionItem whole = itemOf(model, triangles, {});
    const auto add = [&](const PartitionItem& item, std::vector<std::uint32_t> subset) {
      RedefinedObject r;
      r.box = item.box;
      r.centre = item.centre;
      r.area = item.mass;
      r.triangles = item.triangles;
      r.pieces.push_back({o, std::move(subset)});
      pieces.push_back(std::move(r));
    };
    const std::uint32_t all[1] = {0};
    if (!exceedsLimits(std::span(&whole, 1), all, limits)) {
      add(whole, {});
      continue;
    }
    std::vector<PartitionItem> polygons;
    polygons.reserve(triangles.size());
    for (const auto& [mesh, t] : triangles) {
      const TriangleFacts f = triangleFacts(model, mesh, t);
      polygons.push_back({f.centroid, f.box, std::max(f.area, kMinMass), 1});
    }
    std::vector<std::vector<std::uint32_t>> groups = partitionTopDown(polygons, limits);
    polygons = {};
    if (groups.size() == 1) {
      add(whole, {});
      continue;
    }
    for (std::vector<std::uint32_t>& g : groups) {
      const PartitionItem piece = itemOf(model, triangles, g);  // before g moves
      add(piece, std::move(g));
    }
  }
  h.afterPartition = pieces.size();

  // Stage 2: clusters by proximity.
  std::vector<PartitionItem> items;
  items.reserve(pieces.size());
  for (const RedefinedObject& p : pieces) items.push_back(itemOf(p));
  MstClusteringOptions mst;
  mst.k = options.kScale * medianDiagonal(items);
  mst.maxTriangles = options.maxTriangles;
  mst.neighbours = options.neighbours;
  h.k = mst.k;
  const std::vector<std::vector<std::uint32_t>> clusters = clusterByMst(items, mst);
  h.clusters = clusters.size();

  // Stage 3: clusters over the limits (spread out: their triangles are within them) are
  // partitioned again by their objects.
  for (const std::vector<std::uint32_t>& cluster : clusters) {
    std::vector<std::vector<std::uint32_t>> parts{cluster};
    if (exceedsLimits(items, cluster, limits)) {
      std::vector<PartitionItem> members;
      for (std::uint32_t i : cluster) members.push_back(items[i]);
      parts = partitionTopDown(members, limits);
      for (auto& part : parts)
        for (std::uint32_t& i : part) i = cluster[i];
    }
    for (const auto& part : parts) h.objects.push_back(unite(pieces, part));
  }
  h.afterRepartition = h.objects.size();

  // Stage 4: the AABB hierarchy over the redefined objects.
  items.clear();
  for (const RedefinedObject& o : h.objects) items.push_back(itemOf(o));
  for (const AabbNode& n : buildAabbHierarchy(items, options.fanOut))
    h.nodes.push_back(
        {n.box, n.parent, n.firstChild, n.childCount, n.level, n.object, n.triangles});
  return h;
}

HierarchyShape shapeOf(const ObjectHierarchy& h) {
  HierarchyShape shape;
  std::uint32_t objects = 0;
  for (const RedefinedObject& o : h.objects)
    for (const ObjectPiece& p : o.pieces) objects = std::max(objects, p.object + 1);
  shape.leavesPerObject.assign(objects, 0);
  for (const ObjectHierarchy::Node& n : h.nodes) {
    shape.nodes.push_back({n.box, n.parent, n.firstChild, n.childCount, n.triangles});
    if (n.childCount > 0) continue;
    // A leaf counts once per input object, however many pieces of it it holds.
    std::vector<std::uint32_t> seen;
    for (const ObjectPiece& p : h.objects[n.object].pieces) seen.push_back(p.object);
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    for (std::uint32_t o : seen) ++shape.leavesPerObject[o];
  }
  return shape;
}

}  // namespace hlod
