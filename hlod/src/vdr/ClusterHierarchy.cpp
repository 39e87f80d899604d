// The cluster hierarchy generation of Manocha sec. 3.1 (Yoon, Salomon, Manocha 2003). See
// hlod/vdr/ClusterHierarchy.h.
#include "hlod/vdr/ClusterHierarchy.h"

#include <algorithm>
#include <cassert>
#include <deque>
#include <limits>
#include <queue>

#include "hlod/vdr/ActiveMesh.h"

namespace hlod::vdr {

double ClusterHierarchy::errorRatio(std::uint32_t c) const {
  const Cluster& k = clusters[c];
  return std::max(double(k.maxError), errorFloor) / std::max(double(k.minError), errorFloor);
}

double ClusterHierarchy::errorRange(std::uint32_t c) const {
  return double(clusters[c].maxError) - double(clusters[c].minError);
}

namespace {

class Clustering {
 public:
  Clustering(const VertexHierarchy& h, const ClusterOptions& o, ClusterHierarchy& out)
      : h_(h), o_(o), out_(out), mesh_(h) {
    out.errorFloor = o.errorFloor;
    if (!(out.errorFloor > 0.0)) {
      out.errorFloor = std::numeric_limits<double>::max();
      for (float e : h.error)
        if (e > 0.0f) out.errorFloor = std::min(out.errorFloor, double(e));
      if (out.errorFloor == std::numeric_limits<double>::max()) out.errorFloor = 1.0;
    }
    out.clusterOf.assign(h.vertexCount(), kNone);
    queuedIn_.assign(h.vertexCount(), kNone);
  }

  void run() {
    // Initially one cluster, its vertex queue the roots.
    newCluster(kNone, h_.roots());
    std::size_t idle = 0;  // clusters dequeued in a row without a vertex added
    while (!clusterQueue_.empty()) {
      const std::uint32_t c = clusterQueue_.front();  // step 1
      clusterQueue_.pop_front();
      bool added = false;
      for (;;) {
        if (queues_[c].empty()) break;               // every vertex placed: C is done
        const std::uint32_t v = queues_[c].front();  // step 2
        if (!h_.isLeaf(v) && !mesh_.canSplit(v)) {   // step 3
          clusterQueue_.push_back(c);
          break;
        }
        popTop(c);
        if (!add(c, v)) break;  // step 4: C split in two, done
        added = true;           // steps 5 and 6
      }
      idle = added ? 0 : idle + 1;
      if (idle > clusterQueue_.size() && !clusterQueue_.empty()) {
        unblock();
        idle = 0;
      }
    }
    finish();
  }

 private:
  // Max-heap order: higher error first; on equal error, the vertex made later.
  bool before(std::uint32_t a, std::uint32_t b) const {
    return h_.error[a] != h_.error[b] ? h_.error[a] < h_.error[b] : a < b;
  }
  // fresh: v was not queued before (partition moves queued vertices: they are in latest_).
  void pushVertex(std::uint32_t c, std::uint32_t v, bool fresh = true) {
    queuedIn_[v] = c;
    if (fresh && !h_.isLeaf(v)) latest_.push(v);
    queues_[c].push_back(v);
    std::push_heap(queues_[c].begin(), queues_[c].end(),
                   [&](std::uint32_t a, std::uint32_t b) { return before(a, b); });
  }
  void popTop(std::uint32_t c) {
    queuedIn_[queues_[c].front()] = kNone;
    std::pop_heap(queues_[c].begin(), queues_[c].end(),
                  [&](std::uint32_t a, std::uint32_t b) { return before(a, b); });
    queues_[c].pop_back();
  }

  std::uint32_t newCluster(std::uint32_t parent, std::vector<std::uint32_t> queue,
                           bool fresh = true) {
    const auto c = std::uint32_t(out_.clusters.size());
    Cluster k;
    k.parent = parent;
    k.depth = parent == kNone ? 0 : out_.clusters[parent].depth + 1;
    out_.clusters.push_back(k);
    queues_.emplace_back();
    for (std::uint32_t v : queue) pushVertex(c, v, fresh);
    clusterQueue_.push_back(c);
    return c;
  }

  double floored(float e) const { return std::max(double(e), out_.errorFloor); }

