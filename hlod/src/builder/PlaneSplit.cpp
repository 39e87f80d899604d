#include "hlod/builder/PlaneSplit.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace hlod {

namespace {

// Builds one half: copies used input vertices once, and creates each cut vertex once per edge.
class HalfBuilder {
 public:
  HalfBuilder(const Mesh& in, Mesh& out) : in_(in), out_(out) {
    out_.name = in.name;
    out_.baseColor = in.baseColor;
    out_.texture = in.texture;
    out_.oneSided = in.oneSided;
  }

  std::uint32_t original(std::uint32_t v) {
    auto [it, fresh] = originals_.try_emplace(v, 0u);
    if (fresh) {
      it->second = static_cast<std::uint32_t>(out_.positions.size());
      out_.positions.push_back(in_.positions[v]);
      if (hasNormals()) out_.normals.push_back(in_.normals[v]);
      if (hasTexCoords()) out_.texCoords.push_back(in_.texCoords[v]);
    }
    return it->second;
  }

  // The vertex where edge (a, b) meets the plane. Computed from the edge in a canonical order
  // (lower index first), so the same edge of two triangles, in either half, gives the same bits.
  std::uint32_t cut(std::uint32_t a, std::uint32_t b, int axis, double value) {
    if (a > b) std::swap(a, b);
    const std::uint64_t key = (std::uint64_t(a) << 32) | b;
    auto [it, fresh] = cuts_.try_emplace(key, 0u);
    if (!fresh) return it->second;
    const glm::dvec3& pa = in_.positions[a];
    const glm::dvec3& pb = in_.positions[b];
    const double da = pa[axis] - value;
    const double db = pb[axis] - value;
    // da and db have opposite signs here, so the denominator is never zero.
    const double t = std::clamp(da / (da - db), 0.0, 1.0);
    glm::dvec3 p = pa + (pb - pa) * t;
    p[axis] = value;  // exactly on the plane: both halves and both sides agree
    it->second = static_cast<std::uint32_t>(out_.positions.size());
    out_.positions.push_back(p);
    if (hasNormals()) {
      // Opposite normals can cancel; fall back to one endpoint's normal rather than NaN.
      out_.normals.push_back(
          normalizedOr(glm::mix(in_.normals[a], in_.normals[b], float(t)), in_.normals[a]));
    }
    if (hasTexCoords())
      out_.texCoords.push_back(glm::mix(in_.texCoords[a], in_.texCoords[b], float(t)));
    return it->second;
  }

  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    out_.indices.insert(out_.indices.end(), {a, b, c});
  }

 private:
  bool hasNormals() const { return in_.normals.size() == in_.positions.size(); }
  bool hasTexCoords() const { return in_.texCoords.size() == in_.positions.size(); }

  const Mesh& in_;
  Mesh& out_;
  std::unordered_map<std::uint32_t, std::uint32_t> originals_;
  std::unordered_map<std::uint64_t, std::uint32_t> cuts_;
};

int sideOf(double d) {
  return d < 0.0 ? -1 : (d > 0.0 ? 1 : 0);
}

}  // namespace

PlaneSplitResult splitByPlane(const Mesh& mesh, int axis, double value) {
  PlaneSplitResult r;
  HalfBuilder below(mesh, r.below), above(mesh, r.above);
  const std::size_t nv = mesh.positions.size();
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    std::uint32_t v[3] = {mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
    if (v[0] >= nv || v[1] >= nv || v[2] >= nv) continue;  // invalid input index: nothing to cut
    int s[3];
    for (int k = 0; k < 3; ++k) s[k] = sideOf(mesh.positions[v[k]][axis] - value);
    const bool anyBelow = s[0] < 0 || s[1] < 0 || s[2] < 0;
    const bool anyAbove = s[0] > 0 || s[1] > 0 || s[2] > 0;
    if (!anyAbove) {
      below.triangle(below.original(v[0]), below.original(v[1]), below.original(v[2]));
      continue;
    }
    if (!anyBelow) {
      above.triangle(above.original(v[0]), above.original(v[1]), above.original(v[2]));
      continue;
    }
    // Rotate (keeping the winding) so that v[0] is the vertex alone on its side, or on the plane.
    auto rotate = [&] {
      std::rotate(v, v + 1, v + 3);
      std::rotate(s, s + 1, s + 3);
    };
    const int onPlane = (s[0] == 0) + (s[1] == 0) + (s[2] == 0);
    if (onPlane == 1) {
      while (s[0] != 0) rotate();
      // v1 and v2 lie on opposite sides: one new vertex, two triangles.
      HalfBuilder& h1 = s[1] < 0 ? below : above;
      HalfBuilder& h2 = s[2] < 0 ? below : above;
      const std::uint32_t c1 = h1.cut(v[1], v[2], axis, value);
      const std::uint32_t c2 = h2.cut(v[1], v[2], axis, value);
      h1.triangle(h1.original(v[0]), h1.original(v[1]), c1);
      h2.triangle(h2.original(v[0]), c2, h2.original(v[2]));
      continue;
    }
    while (s[0] == s[1] || s[0] == s[2]) rotate();
    // v0 alone on its side: a triangle there, a quad (two triangles) on the other side.
    HalfBuilder& lone = s[0] < 0 ? below : above;
    HalfBuilder& pair = s[0] < 0 ? above : below;
    const std::uint32_t a01 = lone.cut(v[0], v[1], axis, value);
    const std::uint32_t a02 = lone.cut(v[0], v[2], axis, value);
    lone.triangle(lone.original(v[0]), a01, a02);
    const std::uint32_t b01 = pair.cut(v[0], v[1], axis, value);
    const std::uint32_t b02 = pair.cut(v[0], v[2], axis, value);
    const std::uint32_t p1 = pair.original(v[1]), p2 = pair.original(v[2]);
    pair.triangle(b01, p1, p2);
    pair.triangle(b01, p2, b02);
  }
  return r;
}

int longestAxis(const Aabb& box) {
  const glm::dvec3 s = box.size();
  if (s.y > s.x && s.y >= s.z) return 1;
  if (s.z > s.x && s.z > s.y) return 2;
  return 0;
}

SlabSplit splitIntoSlabs(const Mesh& mesh, const Aabb& box, int levelFactor) {
  SlabSplit out;
  out.axis = longestAxis(box);
  const double lo = box.min[out.axis], hi = box.max[out.axis];
  Mesh rest = mesh;
  for (int k = 1; k < levelFactor; ++k) {
    const double plane = lo + (hi - lo) * double(k) / double(levelFactor);
    out.planes.push_back(plane);
    PlaneSplitResult r = splitByPlane(rest, out.axis, plane);
    out.pieces.push_back(std::move(r.below));
    rest = std::move(r.above);
  }
  out.pieces.push_back(std::move(rest));
  return out;
}

double surfaceArea(const Mesh& mesh) {
  double area = 0.0;
  const std::size_t nv = mesh.positions.size();
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const auto a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
    if (a >= nv || b >= nv || c >= nv) continue;
    area += 0.5 * glm::length(glm::cross(mesh.positions[b] - mesh.positions[a],
                                         mesh.positions[c] - mesh.positions[a]));
  }
  return area;
}

}  // namespace hlod
