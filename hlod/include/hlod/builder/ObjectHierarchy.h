#pragma once
// The scene hierarchy of a model of many objects (Manocha sec. 2.2): CAD data organised by
// function, where one pipe spanning the plant and a bolt of 20 polygons are both "objects". The
// objects are first redefined into uniformly sized ones, then put in a tree of boxes:
//   1. partition large objects into sub-objects, top down (ObjectPartition.h): an object over
//      maxTriangles triangles or maxExtent long is split by its polygons' centres of mass;
//   2. cluster the objects and sub-objects bottom up by proximity (MstClustering.h: Felzenszwalb
//      and Huttenlocher's minimum-spanning-tree segmentation on their nearest-neighbour graph);
//   3. partition again the clusters that are uneven in space (over maxExtent), top down;
//   4. build an AABB hierarchy over the redefined objects, top down (AabbHierarchy.h).
// The HLODs are then computed bottom up over this tree (HlodBuilder::addObjectHierarchy, sec.
// 2.2.1). Objects come from the import (Model::objectRuns: glTF node instances, OBJ o/g groups,
// city objects; a file without them is one object).
#include <cstdint>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/builder/HierarchyCriteria.h"

namespace hlod {

// How `hlodr build` organises a model: cut by planes into blocks (Lakhia III-A), or as the object
// hierarchy. Auto: objects for a model of at least kManyObjects objects that is not a city
// (CityJSON's buildings are grouped into blocks), planes otherwise.
enum class HierarchyMode { Auto, Planes, Objects };
constexpr std::size_t kManyObjects = 16;

// What Auto picks for a model (never Auto).
HierarchyMode resolveHierarchy(HierarchyMode mode, const Model& model);

struct ObjectHierarchyOptions {
  int fanOut = 3;                     // children per inner node, at most (C_levelFactor)
  std::uint64_t maxTriangles = 6000;  // a redefined object's triangles, at most
  // A redefined object's longest side, at most: extentFactor times the side of a cube of the
  // scene's box holding maxTriangles of its triangles, were they spread evenly (diagonal /
  // cbrt(triangles / maxTriangles)).
  double extentFactor = 2.0;
  // FH's k is kScale times the median diagonal of the objects' boxes: a lone object joins a
  // neighbour within kScale of its size, a cluster of n objects one within kScale / n.
  double kScale = 4.0;
  int neighbours = 10;  // the nearest-neighbour graph's edges per object
};

// A share of an input object: its triangles numbered across its runs in Model::objectRuns order
// (objectTriangles gives them).
struct ObjectPiece {
  std::uint32_t object = 0;
  std::vector<std::uint32_t> triangles;  // empty: all of them
};

// An object of the redefined set: pieces of one or more input objects.
struct RedefinedObject {
  std::vector<ObjectPiece> pieces;
  Aabb box;
  glm::dvec3 centre{0.0};  // centre of mass (area-weighted centroids)
  double area = 0.0;
  std::uint64_t triangles = 0;
};

struct ObjectHierarchy {
  std::vector<RedefinedObject> objects;
  // The tree, breadth-first from the root (node 0), children contiguous; a leaf's `object`
  // indexes objects, an inner node's is kNoObject.
  struct Node {
    Aabb box;
    std::uint32_t parent = 0xffffffffu;
    std::uint32_t firstChild = 0, childCount = 0;
    std::uint32_t level = 0;
    std::uint32_t object = 0xffffffffu;
    std::uint64_t triangles = 0;
  };
  std::vector<Node> nodes;
  // What each stage made: input objects (with triangles), objects and sub-objects after stage 1,
  // clusters after stage 2, redefined objects after stage 3.
  std::size_t inputObjects = 0, afterPartition = 0, clusters = 0, afterRepartition = 0;
  double maxExtent = 0.0;  // the limit stages 1 and 3 used
  double k = 0.0;          // FH's k used in stage 2
};

// The input objects of a model: per object, its runs (Model::objectRuns in order; a model
// without runs is one object holding every mesh).
std::vector<std::vector<ObjectRun>> objectRunsByObject(const Model& model);

// The (mesh, triangle) of each triangle of an object, in its numbering.
std::vector<std::pair<std::uint32_t, std::uint32_t>> objectTriangles(
    const std::vector<ObjectRun>& runs);

// Stages 1 to 4 for a model. Empty for a model without triangles.
ObjectHierarchy buildObjectHierarchy(const Model& model, const ObjectHierarchyOptions& options);

// The hierarchy as the criteria see it (HierarchyCriteria.h).
HierarchyShape shapeOf(const ObjectHierarchy& hierarchy);

}  // namespace hlod
