// The active front and its faces under vertex splits and edge collapses with the neighbourhood
// test (Manocha sec. 3). See hlod/vdr/ActiveMesh.h.
#include "hlod/vdr/ActiveMesh.h"

#include <algorithm>
#include <cassert>

namespace hlod::vdr {

namespace {

bool holds(const std::array<std::uint32_t, 3>& f, std::uint32_t v) {
  return f[0] == v || f[1] == v || f[2] == v;
}

}  // namespace

ActiveMesh::ActiveMesh(const VertexHierarchy& hierarchy) : h_(hierarchy) {
  const std::uint32_t n = h_.vertexCount();
  const std::size_t faces = h_.faces.size();
  active_.assign(n, 0);
  live_.assign(faces, 0);
  corner_.assign(3 * faces, kNone);
  head_.assign(n, kNone);
  next_.assign(3 * faces, kNone);
  prev_.assign(3 * faces, kNone);
  h_.leafRanges(first_, last_);
  for (std::uint32_t r : h_.roots()) {
    active_[r] = 1;
    ++activeCount_;
  }
  // Each face at its corners' roots, live where those differ.
  std::vector<std::uint32_t> rootOf(h_.leafCount);
  for (std::uint32_t l = 0; l < h_.leafCount; ++l) {
    std::uint32_t v = l;
    while (h_.parent[v] != kNone) v = h_.parent[v];
    rootOf[l] = v;
  }
  for (std::uint32_t t = 0; t < faces; ++t) {
    const auto& f = h_.faces[t];
    const std::array<std::uint32_t, 3> c{rootOf[f[0]], rootOf[f[1]], rootOf[f[2]]};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
    live_[t] = 1;
    ++liveCount_;
    for (int i = 0; i < 3; ++i) link(3 * t + i, c[i]);
  }
}

void ActiveMesh::link(std::uint32_t c, std::uint32_t v) {
  corner_[c] = v;
  prev_[c] = kNone;
  next_[c] = head_[v];
  if (head_[v] != kNone) prev_[head_[v]] = c;
  head_[v] = c;
}

void ActiveMesh::unlink(std::uint32_t c) {
  const std::uint32_t v = corner_[c];
  if (prev_[c] != kNone)
    next_[prev_[c]] = next_[c];
  else
    head_[v] = next_[c];
  if (next_[c] != kNone) prev_[next_[c]] = prev_[c];
  prev_[c] = next_[c] = kNone;
}

std::uint32_t ActiveMesh::cornersAt(std::uint32_t v) const {
  std::uint32_t n = 0;
  for (std::uint32_t c = head_[v]; c != kNone; c = next_[c]) ++n;
  return n;
}

std::vector<std::uint32_t> ActiveMesh::activeVertices() const {
  std::vector<std::uint32_t> out;
  for (std::uint32_t v = 0; v < active_.size(); ++v)
    if (active_[v]) out.push_back(v);
  return out;
}

std::vector<std::uint32_t> ActiveMesh::liveFaces() const {
  std::vector<std::uint32_t> out;
  for (std::uint32_t t = 0; t < live_.size(); ++t)
    if (live_[t]) out.push_back(t);
  return out;
}

std::vector<std::uint32_t> ActiveMesh::facesAround(std::uint32_t v) const {
  std::vector<std::uint32_t> out;
  for (std::uint32_t c = head_[v]; c != kNone; c = next_[c]) out.push_back(c / 3);
  return out;
}

bool ActiveMesh::isBelow(std::uint32_t v, std::uint32_t ancestor) const {
  return first_[ancestor] <= first_[v] && last_[v] <= last_[ancestor];
}

std::uint32_t ActiveMesh::activeAtOrAbove(std::uint32_t v) const {
  while (!active_[v]) {
    v = h_.parent[v];
    if (v == kNone) return kNone;
  }
  return v;
}

bool ActiveMesh::canSplit(std::uint32_t v) const {
  if (!active_[v] || h_.isLeaf(v)) return false;
  const std::uint32_t a = h_.kept(v), b = h_.removed(v);
  std::uint32_t expected = 0;
  for (const StoredFace& s : h_.neighbourhood(v)) {
    if (holds(s.corners, a) && holds(s.corners, b)) continue;  // gone in the collapse
    if (!live_[s.face]) return false;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t want = s.corners[i] == a || s.corners[i] == b ? v : s.corners[i];
      if (corner_[3 * s.face + i] != want) return false;
    }
    ++expected;
  }
  // Every stored face is there as it was; and no other face is around v.
  return cornersAt(v) == expected;
}