  // Steps 4 to 6 for v, taken from C's queue: false when C split instead. unchecked: split v
  // without the neighbourhood test (unblock()).
  bool add(std::uint32_t c, std::uint32_t v, bool unchecked = false) {
    Cluster& k = out_.clusters[c];
    const float e = h_.error[v];
    if (k.vertexCount > 0) {
      const double hi = floored(std::max(k.maxError, e)), lo = floored(std::min(k.minError, e));
      if (hi / lo > o_.maxErrorRatio || k.vertexCount + 1 > o_.maxVertices) {
        pushVertex(c, v, false);
        partition(c);
        return false;
      }
      k.minError = std::min(k.minError, e);
      k.maxError = std::max(k.maxError, e);
    } else {
      k.minError = k.maxError = e;
    }
    ++k.vertexCount;
    out_.clusterOf[v] = c;
    if (!h_.isLeaf(v)) {
      if (unchecked) {
        mesh_.splitUnchecked(v);
        ++out_.uncheckedSplits;
      } else {
        mesh_.split(v);
      }
      pushVertex(c, h_.kept(v));
      pushVertex(c, h_.removed(v));
    }
    return true;
  }

  // Step 4(a, b): C's queue halved at the median along the longest side of its box.
  void partition(std::uint32_t c) {
    std::vector<std::uint32_t> q = std::move(queues_[c]);
    queues_[c] = {};
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (std::uint32_t v : q) {
      lo = glm::min(lo, h_.position(v));
      hi = glm::max(hi, h_.position(v));
    }
    const glm::dvec3 size = hi - lo;
    const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
    const std::size_t half = q.size() / 2;
    std::nth_element(q.begin(), q.begin() + half, q.end(), [&](std::uint32_t a, std::uint32_t b) {
      const double pa = h_.position(a)[axis], pb = h_.position(b)[axis];
      return pa != pb ? pa < pb : a < b;
    });
    std::vector<std::uint32_t> left(q.begin(), q.begin() + half), right(q.begin() + half, q.end());
    // (newCluster grows the clusters: no reference into them is held across it.)
    if (left.empty()) {
      const std::uint32_t only = newCluster(c, std::move(right), false);
      out_.clusters[c].children[0] = only;
    } else {
      const std::uint32_t l = newCluster(c, std::move(left), false);
      const std::uint32_t r = newCluster(c, std::move(right), false);
      out_.clusters[c].children = {l, r};
    }
  }

  // Every queued cluster waits on a split: add the queued vertex made last in the build (the top
  // of latest_, whose placed vertices are dropped on the way). Its split is safe in the build's
  // reverse order, but a split taken earlier out of that order may have left a face around it
  // finer than the build had it, which no later split undoes: it is then split without the test,
  // or the clustering would never end.
  void unblock() {
    while (!latest_.empty() && queuedIn_[latest_.top()] == kNone) latest_.pop();
    assert(!latest_.empty());
    if (latest_.empty()) return;
    const std::uint32_t best = latest_.top(), owner = queuedIn_[best];
    auto& q = queues_[owner];
    q.erase(std::find(q.begin(), q.end(), best));
    queuedIn_[best] = kNone;
    std::make_heap(q.begin(), q.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return before(a, b); });
    if (!add(owner, best, !mesh_.canSplit(best))) std::erase(clusterQueue_, owner);
  }

  void finish() {
    for ([[maybe_unused]] std::uint32_t c : out_.clusterOf) assert(c != kNone);
  }

  const VertexHierarchy& h_;
  const ClusterOptions& o_;
  ClusterHierarchy& out_;
  ActiveMesh mesh_;
  std::vector<std::vector<std::uint32_t>> queues_;  // per cluster: its vertex priority queue
  std::deque<std::uint32_t> clusterQueue_;
  std::vector<std::uint32_t> queuedIn_;        // per vertex: the cluster whose queue holds it
  std::priority_queue<std::uint32_t> latest_;  // queued inner vertices, made last first
};

}  // namespace

ClusterHierarchy buildClusterHierarchy(const VertexHierarchy& hierarchy,
                                       const ClusterOptions& options) {
  ClusterHierarchy out;
  Clustering(hierarchy, options, out).run();
  return out;
}

}  // namespace hlod::vdr
