#pragma once
// The criteria for a scene hierarchy of Manocha sec. 2.1.1, measured: localisation, tree depth
// and balance, overlap between sibling boxes, and object size (the fifth, simplicity, is the
// runtime's: every hierarchy here is a tree of boxes). For `hlodr info`, to compare the object
// hierarchy (builder/ObjectHierarchy.h) with the plane cuts on the same input.
//
// Volumes are of boxes grown by `pad` on every side, so that flat boxes (a floor, a wall) have a
// volume and two flat siblings crossing each other an overlap.
#include <cstdint>
#include <vector>

#include "hlod/Mesh.h"

namespace hlod {

// A node of a hierarchy as the criteria see it: its box, its place in the tree and, for a leaf,
// its triangles. Parents come before their children; children are contiguous.
struct HierarchyNode {
  Aabb box;
  std::uint32_t parent = 0xffffffffu;  // none: a root
  std::uint32_t firstChild = 0, childCount = 0;
  std::uint64_t triangles = 0;  // a leaf's
};

struct HierarchyShape {
  std::vector<HierarchyNode> nodes;
  // Per input object, how many leaves hold some of its triangles (0: none, it had none).
  std::vector<std::uint32_t> leavesPerObject;
};

// Min, median, max of a list (nearest rank; zeros when empty).
struct Spread3 {
  double min = 0.0, median = 0.0, max = 0.0;
};

struct HierarchyFigures {
  std::size_t nodes = 0, leaves = 0, roots = 0;
  // 1. Localisation: how much of an inner node's box its children's boxes fill (the volume of
  // their union over its volume, mean over the inner nodes with at most kMaxFillChildren
  // children), and how the input's objects are cut: leaves per object (mean over the objects
  // with triangles; 1 when none is cut) and the share of objects spread over several leaves.
  double innerFill = 0.0;
  double leavesPerObject = 0.0;
  double objectsCut = 0.0;
  // 2. Depth and balance: the leaves' depths (a root's is 0), and balance = shallowest leaf over
  // deepest (1 for a complete tree).
  std::uint32_t depth = 0, minLeafDepth = 0;
  double meanLeafDepth = 0.0;
  double balance = 0.0;
  // 3. Overlap between sibling boxes (the roots count as siblings): per node with two or more
  // children, the volume its children's boxes share pairwise over the node's volume, mean over
  // those nodes (0: none; pairs sharing a volume count each time); and the share of sibling pairs
  // whose boxes overlap.
  double siblingOverlap = 0.0;
  double overlappingPairs = 0.0;
  // 4. Object size: the leaves' triangles, and their box diagonals over the scene's.
  Spread3 leafTriangles;
  Spread3 leafDiagonal;
};

// The inner nodes whose fill is measured: the union of more boxes is left out (it costs the
// cube of their number).
constexpr std::uint32_t kMaxFillChildren = 16;

// The volume the boxes a and b share (0 when they do not overlap, or only touch).
double overlapVolume(const Aabb& a, const Aabb& b);

// The volume of the union of boxes (exact: over the grid their faces make).
double unionVolume(const std::vector<Aabb>& boxes);

HierarchyFigures measureHierarchy(const HierarchyShape& shape, double pad);

// The pad measureHierarchy is given by `hlodr info`: a thousandth of the scene's diagonal.
double defaultPad(const HierarchyShape& shape);

}  // namespace hlod