bool ActiveMesh::canCollapse(std::uint32_t v) const {
  if (h_.isLeaf(v) || active_[v]) return false;
  const std::uint32_t a = h_.kept(v), b = h_.removed(v);
  if (!active_[a] || !active_[b]) return false;
  std::uint32_t expected = 0;
  for (const StoredFace& s : h_.neighbourhood(v)) {
    if (!live_[s.face]) return false;
    for (int i = 0; i < 3; ++i) {
      if (corner_[3 * s.face + i] != s.corners[i]) return false;
      expected += s.corners[i] == a || s.corners[i] == b;
    }
  }
  return cornersAt(a) + cornersAt(b) == expected;
}

std::vector<std::uint32_t> ActiveMesh::coarserNeighbours(std::uint32_t v) const {
  std::vector<std::uint32_t> out;
  if (!active_[v] || h_.isLeaf(v)) return out;
  const std::uint32_t a = h_.kept(v), b = h_.removed(v);
  for (const StoredFace& s : h_.neighbourhood(v))
    for (std::uint32_t x : s.corners) {
      if (x == a || x == b || active_[x]) continue;
      const std::uint32_t y = activeAtOrAbove(x);
      if (y != kNone && y != v) out.push_back(y);
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void ActiveMesh::split(std::uint32_t v) {
  assert(canSplit(v));
  splitImpl(v);
}

void ActiveMesh::splitUnchecked(std::uint32_t v) {
  assert(active_[v] && !h_.isLeaf(v));
  splitImpl(v);
}

void ActiveMesh::splitImpl(std::uint32_t v) {
  touched_.clear();
  const std::uint32_t a = h_.kept(v), b = h_.removed(v);
  active_[v] = 0;
  active_[a] = active_[b] = 1;
  ++activeCount_;
  // The corners at v go to the child their leaf lies below.
  for (std::uint32_t c = head_[v]; c != kNone;) {
    const std::uint32_t nextCorner = next_[c];
    const std::uint32_t leaf = h_.faces[c / 3][c % 3];
    link(c, isBelow(leaf, a) ? a : b);
    touched_.push_back(c / 3);
    c = nextCorner;
  }
  head_[v] = kNone;
  // The faces the collapse degenerated come back, at their corners' active vertices (with the
  // test passed, those it stored; computed all the same, so that the front stays a consistent
  // cut whatever a store holds).
  for (const StoredFace& s : h_.neighbourhood(v)) {
    if (!holds(s.corners, a) || !holds(s.corners, b) || live_[s.face]) continue;
    std::array<std::uint32_t, 3> c{};
    for (int i = 0; i < 3; ++i) c[i] = activeAtOrAbove(h_.faces[s.face][i]);
    if (c[0] == kNone || c[1] == kNone || c[2] == kNone || c[0] == c[1] || c[1] == c[2] ||
        c[0] == c[2])
      continue;
    live_[s.face] = 1;
    ++liveCount_;
    for (int i = 0; i < 3; ++i) link(3 * s.face + i, c[i]);
    touched_.push_back(s.face);
  }
}

void ActiveMesh::collapse(std::uint32_t v) {
  assert(canCollapse(v));
  touched_.clear();
  const std::uint32_t a = h_.kept(v), b = h_.removed(v);
  // The faces holding both children die; the others move their corner to v.
  for (std::uint32_t child : {a, b}) {
    for (std::uint32_t c = head_[child]; c != kNone;) {
      const std::uint32_t nextCorner = next_[c];
      const std::uint32_t t = c / 3;
      const auto f = corners(t);
      if (holds(f, a) && holds(f, b)) {
        // A live face has one corner at a vertex: nextCorner is another face's, still linked.
        for (int i = 0; i < 3; ++i) unlink(3 * t + i);
        live_[t] = 0;
        --liveCount_;
        touched_.push_back(t);
      }
      c = nextCorner;
    }
  }
  for (std::uint32_t child : {a, b}) {
    for (std::uint32_t c = head_[child]; c != kNone;) {
      const std::uint32_t nextCorner = next_[c];
      link(c, v);
      touched_.push_back(c / 3);
      c = nextCorner;
    }
    head_[child] = kNone;
  }
  active_[a] = active_[b] = 0;
  active_[v] = 1;
  --activeCount_;
}

Mesh currentMesh(const ActiveMesh& mesh) {
  const VertexHierarchy& h = mesh.hierarchy();
  Mesh out;
  out.positions = h.leafPosition;
  for (std::uint32_t t : mesh.liveFaces())
    for (std::uint32_t v : mesh.corners(t)) out.indices.push_back(h.leafOf[v]);
  return out;
}

}  // namespace hlod::vdr
