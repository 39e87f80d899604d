#pragma once
// The bounding-sphere hierarchy of Parry et al., "Hierarchical organization of urban models"
// (sec. 5, after QSplat [Rus00]): "The sphere hierarchy is set up by starting from the bounding
// box for the overall model and recursively splitting vertices along the longest axis to find
// the bounding boxes (and bounding spheres) of the children." At the highest LOD each vertex is a
// leaf sphere; "parent nodes hold the average position of their children and their bounding
// spheres encompass the child bounding spheres". Each node keeps its centre and radius (its
// splat size), a normal, the width of its normal cone and a texture coordinate, enough to draw it
// as a splat.
//
// Vertices are split in groups that are never combined with each other (a facade face's inside,
// one straight run of its outline), and silhouette vertices are never combined at all (sec. 5:
// "silhouette vertices are not combined with other vertices"): each group is a tree of its own,
// each silhouette vertex a root of its own.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace hlod {

constexpr std::uint32_t kNoSphere = 0xffffffffu;

struct SphereNode {
  // A leaf: its vertex; a parent: the average of its children's centres (a corner merge: its
  // corner's).
  glm::dvec3 centre{0.0};
  double radius = 0.0;                 // the splat size (a parent's sphere holds its children's)
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // unit: a leaf's own, a parent's the children's average
  float coneCos = 1.0f;                // cos of the normal cone's half-width (1: a single normal)
  glm::vec2 texCoord{0.0f};            // a parent's: the average of its children's
  std::uint32_t parent = kNoSphere;
  std::uint32_t child[2] = {kNoSphere, kNoSphere};  // both kNoSphere for a leaf
  bool isLeaf() const { return child[0] == kNoSphere; }
};

// A vertex to organise: its position, unit normal, texture coordinate, leaf splat radius (about
// half the longest edge at it, so that leaf splats cover the surface), the group it may be
// combined within, and whether it is a silhouette vertex.
struct SphereVertex {
  glm::dvec3 position{0.0};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};
  glm::vec2 texCoord{0.0f};
  double radius = 0.0;
  std::uint32_t group = 0;
  bool silhouette = false;
};

struct SphereHierarchy {
  // nodes[v] is the leaf of vertex v; parents follow, each after both its children.
  std::vector<SphereNode> nodes;
  // One per group and one per silhouette vertex; after mergeIntoCorners, the trees it made.
  std::vector<std::uint32_t> roots;
  std::size_t leafCount = 0;
  // The last `merges` nodes are corner merges (mergeIntoCorners), combined after the forest.
  std::size_t merges = 0;
};

// Builds the forest. Deterministic in the vertices' positions, not their order within a group:
// two copies of one outline run (each face that shares it has its own) get equal trees, so both
// faces move the run's vertices alike and meet without a crack.
SphereHierarchy buildSphereHierarchy(std::span<const SphereVertex> vertices);

// "At the highest level of the hierarchy (lowest LOD), we wish to retain the fewest points
// necessary to describe a facade face" (sec. 5): once a straight run of a face's outline has
// combined into its root, that root combines into a corner at the run's end. Per pair (root of a
// run, corner leaf), in order: a parent of the corner's top node (the leaf or an earlier merge's
// parent) and the run's root, standing at the corner (the corner never moves; the run, straight,
// folds onto its own line), its sphere holding both. Roots are updated. Called once, after the
// forest is built.
void mergeIntoCorners(SphereHierarchy& hierarchy,
                      std::span<const std::pair<std::uint32_t, std::uint32_t>> runIntoCorner);

// The nodes of a cut through the forest with about `count` nodes (at least one per root): from
// the roots, the node of largest radius is replaced by its children until there are count
// nodes or only leaves. For splat rendering at a fixed size.
std::vector<std::uint32_t> sphereCut(const SphereHierarchy& hierarchy, std::size_t count);

}  // namespace hlod
