#pragma once
// The cluster hierarchy of Manocha sec. 3.1 (Yoon, Salomon, Manocha, IEEE Visualization 2003):
// the vertex hierarchy cut into clusters, the units of occlusion culling and of drawing, by
// descending it from its roots:
//   "Initially, the cluster queue contains a single cluster. The vertex priority queue
//    associated with this initial cluster contains the roots of the vertex hierarchy. While the
//    cluster queue is not empty the following steps are performed:
//    1. Dequeue the cluster, C, at the front of the cluster queue.
//    2. Dequeue the vertex, v, with highest error from the vertex priority queue.
//    3. If splitting v is not fold-over safe, return it to the vertex priority queue, place C at
//       the back of the cluster queue and go back to Step 1.
//    4. If adding v to C makes the error ratio of C too large or increases its vertex count
//       beyond the target: (a) create two children clusters C_l and C_r of C in the cluster
//       queue, (b) partition the vertex priority queue and assign the two resulting queues to
//       C_l and C_r, (c) go back to Step 1 without placing C in the back of the cluster queue.
//    5. Add v to C, update the number of vertices and the error ratio associated with C.
//    6. Replace v on the active vertex front by its children and enqueue the children in the
//       vertex priority queue associated with C. Go back to Step 2."
// The front is an ActiveMesh, so "fold-over safe" is its neighbourhood test; a leaf is added
// without a split. Where the paper is silent:
//  - the error ratio is max / min of the cluster's errors, each taken at least errorFloor (the
//    leaves' error is 0): by default the smallest non-zero error of the hierarchy;
//  - step 4(b) halves the queue at the median of its vertices' positions along the longest
//    side of their box; a queue of one vertex makes one child;
//  - the paper notes that a split never waits on its own queue when errors shrink with every
//    split, which a local Hausdorff distance does not promise. When every cluster in the queue
//    has been tried once in a row without adding a vertex, the front vertex made last in the
//    build is added to its cluster out of error order. Its split is safe in the build's order
//    reversed, unless a split taken earlier out of that order left a face around it finer than
//    the build had it (no later split undoes that): it is then split without the test, or the
//    clustering would never end (head.stl did not).
#include <cstdint>
#include <vector>

#include "hlod/vdr/VertexHierarchy.h"

namespace hlod::vdr {

struct ClusterOptions {
  double maxErrorRatio = 8.0;        // "the error ratio of C too large": above this
  std::uint32_t maxVertices = 2048;  // "its vertex count beyond the target": above this
  double errorFloor = 0.0;           // 0: the hierarchy's smallest non-zero error
};

struct Cluster {
  std::uint32_t parent = kNone;
  std::array<std::uint32_t, 2> children{kNone, kNone};  // C_l, C_r (kNone: none)
  std::uint32_t vertexCount = 0;
  float minError = 0.0f;  // the error range: [minError, maxError] of its vertices
  float maxError = 0.0f;
  std::uint32_t depth = 0;  // 0 for the first cluster
};

struct ClusterHierarchy {
  std::vector<Cluster> clusters;         // cluster 0 is the first one (it holds the roots' top)
  std::vector<std::uint32_t> clusterOf;  // per vertex of the hierarchy
  double errorFloor = 0.0;               // what the error ratio counts a smaller error as
  std::uint32_t uncheckedSplits = 0;     // splits the build took without the test (not stored)

  // Yoon et al. 2003: "The error ratio is defined as the ratio of the maximum error value
  // associated with a vertex in the cluster to that of the minimum. The error range is the
  // difference between the maximum and minimum error values in a cluster."
  double errorRatio(std::uint32_t c) const;
  double errorRange(std::uint32_t c) const;
};

// Every vertex ends in exactly one cluster; no cluster is empty.
ClusterHierarchy buildClusterHierarchy(const VertexHierarchy& hierarchy,
                                       const ClusterOptions& options = {});

}  // namespace hlod::vdr
