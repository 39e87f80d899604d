// The vertex hierarchy from edge collapses (Manocha sec. 3; Hoppe 1997; Garland and Heckbert
// 1997 for the collapse order and virtual pairs). See hlod/vdr/VertexHierarchy.h.
#include "hlod/vdr/VertexHierarchy.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <queue>
#include <string>
#include <unordered_map>

#include "hlod/metrics/TriangleBvh.h"

namespace hlod::vdr {

HierarchyInput hierarchyInputOf(const Mesh& mesh, const std::vector<std::uint8_t>& locked,
                                std::vector<std::uint32_t>* positionOf,
                                std::vector<std::array<std::uint32_t, 3>>* faceVertices) {
  HierarchyInput in;
  std::vector<std::uint32_t> posOf(mesh.positions.size());
  // Exact equality: welding by the bits of the doubles.
  struct Key {
    glm::dvec3 p;
    bool operator==(const Key& o) const { return std::memcmp(&p, &o.p, sizeof p) == 0; }
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 1469598103934665603ull;
      unsigned char bytes[sizeof(glm::dvec3)];
      std::memcpy(bytes, &k.p, sizeof bytes);
      for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
      return std::size_t(h);
    }
  };
  std::unordered_map<Key, std::uint32_t, Hash> index;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    auto [it, fresh] = index.emplace(Key{mesh.positions[v]}, std::uint32_t(in.positions.size()));
    if (fresh) {
      in.positions.push_back(mesh.positions[v]);
      if (!locked.empty()) in.locked.push_back(0);
    }
    posOf[v] = it->second;
    if (v < locked.size() && locked[v]) in.locked[it->second] = 1;
  }
  const std::size_t n = mesh.positions.size();
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const std::uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
    if (a >= n || b >= n || c >= n) continue;
    const std::array<std::uint32_t, 3> f{posOf[a], posOf[b], posOf[c]};
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) continue;
    in.faces.push_back(f);
    if (faceVertices) faceVertices->push_back({a, b, c});
  }
  if (positionOf) *positionOf = std::move(posOf);
  return in;
}

std::vector<std::uint32_t> VertexHierarchy::roots() const {
  std::vector<std::uint32_t> out;
  for (std::uint32_t v = 0; v < vertexCount(); ++v)
    if (parent[v] == kNone) out.push_back(v);
  return out;
}

void VertexHierarchy::leafRanges(std::vector<std::uint32_t>& first,
                                 std::vector<std::uint32_t>& last) const {
  first.assign(vertexCount(), 0);
  last.assign(vertexCount(), 0);
  std::uint32_t order = 0;
  std::vector<std::pair<std::uint32_t, bool>> stack;
  for (std::uint32_t r : roots()) {
    stack.push_back({r, false});
    while (!stack.empty()) {
      auto [v, done] = stack.back();
      stack.pop_back();
      if (isLeaf(v)) {
        first[v] = last[v] = order++;
      } else if (done) {
        first[v] = first[kept(v)];
        last[v] = last[removed(v)];
      } else {
        stack.push_back({v, true});
        stack.push_back({removed(v), false});
        stack.push_back({kept(v), false});
      }
    }
  }
}

namespace {

bool contains(const std::array<std::uint32_t, 3>& f, std::uint32_t v) {
  return f[0] == v || f[1] == v || f[2] == v;
}

// A plane quadric (Garland and Heckbert 1997): Q(p) = p'Ap + 2b'p + c, A symmetric.
struct Quadric {
  double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0;
  double b0 = 0, b1 = 0, b2 = 0, c = 0;

