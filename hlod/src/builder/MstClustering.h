#pragma once
// Clustering, stage 2 of Manocha sec. 2.2: "Organize disjoint objects and sub-objects into
// clusters (bottom-up)", with the minimum-spanning-tree method the paper adapts from image
// segmentation (P. F. Felzenszwalb and D. P. Huttenlocher, "Efficient graph-based image
// segmentation", IJCV 59(2), 2004, the journal form of their 1998 paper; the merging is
// Kruskal's algorithm, J. B. Kruskal 1956).
//
// The graph: each object is a vertex joined to its `neighbours` nearest objects (their nearest
// neighbour graph, with the distance between two objects' boxes as the edge weight w: 0 for boxes
// that touch or overlap). Edges in non-decreasing order of w (ties: the nearer centres first).
// Each cluster C keeps Int(C), the largest weight in its minimum spanning tree (the edges that
// merged it), and |C|, its number of objects. An edge between C1 and C2 merges them when
//     w <= MInt(C1, C2) = min(Int(C1) + tau(C1), Int(C2) + tau(C2)),   tau(C) = k / |C|,
// Felzenszwalb and Huttenlocher's predicate, and (the adaptation to uniformly sized objects) when
// the merged cluster holds at most maxTriangles triangles. Private to the builder.
#include <cstdint>
#include <span>
#include <vector>

#include "builder/SplitAxis.h"

namespace hlod {

struct MstClusteringOptions {
  double k = 1.0;                     // FH's k (world units: tau is a distance)
  std::uint64_t maxTriangles = 6000;  // a cluster's triangles, at most
  int neighbours = 10;                // edges per object (FH used 10 nearest neighbours)
};

// The distance between two boxes (0 when they touch or overlap).
double boxGap(const Aabb& a, const Aabb& b);

// The clusters of the items (their boxes, centres and triangle counts), each a list of item
// indices ascending, the clusters ordered by their first item. Every item is in exactly one.
std::vector<std::vector<std::uint32_t>> clusterByMst(std::span<const PartitionItem> items,
                                                     const MstClusteringOptions& options);

}  // namespace hlod