  static Quadric plane(const glm::dvec3& n, double d, double w) {
    Quadric q;
    q.a00 = w * n.x * n.x, q.a01 = w * n.x * n.y, q.a02 = w * n.x * n.z;
    q.a11 = w * n.y * n.y, q.a12 = w * n.y * n.z, q.a22 = w * n.z * n.z;
    q.b0 = w * d * n.x, q.b1 = w * d * n.y, q.b2 = w * d * n.z;
    q.c = w * d * d;
    return q;
  }
  Quadric& operator+=(const Quadric& o) {
    a00 += o.a00, a01 += o.a01, a02 += o.a02, a11 += o.a11, a12 += o.a12, a22 += o.a22;
    b0 += o.b0, b1 += o.b1, b2 += o.b2, c += o.c;
    return *this;
  }
  double operator()(const glm::dvec3& p) const {
    const double x = p.x, y = p.y, z = p.z;
    return x * (a00 * x + a01 * y + a02 * z) + y * (a01 * x + a11 * y + a12 * z) +
           z * (a02 * x + a12 * y + a22 * z) + 2.0 * (b0 * x + b1 * y + b2 * z) + c;
  }
};

double longestEdge2(const glm::dvec3 (&p)[3]) {
  return std::max({glm::dot(p[1] - p[0], p[1] - p[0]), glm::dot(p[2] - p[1], p[2] - p[1]),
                   glm::dot(p[0] - p[2], p[0] - p[2])});
}

glm::dvec3 unitOr(const glm::dvec3& n, const glm::dvec3& fallback) {
  const double l = glm::length(n);
  return l > 0.0 && std::isfinite(l) ? n / l : fallback;
}

Status validate(const HierarchyInput& in) {
  const std::size_t n = in.positions.size();
  if (n >= kNone / 2) return makeError("too many vertices for a vertex hierarchy");
  if (in.faces.size() >= kNone) return makeError("too many faces for a vertex hierarchy");
  if (!in.locked.empty() && in.locked.size() != n)
    return makeError("the lock flags do not match the vertices");
  for (const glm::dvec3& p : in.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return makeError("a vertex position is not finite");
  for (const auto& f : in.faces) {
    if (f[0] >= n || f[1] >= n || f[2] >= n) return makeError("a face index is out of range");
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
      return makeError("a face has a repeated corner");
  }
  return Ok{};
}

// The state of the mesh while it is collapsed, and the one operation that changes it: what both
// the quadric-ordered build and the hand-given sequence apply.
class Collapser {
 public:
  Collapser(const HierarchyInput& in, VertexHierarchy& h, std::uint32_t maxErrorSamples)
      : h_(h), maxErrorSamples_(std::max<std::uint32_t>(1, maxErrorSamples)) {
    const auto n = std::uint32_t(in.positions.size());
    h.leafCount = n;
    h.leafPosition = in.positions;
    h.faces = in.faces;
    h.parent.assign(n, kNone);
    h.leafOf.resize(n);
    std::iota(h.leafOf.begin(), h.leafOf.end(), 0u);
    h.error.assign(n, 0.0f);
    h.radius.assign(n, 0.0f);
    h.neighbourhoodStart = {0};
    corners_ = in.faces;
    live_.assign(in.faces.size(), 1);
    faceStamp_.assign(in.faces.size(), 0);
    incident_.resize(n);
    normal_.resize(in.faces.size());
    std::vector<metrics::Triangle> triangles;
    triangles.reserve(in.faces.size());
    for (std::uint32_t t = 0; t < in.faces.size(); ++t) {
      const auto& f = in.faces[t];
      for (std::uint32_t v : f) incident_[v].push_back(t);
      const metrics::Triangle tri{in.positions[f[0]], in.positions[f[1]], in.positions[f[2]]};
      normal_[t] = unitOr(glm::cross(tri[1] - tri[0], tri[2] - tri[0]), glm::dvec3(0.0));
      triangles.push_back(tri);
      for (std::uint32_t v : f)
        for (const glm::dvec3& c : tri)
          h.radius[v] = std::max(h.radius[v], float(glm::length(c - in.positions[v])));
    }
    if (!triangles.empty()) bvh_ = std::make_unique<metrics::TriangleBvh>(std::move(triangles));
    firstLeaf_.resize(n);
    lastLeaf_.resize(n);
    std::iota(firstLeaf_.begin(), firstLeaf_.end(), 0u);
    std::iota(lastLeaf_.begin(), lastLeaf_.end(), 0u);
    nextLeaf_.assign(n, kNone);
    leaves_.assign(n, 1);
  }

  bool active(std::uint32_t v) const { return v < h_.vertexCount() && h_.parent[v] == kNone; }
  const std::vector<std::uint32_t>& incident(std::uint32_t v) const { return incident_[v]; }
  const std::array<std::uint32_t, 3>& corners(std::uint32_t t) const { return corners_[t]; }

  // Moving `removed` onto `kept` turns or flattens a face it moves (see HierarchyOptions).
  bool foldsOver(std::uint32_t kept, std::uint32_t removed, double minFacing) const {
    const glm::dvec3 to = h_.position(kept);
    for (std::uint32_t t : incident_[removed]) {
      const auto& f = corners_[t];
      if (contains(f, kept)) continue;
      glm::dvec3 p[3], q[3];
      for (int i = 0; i < 3; ++i) {
        p[i] = h_.position(f[i]);
        q[i] = f[i] == removed ? to : p[i];
      }
      const glm::dvec3 before = glm::cross(p[1] - p[0], p[2] - p[0]);
      const glm::dvec3 after = glm::cross(q[1] - q[0], q[2] - q[0]);
      const double len = glm::length(after);
      const bool flatBefore = !(glm::length(before) > 1e-9 * longestEdge2(p));
      // A needle or a point has no side to face: made from a triangle, a fold all the same (a
      // sliver of the input may stay one).
      if (!(len > 1e-9 * longestEdge2(q))) {
        if (!flatBefore) return true;
        continue;
      }
      if (!flatBefore && glm::dot(before, after) <= 0.0) return true;
      if (normal_[t] != glm::dvec3(0.0) && glm::dot(after / len, normal_[t]) < minFacing)
        return true;
    }
    return false;
  }

  // Collapses (kept, removed) into a new vertex and returns it.
  std::uint32_t collapse(std::uint32_t kept, std::uint32_t removed) {
    VertexHierarchy& h = h_;
    const std::uint32_t v = h.vertexCount();
    h.parent.push_back(kNone);
    h.leafOf.push_back(h.leafOf[kept]);
    h.parent[kept] = h.parent[removed] = v;
    h.children.push_back({kept, removed});
    // The stored neighbourhood: every face around either child, as it is now.
    for (std::uint32_t t : incident_[kept]) h.storedFaces.push_back({t, corners_[t]});
    for (std::uint32_t t : incident_[removed])
      if (!contains(corners_[t], kept)) h.storedFaces.push_back({t, corners_[t]});
    h.neighbourhoodStart.push_back(std::uint32_t(h.storedFaces.size()));

    incident_.emplace_back();
    std::vector<std::uint32_t>& around = incident_[v];
    for (std::uint32_t t : incident_[removed]) {
      auto& f = corners_[t];
      if (contains(f, kept)) {
        // Both children in one face: it degenerates, and leaves its third corner's list.
        live_[t] = 0;
        for (std::uint32_t c : f)
          if (c != kept && c != removed) std::erase(incident_[c], t);
        continue;
      }
      for (std::uint32_t& c : f)
        if (c == removed) c = v;
      around.push_back(t);
    }
    for (std::uint32_t t : incident_[kept]) {
      if (!live_[t]) continue;
      for (std::uint32_t& c : corners_[t])
        if (c == kept) c = v;
      around.push_back(t);
    }
    incident_[kept] = {};
    incident_[removed] = {};

    firstLeaf_.push_back(firstLeaf_[kept]);
    lastLeaf_.push_back(lastLeaf_[removed]);
    nextLeaf_[lastLeaf_[kept]] = firstLeaf_[removed];
    leaves_.push_back(leaves_[kept] + leaves_[removed]);

    h.error.push_back(std::max({h.error[kept], h.error[removed], float(localHausdorff(v))}));
    const glm::dvec3 pv = h.position(v);
    double r = std::max(double(h.radius[kept]),
                        glm::length(h.position(removed) - pv) + double(h.radius[removed]));
    for (std::uint32_t t : around)
      for (std::uint32_t c : corners_[t]) r = std::max(r, glm::length(h.position(c) - pv));
    h.radius.push_back(float(r));
    return v;
  }

 private:
  // The local Hausdorff distance at v just after its collapse (see buildVertexHierarchy).
  double localHausdorff(std::uint32_t v) {
    const auto& around = incident_[v];
    const glm::dvec3 pv = h_.position(v);
    const auto faceDistance = [&](const glm::dvec3& p, std::uint32_t t) {
      const auto& f = corners_[t];
      return metrics::pointTriangleDistance(
          p, {h_.position(f[0]), h_.position(f[1]), h_.position(f[2])});
    };
    double e = 0.0;
    // Input -> current: each leaf below v (evenly sampled) to the faces around v, or where those
    // are farther than what is found so far, to the faces around v's neighbours too (a leaf of
    // a vertex slid along a straight border may now lie under a neighbour's face).
    std::vector<std::uint32_t> ring;
    bool ringMade = false;
    const std::uint32_t stride = (leaves_[v] + maxErrorSamples_ - 1) / maxErrorSamples_;
    std::uint32_t k = 0;
    for (std::uint32_t l = firstLeaf_[v]; l != kNone; l = nextLeaf_[l], ++k) {
      if (k % stride == 0) {
        const glm::dvec3& p = h_.leafPosition[l];
        double d = around.empty() ? glm::length(p - pv) : std::numeric_limits<double>::max();
        for (std::uint32_t t : around) d = std::min(d, faceDistance(p, t));
        if (d > e) {
          if (!ringMade) {
            ringMade = true;
            ++stamp_;
            for (std::uint32_t t : around) faceStamp_[t] = stamp_;
            for (std::uint32_t t : around)
              for (std::uint32_t c : corners_[t])
                for (std::uint32_t u : incident_[c])
                  if (faceStamp_[u] != stamp_) {
                    faceStamp_[u] = stamp_;
                    ring.push_back(u);
                  }
          }
          for (std::uint32_t t : ring) d = std::min(d, faceDistance(p, t));
          e = std::max(e, d);
        }
      }
      if (l == lastLeaf_[v]) break;
    }
    // Current -> input: v's part of each face around it, to the input's triangles.
    if (!bvh_) return e;
    for (std::uint32_t t : around) {
      const auto& f = corners_[t];
      glm::dvec3 other[2];
      int n = 0;
      for (std::uint32_t c : f)
        if (c != v && n < 2) other[n++] = h_.position(c);
      const glm::dvec3 samples[3] = {(2.0 * pv + other[0]) / 3.0, (2.0 * pv + other[1]) / 3.0,
                                     (4.0 * pv + other[0] + other[1]) / 6.0};
      for (const glm::dvec3& s : samples) e = std::max(e, bvh_->distance(s));
    }
    return e;
  }

  VertexHierarchy& h_;
  std::uint32_t maxErrorSamples_;
  std::vector<std::array<std::uint32_t, 3>> corners_;  // per face: its corners' vertices now
  std::vector<std::uint8_t> live_;
  std::vector<std::vector<std::uint32_t>> incident_;  // per vertex: its live faces
  std::vector<glm::dvec3> normal_;                    // per face: its input triangle's normal
  // Per vertex: its leaves, as a linked list (collapses concatenate two lists).
  std::vector<std::uint32_t> firstLeaf_, lastLeaf_, nextLeaf_, leaves_;
  std::unique_ptr<metrics::TriangleBvh> bvh_;
  std::vector<std::uint32_t> faceStamp_;  // per face: the last localHausdorff that listed it
  std::uint32_t stamp_ = 0;
};

// Quadric-ordered collapses: one candidate per pair, its cheaper allowed direction.
class QuadricOrder {
 public:
  QuadricOrder(const HierarchyInput& in, const HierarchyOptions& o, Collapser& c,
               VertexHierarchy& h)
      : in_(in), o_(o), c_(c), h_(h) {
    const std::size_t n = in.positions.size();
    quadric_.resize(n);
    locked_.assign(n, 0);
    blocked_.assign(n, 0);
    virtual_.assign(n, {});
    for (std::size_t v = 0; v < in.locked.size(); ++v) locked_[v] = in.locked[v] != 0;
    // Face planes, area weighted; and for each open edge a plane through it at right angles
    // to its face, so that borders keep their shape (Garland and Heckbert sec. 6.1).
    std::unordered_map<std::uint64_t, std::int32_t> edgeUse;
    for (const auto& f : in.faces) {
      const glm::dvec3 a = in.positions[f[0]], b = in.positions[f[1]], cc = in.positions[f[2]];
      const glm::dvec3 cr = glm::cross(b - a, cc - a);
      const double area2 = glm::length(cr);
      if (!(area2 > 0.0)) continue;
      const glm::dvec3 nrm = cr / area2;
      const Quadric q = Quadric::plane(nrm, -glm::dot(nrm, a), 0.5 * area2);
      for (std::uint32_t v : f) quadric_[v] += q;
      for (int i = 0; i < 3; ++i) {
        const std::uint32_t x = f[i], y = f[(i + 1) % 3];
        const std::uint64_t key = (std::uint64_t(std::min(x, y)) << 32) | std::max(x, y);
        edgeUse[key] += 1;
      }
    }
    for (const auto& f : in.faces) {
      const glm::dvec3 a = in.positions[f[0]], b = in.positions[f[1]], cc = in.positions[f[2]];
      const glm::dvec3 nrm = unitOr(glm::cross(b - a, cc - a), glm::dvec3(0.0));
      for (int i = 0; i < 3; ++i) {
        const std::uint32_t x = f[i], y = f[(i + 1) % 3];
        const std::uint64_t key = (std::uint64_t(std::min(x, y)) << 32) | std::max(x, y);
        if (edgeUse[key] != 1) continue;
        const glm::dvec3 e = in.positions[y] - in.positions[x];
        const glm::dvec3 side = unitOr(glm::cross(e, nrm), glm::dvec3(0.0));
        if (side == glm::dvec3(0.0)) continue;
        const Quadric q =
            Quadric::plane(side, -glm::dot(side, in.positions[x]), 100.0 * glm::dot(e, e));
        quadric_[x] += q;
        quadric_[y] += q;
      }
    }
    if (o.virtualEdgeDistance > 0.0) addVirtualEdges();
    for (const auto& f : in.faces)
      for (int i = 0; i < 3; ++i) push(f[i], f[(i + 1) % 3]);
    for (std::uint32_t v = 0; v < virtual_.size(); ++v)
      for (std::uint32_t w : virtual_[v])
        if (v < w) push(v, w);
  }

  void run() {
    while (!heap_.empty()) {
      const Candidate cand = heap_.top();
      heap_.pop();
      if (!c_.active(cand.kept) || !c_.active(cand.removed)) continue;
      const std::uint32_t kept = cand.kept, removed = cand.removed;
      if (c_.foldsOver(kept, removed, o_.minFacing)) {
        // The other way round at its own cost, where allowed; and both ends wait for a change of
        // their neighbourhoods to try this way again.
        if (!cand.reversed) push(removed, kept, true);
        blocked_[removed] = blocked_[kept] = 1;
        continue;
      }
      // The children's neighbours stay v's candidates even where their faces die with the
      // collapse (the last triangle of a part): the part can then shrink to one vertex.
      std::vector<std::uint32_t> ring = neighbours(kept);
      for (std::uint32_t w : neighbours(removed)) ring.push_back(w);
      const std::uint32_t v = c_.collapse(kept, removed);
      quadric_.push_back(quadric_[kept]);
      quadric_.back() += quadric_[removed];
      locked_.push_back(locked_[kept]);
      blocked_.push_back(0);
      virtual_.push_back(virtualPartners(kept, removed));
      for (std::uint32_t w : neighbours(v)) ring.push_back(w);
      std::erase_if(ring, [&](std::uint32_t w) { return w == kept || w == removed || w == v; });
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      // A vertex left without faces stays linked to what it touched, as a virtual edge: a
      // part shrinks to one vertex and still joins its neighbours.
      for (std::uint32_t w : ring)
        if (c_.incident(v).empty() || c_.incident(w).empty()) {
          virtual_[v].push_back(w);
          virtual_[w].push_back(v);
        }
      for (std::uint32_t w : ring) push(v, w);
      // A vertex whose collapse folded over may not now that its neighbourhood moved.
      for (std::uint32_t w : ring) {
        if (!blocked_[w]) continue;
        blocked_[w] = 0;
        for (std::uint32_t z : neighbours(w))
          if (z != v) push(w, z);
      }
    }
  }

 private:
  struct Candidate {
    double cost = 0.0;
    double length2 = 0.0;  // ties (flat regions) go to the shorter edge
    std::uint32_t kept = 0, removed = 0;
    bool reversed = false;  // the costlier direction of its pair, the other having folded
    bool operator<(const Candidate& o) const {
      return cost != o.cost ? cost > o.cost : length2 > o.length2;
    }
  };

  // The active neighbours of v: through its faces, and its virtual edges.
  std::vector<std::uint32_t> neighbours(std::uint32_t v) const {
    std::vector<std::uint32_t> out;
    for (std::uint32_t t : c_.incident(v))
      for (std::uint32_t c : c_.corners(t))
        if (c != v) out.push_back(c);
    for (std::uint32_t w : virtual_[v])
      if (const std::uint32_t y = activeAncestor(w); y != v) out.push_back(y);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  std::uint32_t activeAncestor(std::uint32_t v) const {
    while (h_.parent[v] != kNone) v = h_.parent[v];
    return v;
  }

  std::vector<std::uint32_t> virtualPartners(std::uint32_t a, std::uint32_t b) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t x : {a, b}) {
      for (std::uint32_t w : virtual_[x]) {
        const std::uint32_t y = activeAncestor(w);
        if (y != h_.vertexCount() - 1) out.push_back(y);
      }
      virtual_[x] = {};
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  // The cheaper allowed direction of the pair (x, y); with `only`, x -> y (x removed).
  void push(std::uint32_t x, std::uint32_t y, bool only = false) {
    if (x == y) return;
    const glm::dvec3 px = h_.position(x), py = h_.position(y);
    Quadric q = quadric_[x];
    q += quadric_[y];
    // x -> y keeps y's position; y -> x keeps x's.
    const double inf = std::numeric_limits<double>::infinity();
    const double toY = locked_[x] ? inf : q(py);
    const double toX = locked_[y] || only ? inf : q(px);
    if (!std::isfinite(std::min(toX, toY))) return;
    const glm::dvec3 d = px - py;
    Candidate c;
    c.length2 = glm::dot(d, d);
    c.reversed = only;
    if (toY <= toX) {
      c.cost = std::max(0.0, toY), c.kept = y, c.removed = x;
    } else {
      c.cost = std::max(0.0, toX), c.kept = x, c.removed = y;
    }
    heap_.push(c);
  }

  // Pairs of vertices of different connected parts within virtualEdgeDistance: a uniform grid of
  // that cell size, the nearest virtualEdgesPerVertex of each vertex.
  void addVirtualEdges() {
    const std::size_t n = in_.positions.size();
    std::vector<std::uint32_t> part(n);
    std::iota(part.begin(), part.end(), 0u);
    const auto find = [&](std::uint32_t x) {
      while (part[x] != x) x = part[x] = part[part[x]];
      return x;
    };
    for (const auto& f : in_.faces) {
      const std::uint32_t a = find(f[0]);
      part[find(f[1])] = a;
      part[find(f[2])] = a;
    }
    const double cell = o_.virtualEdgeDistance;
    const auto key = [&](const glm::ivec3& c) {
      return (std::uint64_t(std::uint32_t(c.x) & 0x1fffff) << 42) |
             (std::uint64_t(std::uint32_t(c.y) & 0x1fffff) << 21) |
             std::uint64_t(std::uint32_t(c.z) & 0x1fffff);
    };
    const auto cellOf = [&](const glm::dvec3& p) { return glm::ivec3(glm::floor(p / cell)); };
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
    for (std::uint32_t v = 0; v < n; ++v) grid[key(cellOf(in_.positions[v]))].push_back(v);
    const double limit2 = cell * cell;
    for (std::uint32_t v = 0; v < n; ++v) {
      const glm::dvec3 p = in_.positions[v];
      const glm::ivec3 c = cellOf(p);
      const std::uint32_t pv = find(v);
      std::vector<std::pair<double, std::uint32_t>> near;
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            auto it = grid.find(key(c + glm::ivec3(dx, dy, dz)));
            if (it == grid.end()) continue;
            for (std::uint32_t w : it->second) {
              if (find(w) == pv) continue;
              const double d2 = glm::dot(in_.positions[w] - p, in_.positions[w] - p);
              if (d2 <= limit2) near.emplace_back(d2, w);
            }
          }
      const std::size_t keep = std::min<std::size_t>(near.size(), o_.virtualEdgesPerVertex);
      std::partial_sort(near.begin(), near.begin() + keep, near.end());
      for (std::size_t i = 0; i < keep; ++i) {
        virtual_[v].push_back(near[i].second);
        virtual_[near[i].second].push_back(v);
      }
    }
    for (auto& list : virtual_) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
  }

  const HierarchyInput& in_;
  const HierarchyOptions& o_;
  Collapser& c_;
  VertexHierarchy& h_;
  std::vector<Quadric> quadric_;
  std::vector<std::uint8_t> locked_;
  std::vector<std::uint8_t> blocked_;  // per vertex: a collapse of it folded over
  std::vector<std::vector<std::uint32_t>> virtual_;
  std::priority_queue<Candidate> heap_;
};

}  // namespace

Result<VertexHierarchy> buildVertexHierarchy(const HierarchyInput& input,
                                             const HierarchyOptions& options) {
  if (auto ok = validate(input); !ok) return ok.error();
  VertexHierarchy h;
  Collapser collapser(input, h, options.maxErrorSamples);
  QuadricOrder order(input, options, collapser, h);
  order.run();
  return h;
}

Result<VertexHierarchy> buildVertexHierarchy(const HierarchyInput& input,
                                             std::span<const Collapse> collapses) {
  if (auto ok = validate(input); !ok) return ok.error();
  VertexHierarchy h;
  Collapser collapser(input, h, HierarchyOptions{}.maxErrorSamples);
  for (std::size_t i = 0; i < collapses.size(); ++i) {
    const Collapse& c = collapses[i];
    if (c.kept == c.removed || !collapser.active(c.kept) || !collapser.active(c.removed))
      return makeError("collapse " + std::to_string(i) + " names a vertex that is not active");
    collapser.collapse(c.kept, c.removed);
  }
  return h;
}

}  // namespace hlod::vdr
