// Cell nodes above the blocks (builder/CellNodes.h).
#include "builder/CellNodes.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <unordered_map>

#include "builder/BlockBorders.h"
#include "builder/Preprocess.h"
#include "builder/SimplifierImpl.h"
#include "hlod/parry/Splats.h"

namespace hlod {

namespace {

bool hasTexture(const LocalMesh& m) {
  return m.texture && !m.texture->empty() &&
         m.texture->pixels.size() == std::size_t(m.texture->width) * m.texture->height * 4 &&
         m.texCoords.size() == m.positions.size();
}

std::uint8_t toByte(float v) {
  return std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

std::vector<CutPlane> outerSides(std::span<const Aabb> boxes,
                                 std::span<const std::vector<CutPlane>> sides, UpAxis up) {
  assert(boxes.size() == sides.size());
  const int vertical = int(up);
  std::vector<CutPlane> out;
  for (std::size_t k = 0; k < boxes.size(); ++k)
    for (const CutPlane& c : sides[k]) {
      const int along = 3 - c.axis - vertical;  // the horizontal axis the plane runs along
      const bool below = boxes[k].centre()[c.axis] < c.value;
      bool inner = false;
      for (std::size_t j = 0; j < boxes.size() && !inner; ++j) {
        if (j == k || (boxes[j].centre()[c.axis] < c.value) == below) continue;
        const double overlap = std::min(boxes[k].max[along], boxes[j].max[along]) -
                               std::max(boxes[k].min[along], boxes[j].min[along]);
        inner =
            overlap > 0.0 && std::any_of(sides[j].begin(), sides[j].end(), [&](const CutPlane& o) {
              return o.axis == c.axis && o.value == c.value;
            });
      }
      if (!inner && std::none_of(out.begin(), out.end(), [&](const CutPlane& o) {
            return o.axis == c.axis && o.value == c.value;
          }))
        out.push_back(c);
    }
  return out;
}

ColouredMesh mergeCellChildren(std::span<const LocalMesh> children) {
  ColouredMesh out;
  Mesh& m = out.mesh;
  m.oneSided = !children.empty();
  m.baseColor = glm::vec4(1.0f);
  std::unordered_map<std::uint32_t, std::uint32_t> colourIndex;  // RGBA8 -> colours
  for (const LocalMesh& c : children) {
    m.oneSided = m.oneSided && c.oneSided;
    const bool textured = hasTexture(c);
    const Image* image = textured ? c.texture.get() : nullptr;
    // A texel of a texture that repeats (coordinates outside [0,1]) wraps around.
    const auto texel = [&](glm::vec2 t) {
      const float x = t.x - std::floor(t.x), y = t.y - std::floor(t.y);
      const int px = std::min(image->width - 1, int(x * float(image->width)));
      const int py = std::min(image->height - 1, int(y * float(image->height)));
      const std::uint8_t* p = &image->pixels[(std::size_t(py) * image->width + px) * 4];
      return glm::vec4(p[0], p[1], p[2], p[3]) / 255.0f;
    };
    // Each triangle's mean colour over its texture footprint (15 barycentric points),
    // spread to its vertices weighted by its area.
    std::vector<glm::dvec4> sum(c.positions.size(), glm::dvec4(0.0));
    std::vector<double> weight(c.positions.size(), 0.0);
    for (std::size_t i = 0; i + 2 < c.indices.size(); i += 3) {
      const std::uint32_t v[3] = {c.indices[i], c.indices[i + 1], c.indices[i + 2]};
      glm::vec4 colour(1.0f);
      if (textured) {
        constexpr int kSteps = 4;
        glm::vec4 acc(0.0f);
        int n = 0;
        for (int a = 0; a <= kSteps; ++a)
          for (int b = 0; a + b <= kSteps; ++b, ++n) {
            const float u = float(a) / kSteps, w = float(b) / kSteps;
            acc += texel(c.texCoords[v[0]] * (1.0f - u - w) + c.texCoords[v[1]] * u +
                         c.texCoords[v[2]] * w);
          }
        colour = acc / float(n);
      }
      const double area =
          0.5 * glm::length(glm::cross(glm::dvec3(c.positions[v[1]] - c.positions[v[0]]),
                                       glm::dvec3(c.positions[v[2]] - c.positions[v[0]])));
      const double w = std::max(area, 1e-12);
      for (std::uint32_t k : v) {
        sum[k] += w * glm::dvec4(colour);
        weight[k] += w;
      }
    }
    const auto base = std::uint32_t(m.positions.size());
    for (std::size_t v = 0; v < c.positions.size(); ++v) {
      m.positions.push_back(c.centre + glm::dvec3(c.positions[v]));
      m.normals.push_back(v < c.normals.size() ? c.normals[v] : glm::vec3(0.0f, 0.0f, 1.0f));
      const glm::vec4 colour =
          (weight[v] > 0.0 ? glm::vec4(sum[v] / weight[v]) : glm::vec4(1.0f)) * c.baseColor;
      std::uint32_t key = 0;
      for (int ch = 0; ch < 4; ++ch) key = key << 8 | toByte(colour[ch]);
      auto [it, fresh] = colourIndex.try_emplace(key, std::uint32_t(out.colours.size()));
      if (fresh) out.colours.push_back(colour);
      m.texCoords.emplace_back(float(it->second), 0.0f);
    }
    for (std::uint32_t i : c.indices) m.indices.push_back(base + i);
  }
  return out;
}

Mesh flatColoured(const Mesh& simplified, std::span<const glm::vec4> colours) {
  Mesh out;
  out.oneSided = simplified.oneSided;
  out.baseColor = glm::vec4(1.0f);
  const auto colourOf = [&](std::uint32_t v) {
    const auto i = std::size_t(simplified.texCoords[v].x);
    assert(i < colours.size());
    return colours[i];
  };
  // Per triangle its colour's texel; texels in the order first used.
  std::unordered_map<std::uint32_t, std::uint32_t> texelOf;
  std::vector<std::uint32_t> triangleTexel, texelColour;
  for (std::size_t i = 0; i + 2 < simplified.indices.size(); i += 3) {
    const glm::vec4 c = (colourOf(simplified.indices[i]) + colourOf(simplified.indices[i + 1]) +
                         colourOf(simplified.indices[i + 2])) /
                        3.0f;
    std::uint32_t key = 0;
    for (int ch = 0; ch < 4; ++ch) key = key << 8 | toByte(c[ch]);
    auto [it, fresh] = texelOf.try_emplace(key, std::uint32_t(texelColour.size()));
    if (fresh) texelColour.push_back(key);
    triangleTexel.push_back(it->second);
  }
  const int side = std::max(1, int(std::ceil(std::sqrt(double(texelColour.size())))));
  auto image = std::make_shared<Image>();
  image->width = image->height = side;
  image->pixels.assign(std::size_t(side) * side * 4, 255);
  for (std::size_t t = 0; t < texelColour.size(); ++t)
    for (int ch = 0; ch < 4; ++ch)
      image->pixels[4 * t + ch] = std::uint8_t(texelColour[t] >> (24 - 8 * ch));
  // Three vertices per triangle, with its face's normal: after a simplification that joined
  // separate parts, the input vertices' normals no longer match their triangles, and shading
  // them smoothly paints swirls across flat walls.
  for (std::size_t i = 0; i + 2 < simplified.indices.size(); i += 3) {
    const std::uint32_t* tri = &simplified.indices[i];
    const std::uint32_t texel = triangleTexel[i / 3];
    const glm::dvec3 n = glm::cross(simplified.positions[tri[1]] - simplified.positions[tri[0]],
                                    simplified.positions[tri[2]] - simplified.positions[tri[0]]);
    for (int k = 0; k < 3; ++k) {
      assert(tri[k] < simplified.positions.size());
      const glm::vec3 fallback =
          tri[k] < simplified.normals.size() ? simplified.normals[tri[k]] : glm::vec3(0, 0, 1);
      out.indices.push_back(std::uint32_t(out.positions.size()));
      out.positions.push_back(simplified.positions[tri[k]]);
      out.normals.push_back(normalizedOr(glm::vec3(n), fallback));
      out.texCoords.push_back((glm::vec2(float(texel % side), float(texel / side)) + 0.5f) /
                              float(side));
    }
  }
  out.texture = std::move(image);
  return out;
}

namespace {

// A cell node under construction: the nodes below it and the blocks they hold.
struct Cell {
  std::vector<std::uint32_t> children;  // node indices, before the final ordering
  std::vector<std::uint32_t> blocks;    // NodeInfo::block of every block below
};

// Relative to a cell's diagonal: far above a float's rounding of a vertex around its node's
// centre (2^-24 of the node's size), far below any detail.
constexpr double kSnap = 1e-6;

// Moves positions within `tolerance` of a plane onto it, and of a point onto the point.
void snapOnto(Mesh& mesh, std::span<const CutPlane> planes, std::span<const glm::dvec3> points,
              double tolerance) {
  // Points in a grid of cells `tolerance` wide: a point within it lies in one of 27 cells.
  const auto cellOf = [&](const glm::dvec3& p) { return glm::i64vec3(glm::floor(p / tolerance)); };
  struct CellHash {
    std::size_t operator()(const glm::i64vec3& c) const {
      return std::size_t(c.x * 73856093 ^ c.y * 19349663 ^ c.z * 83492791);
    }
  };
  std::unordered_map<glm::i64vec3, std::vector<glm::dvec3>, CellHash> grid;
  if (tolerance > 0.0)
    for (const glm::dvec3& p : points) grid[cellOf(p)].push_back(p);
  for (glm::dvec3& p : mesh.positions) {
    for (const CutPlane& c : planes)
      if (std::abs(p[c.axis] - c.value) <= tolerance) p[c.axis] = c.value;
    if (grid.empty()) continue;
    const glm::i64vec3 at = cellOf(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (auto it = grid.find(at + glm::i64vec3(dx, dy, dz)); it != grid.end())
            for (const glm::dvec3& q : it->second)
              if (glm::length(q - p) <= tolerance) p = q;
  }
}

}  // namespace

void stitchBorders(Mesh& mesh, std::span<const CutPlane> planes, UpAxis up, double tolerance) {
  // Position ids, and the open-border edges by position: an edge one triangle uses.
  std::unordered_map<glm::dvec3, std::uint32_t, PositionHash> id;
  std::vector<std::uint32_t> pid(mesh.positions.size());
  std::vector<std::uint32_t> vertexAt;  // a vertex per position id
  for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
    auto [it, fresh] =
        id.try_emplace(mesh.positions[v] + glm::dvec3(0.0), std::uint32_t(id.size()));
    if (fresh) vertexAt.push_back(v);
    pid[v] = it->second;
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;  // (position pair, corner)
  for (std::uint32_t c = 0; c < mesh.indices.size(); ++c) {
    const std::uint32_t a = pid[mesh.indices[c]], b = pid[mesh.indices[c - c % 3 + (c + 1) % 3]];
    edges.emplace_back(std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), c);
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::uint32_t> borderCorners;  // corner c: the edge from c to the next corner
  std::vector<std::uint8_t> onBorder(id.size(), 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t end = i + 1;
    while (end < edges.size() && edges[end].first == edges[i].first) ++end;
    if (end - i == 1) {
      borderCorners.push_back(edges[i].second);
      onBorder[edges[i].first >> 32] = onBorder[edges[i].first & 0xffffffffu] = 1;
    }
    i = end;
  }
  // Per border edge on a plane, the border positions strictly inside it.
  struct Split {
    double t;
    std::uint32_t position;
  };
  std::unordered_map<std::uint32_t, std::vector<Split>> splits;  // by corner
  for (const CutPlane& plane : planes) {
    const int along = 3 - plane.axis - int(up);  // the horizontal axis the plane runs along
    std::vector<std::uint32_t> points;
    for (std::uint32_t p = 0; p < id.size(); ++p)
      if (onBorder[p] && plane.contains(mesh.positions[vertexAt[p]])) points.push_back(p);
    const auto at = [&](std::uint32_t p) { return mesh.positions[vertexAt[p]][along]; };
    std::sort(points.begin(), points.end(),
              [&](std::uint32_t a, std::uint32_t b) { return at(a) < at(b); });
    for (std::uint32_t c : borderCorners) {
      const glm::dvec3 a = mesh.positions[mesh.indices[c]];
      const glm::dvec3 b = mesh.positions[mesh.indices[c - c % 3 + (c + 1) % 3]];
      if (!plane.contains(a) || !plane.contains(b)) continue;
      const double lo = std::min(a[along], b[along]), hi = std::max(a[along], b[along]);
      const glm::dvec3 d = b - a;
      const double len2 = glm::dot(d, d);
      if (!(len2 > 0.0)) continue;
      auto it = std::lower_bound(points.begin(), points.end(), lo,
                                 [&](std::uint32_t p, double v) { return at(p) < v; });
      for (; it != points.end() && at(*it) <= hi; ++it) {
        const glm::dvec3 q = mesh.positions[vertexAt[*it]];
        const double t = glm::dot(q - a, d) / len2;
        if (t <= 1e-9 || t >= 1.0 - 1e-9 || glm::length(a + t * d - q) > tolerance) continue;
        splits[c].push_back({t, *it});
      }
    }
  }
  // Each split triangle becomes a fan from the corner opposite its border edge.
  std::vector<std::uint32_t> indices;
  indices.reserve(mesh.indices.size());
  for (std::uint32_t t = 0; t * 3 < mesh.indices.size(); ++t) {
    std::uint32_t split = 3;
    for (std::uint32_t k = 0; k < 3; ++k)
      if (splits.count(3 * t + k)) split = split == 3 ? k : 4;  // 4: more than one edge
    const std::uint32_t* tri = &mesh.indices[3 * t];
    if (split >= 3) {
      indices.insert(indices.end(), tri, tri + 3);
      continue;
    }
    std::vector<Split>& points = splits[3 * t + split];
    std::sort(points.begin(), points.end(),
              [](const Split& x, const Split& y) { return x.t < y.t; });
    const std::uint32_t a = tri[split], b = tri[(split + 1) % 3], c = tri[(split + 2) % 3];
    std::uint32_t prev = a;
    for (const Split& p : points) {
      // The new vertex: the other side's position, with the attributes of the nearer end.
      const std::uint32_t from = p.t < 0.5 ? a : b;
      const auto v = std::uint32_t(mesh.positions.size());
      mesh.positions.push_back(mesh.positions[vertexAt[p.position]]);
      if (!mesh.normals.empty()) mesh.normals.push_back(mesh.normals[from]);
      if (!mesh.texCoords.empty()) mesh.texCoords.push_back(mesh.texCoords[from]);
      indices.insert(indices.end(), {prev, v, c});
      prev = v;
    }
    indices.insert(indices.end(), {prev, b, c});
  }
  mesh.indices = std::move(indices);
}

void addUnderlay(Mesh& mesh, const Mesh& input, std::vector<glm::vec4>& colours, const Aabb& box,
                 UpAxis up) {
  const int u = int(up), e0 = (u + 1) % 3, e1 = (u + 2) % 3;  // e0 x e1 = +up
  const double size = std::max(box.max[e0] - box.min[e0], box.max[e1] - box.min[e1]);
  // The colour of the lowest ground: the input's triangles facing up within a metre of the
  // bottom, weighted by area.
  glm::dvec4 sum(0.0);
  double weight = 0.0;
  for (std::size_t i = 0; i + 2 < input.indices.size(); i += 3) {
    const glm::dvec3 a = input.positions[input.indices[i]],
                     b = input.positions[input.indices[i + 1]],
                     c = input.positions[input.indices[i + 2]];
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double area = 0.5 * glm::length(n);
    if (!(area > 0.0) || n[u] < 0.9 * 2.0 * area || std::min({a[u], b[u], c[u]}) > box.min[u] + 1.0)
      continue;
    for (int k = 0; k < 3; ++k)
      sum += area * glm::dvec4(colours[std::size_t(input.texCoords[input.indices[i + k]].x)]);
    weight += 3.0 * area;
  }
  if (!(weight > 0.0)) return;
  const auto colour = float(colours.size());
  colours.push_back(glm::vec4(sum / weight));
  const double depth = box.min[u] - kUnderlayDepth * size;
  const auto base = std::uint32_t(mesh.positions.size());
  for (const auto& [x, y] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
    glm::dvec3 p(0.0);
    p[u] = depth;
    p[e0] = x ? box.max[e0] : box.min[e0];
    p[e1] = y ? box.max[e1] : box.min[e1];
    mesh.positions.push_back(p);
    glm::vec3 n(0.0f);
    n[u] = 1.0f;
    mesh.normals.push_back(n);
    mesh.texCoords.emplace_back(colour, 0.0f);
  }
  mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

std::vector<BuildingBox> takeBuildings(Mesh& mesh, std::span<const glm::vec4> colours, UpAxis up,
                                       std::vector<std::uint32_t>* others) {
  const int u = int(up), e0 = (u + 1) % 3, e1 = (u + 2) % 3;
  // Components by position: a union-find over the triangles' corners.
  std::unordered_map<glm::dvec3, std::uint32_t, PositionHash> id;
  std::vector<std::uint32_t> pid(mesh.positions.size());
  for (std::size_t v = 0; v < pid.size(); ++v)
    pid[v] =
        id.try_emplace(mesh.positions[v] + glm::dvec3(0.0), std::uint32_t(id.size())).first->second;
  std::vector<std::uint32_t> parent(id.size());
  for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  const auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
    for (int k = 1; k < 3; ++k) parent[find(pid[mesh.indices[i]])] = find(pid[mesh.indices[i + k]]);
  struct Part {
    Aabb box;
    std::vector<std::uint32_t> triangles;
  };
  std::unordered_map<std::uint32_t, Part> parts;
  for (std::uint32_t t = 0; t * 3 < mesh.indices.size(); ++t) {
    Part& part = parts[find(pid[mesh.indices[3 * t]])];
    part.triangles.push_back(t);
    for (int k = 0; k < 3; ++k) part.box.extend(mesh.positions[mesh.indices[3 * t + k]]);
  }
  std::vector<BuildingBox> out;
  std::vector<std::uint8_t> taken(mesh.triangleCount(), 0);
  for (auto& [root, part] : parts) {
    const glm::dvec3 size = part.box.size();
    if (size[u] * kGroundAspect < std::max(size[e0], size[e1])) continue;  // ground
    // The footprint's direction: the walls' edges across `up` weighted by length (a wall's
    // diagonals too lie along it, a roof's would not), their angle taken four times over, so
    // that a rectangle's two edge directions agree.
    glm::dvec2 dir(0.0);
    glm::dvec4 topSum(0.0), sideSum(0.0);
    double topArea = 0.0, sideArea = 0.0, roofFootprint = 0.0, roofVolume = 0.0;
    for (std::uint32_t t : part.triangles) {
      const std::uint32_t* tri = &mesh.indices[3 * t];
      const glm::dvec3 n = glm::cross(mesh.positions[tri[1]] - mesh.positions[tri[0]],
                                      mesh.positions[tri[2]] - mesh.positions[tri[0]]);
      const double area = 0.5 * glm::length(n);
      glm::dvec4 colour(0.0);
      for (int k = 0; k < 3; ++k)
        colour += glm::dvec4(colours[std::size_t(mesh.texCoords[tri[k]].x)]) / 3.0;
      if (n[u] > 0.7 * 2.0 * area) {
        topSum += area * colour;
        topArea += area;
        roofFootprint += 0.5 * n[u];
        roofVolume +=
            0.5 * n[u] *
            ((mesh.positions[tri[0]][u] + mesh.positions[tri[1]][u] + mesh.positions[tri[2]][u]) /
                 3.0 -
             part.box.min[u]);
        continue;
      }
      sideSum += area * colour;
      sideArea += area;
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 d = mesh.positions[tri[(k + 1) % 3]] - mesh.positions[tri[k]];
        const double len = std::hypot(d[e0], d[e1]);
        if (len > 0.0) {
          const double angle = 4.0 * std::atan2(d[e1], d[e0]);
          dir += len * glm::dvec2(std::cos(angle), std::sin(angle));
        }
      }
    }
    BuildingBox b;
    const double angle = glm::length(dir) > 0.0 ? std::atan2(dir.y, dir.x) / 4.0 : 0.0;
    b.axis = glm::dvec2(std::cos(angle), std::sin(angle));
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (std::uint32_t t : part.triangles)
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3& p = mesh.positions[mesh.indices[3 * t + k]];
        const glm::dvec2 q(p[e0] * b.axis.x + p[e1] * b.axis.y,
                           -p[e0] * b.axis.y + p[e1] * b.axis.x);
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
      }
    // A wall without thickness, or buildings joined around a courtyard (roofs covering less than
    // kBoxFill of the box), stay as they are: a box would be a slab over the courtyard.
    if (!(hi.x > lo.x && hi.y > lo.y) || roofFootprint < kBoxFill * (hi.x - lo.x) * (hi.y - lo.y)) {
      if (others)
        for (std::uint32_t t : part.triangles) taken[t] = 2;
      continue;
    }
    b.lo = lo;
    b.hi = hi;
    // As high as the volume under its roofs over their footprint: a tower on a podium becomes
    // a block of their mean height, not a slab as high as the tower.
    b.bottom = part.box.min[u];
    b.top = b.bottom + roofVolume / roofFootprint;
    const glm::vec4 side = sideArea > 0.0 ? glm::vec4(sideSum / sideArea) : glm::vec4(1.0f);
    b.side = side;
    b.roof = topArea > 0.0 ? glm::vec4(topSum / topArea) : side;
    for (std::uint32_t t : part.triangles) taken[t] = 1;
    out.push_back(b);
  }
  std::vector<std::uint32_t> kept;
  for (std::uint32_t t = 0; t * 3 < mesh.indices.size(); ++t) {
    const std::uint32_t* tri = &mesh.indices[3 * t];
    if (!taken[t]) kept.insert(kept.end(), tri, tri + 3);
    if (taken[t] == 2) others->insert(others->end(), tri, tri + 3);
  }
  mesh.indices = std::move(kept);
  // The tallest and widest first: what a far view keeps longest.
  std::sort(out.begin(), out.end(), [](const BuildingBox& a, const BuildingBox& b) {
    return a.silhouette() > b.silhouette();
  });
  return out;
}

void appendBox(Mesh& mesh, const BuildingBox& b, std::vector<glm::vec4>& colours, UpAxis up) {
  const int u = int(up), e0 = (u + 1) % 3, e1 = (u + 2) % 3;
  const auto at = [&](double x, double y, double h) {
    glm::dvec3 p(0.0);
    p[e0] = x * b.axis.x - y * b.axis.y;
    p[e1] = x * b.axis.y + y * b.axis.x;
    p[u] = h;
    return p;
  };
  const auto side = float(colours.size()), roof = side + 1.0f;
  colours.push_back(b.side);
  colours.push_back(b.roof);
  // Footprint corners counter-clockwise seen from +up (e0 x e1 = up).
  const glm::dvec2 c[4] = {{b.lo.x, b.lo.y}, {b.hi.x, b.lo.y}, {b.hi.x, b.hi.y}, {b.lo.x, b.hi.y}};
  const auto quad = [&](const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                        const glm::dvec3& p3, float colour) {
    const auto base = std::uint32_t(mesh.positions.size());
    glm::vec3 upward(0.0f);
    upward[u] = 1.0f;
    const glm::vec3 n = normalizedOr(glm::vec3(glm::cross(p1 - p0, p2 - p0)), upward);
    for (const glm::dvec3& p : {p0, p1, p2, p3}) {
      mesh.positions.push_back(p);
      mesh.normals.push_back(n);
      mesh.texCoords.emplace_back(colour, 0.0f);
    }
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  };
  quad(at(c[0].x, c[0].y, b.top), at(c[1].x, c[1].y, b.top), at(c[2].x, c[2].y, b.top),
       at(c[3].x, c[3].y, b.top), roof);
  for (int k = 0; k < 4; ++k) {
    const glm::dvec2 a = c[k], d = c[(k + 1) % 4];
    quad(at(a.x, a.y, b.bottom), at(d.x, d.y, b.bottom), at(d.x, d.y, b.top), at(a.x, a.y, b.top),
         side);
  }
}

void dropRepeatedTriangles(Mesh& mesh) {
  std::vector<std::array<std::uint32_t, 4>> keys;  // rotated so the smallest comes first, then t
  for (std::uint32_t t = 0; t * 3 < mesh.indices.size(); ++t) {
    const std::uint32_t* v = &mesh.indices[3 * t];
    const int k = v[0] <= v[1] && v[0] <= v[2] ? 0 : v[1] <= v[2] ? 1 : 2;
    keys.push_back({v[k], v[(k + 1) % 3], v[(k + 2) % 3], t});
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint8_t> keep(keys.size(), 0);
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (i == 0 || !std::equal(keys[i].begin(), keys[i].begin() + 3, keys[i - 1].begin()))
      keep[keys[i][3]] = 1;
  std::vector<std::uint32_t> indices;
  for (std::uint32_t t = 0; t < keep.size(); ++t)
    if (keep[t]) indices.insert(indices.end(), &mesh.indices[3 * t], &mesh.indices[3 * t] + 3);
  mesh.indices = std::move(indices);
}

namespace {

Result<NodeInfo> buildCell(
    CellPass& pass, const Cell& cell, const std::vector<Aabb>& blockBoxes,
    const std::unordered_map<glm::dvec3, std::vector<std::uint32_t>, PositionHash>& seamOwners) {
  const Skeleton& s = pass.skeleton;
  std::vector<LocalMesh> meshes;
  NodeInfo info;
  info.block = kCellBlock;
  std::uint64_t childTriangles = 0;
  for (std::uint32_t n : cell.children) {
    auto mesh = pass.writer.readBack(s.nodes[n]);
    if (!mesh) return mesh.error();
    meshes.push_back(std::move(*mesh));
    info.bounds.extend(s.nodes[n].bounds);
    info.geometricError = std::max(info.geometricError, s.nodes[n].geometricError);
    childTriangles += s.nodes[n].numTri;
  }
  info.centre = info.bounds.centre();
  const ColouredMesh coloured = mergeCellChildren(meshes);
  Mesh merged = weldVertices(coloured.mesh);
  dropRepeatedTriangles(merged);
  meshes.clear();
  // Locks: seam positions shared with a block outside the cell, and the outline on every side
  // of every block (a side inside the cell too: there the ground ends at the street's middle,
  // and without its outline a street between two blocks simplifies into a gap).
  std::vector<glm::dvec3> seam;
  std::vector<CutPlane> sides;
  std::vector<Aabb> boxes;
  std::vector<std::vector<CutPlane>> blockSides;
  for (std::uint32_t b : cell.blocks) {
    boxes.push_back(blockBoxes[b]);
    blockSides.push_back(pass.sides[b]);
    for (const CutPlane& c : pass.sides[b])
      if (std::none_of(sides.begin(), sides.end(),
                       [&](const CutPlane& o) { return o.axis == c.axis && o.value == c.value; }))
        sides.push_back(c);
    for (const glm::dvec3& p : pass.seams[b]) {
      const auto& owners = seamOwners.at(p + glm::dvec3(0.0));
      if (std::any_of(owners.begin(), owners.end(), [&](std::uint32_t o) {
            return !std::binary_search(cell.blocks.begin(), cell.blocks.end(), o);
          }))
        seam.push_back(p);
    }
  }
  // The payloads' positions are floats around their nodes' centres: back in doubles they lie
  // within a few ulps of the planes and seam positions the blocks were built with. Put them back
  // on them, so that the exact tests of markOutline and blockBorders find them.
  const double tolerance = kSnap * glm::length(info.bounds.size());
  snapOnto(merged, sides, seam, tolerance);
  const UpAxis up = pass.options.up.value_or(s.up);
  const std::vector<CutPlane> outer = outerSides(boxes, blockSides, up);
  stitchBorders(merged, sides, up, tolerance);
  BlockBorders borders = blockBorders(merged, seam);
  std::vector<std::uint32_t> origin(merged.positions.size());
  for (std::uint32_t v = 0; v < origin.size(); ++v) origin[v] = v;
  std::vector<std::uint8_t> locked = lockBorder(merged, origin, borders);
  markOutline(merged, origin, borders, outer, locked);
  const std::size_t target = std::max<std::size_t>(
      pass.options.desiredTri, childTriangles / std::size_t(pass.options.levelFactor));
  // A city's buildings become boxes (LoD1 block models), the tallest and widest first within
  // half the target; the rest of the target is the ground's.
  std::vector<BuildingBox> buildings;
  Mesh complexes;  // buildings that are no box: simplified apart from the ground
  if (!sides.empty()) {
    buildings = takeBuildings(merged, coloured.colours, up, &complexes.indices);
    complexes.positions = merged.positions;
    complexes.normals = merged.normals;
    complexes.texCoords = merged.texCoords;
    complexes.oneSided = merged.oneSided;
  }
  const std::size_t keptBoxes = std::min(buildings.size(), target / 2 / kBoxTriangles);
  double dropped = 0.0;
  for (std::size_t k = keptBoxes; k < buildings.size(); ++k)
    dropped = std::max(dropped, buildings[k].top - buildings[k].bottom);
  // The rest of the target, shared by the ground and the other buildings as their triangles.
  const std::size_t rest = std::max<std::size_t>(2, target - keptBoxes * kBoxTriangles);
  const std::size_t all = merged.triangleCount() + complexes.triangleCount();
  const auto simplifyShare = [&](const Mesh& part) {
    const std::size_t share =
        std::max<std::size_t>(1, std::size_t(double(rest) * double(part.triangleCount()) /
                                             double(std::max<std::size_t>(1, all))));
    const double factor = double(part.triangleCount()) / double(share);
    return pass.simplifier.simplifyUnion(
        part, share, locked, errorLimit(surfaceArea(part), part.triangleCount(), factor));
  };
  SimplifiedMesh simplified = simplifyShare(merged);
  if (complexes.triangleCount() > 0) {
    const SimplifiedMesh other = simplifyShare(complexes);
    simplified.geometricError = std::max(simplified.geometricError, other.geometricError);
    const auto base = std::uint32_t(simplified.mesh.positions.size());
    Mesh& m = simplified.mesh;
    m.positions.insert(m.positions.end(), other.mesh.positions.begin(), other.mesh.positions.end());
    m.normals.insert(m.normals.end(), other.mesh.normals.begin(), other.mesh.normals.end());
    m.texCoords.insert(m.texCoords.end(), other.mesh.texCoords.begin(), other.mesh.texCoords.end());
    for (std::uint32_t i : other.mesh.indices) m.indices.push_back(base + i);
  }
  info.geometricError += std::max(simplified.geometricError, dropped);
  // Without a progression (parry's would index the vertices flatColoured renumbers): a cell is
  // drawn whole.
  std::vector<glm::vec4> colours = coloured.colours;
  for (std::size_t k = 0; k < keptBoxes; ++k) appendBox(simplified.mesh, buildings[k], colours, up);
  if (!sides.empty()) addUnderlay(simplified.mesh, coloured.mesh, colours, info.bounds, up);
  simplified.mesh = flatColoured(simplified.mesh, colours);
  // The box holds what the node draws: its children's boxes, and its underlay below them.
  info.bounds.extend(simplified.mesh.bounds());
  describeNode(info, simplified.mesh, pass.options.cTex);
  LocalMesh local = localAround(simplified.mesh, info.centre);
  local.splats = makeSplats(local);
  info.splatCount = std::uint32_t(local.splats.size());
  if (auto w = pass.writer.appendPayload(local, info); !w) return w.error();
  return info;
}

}  // namespace

Result<std::uint32_t> addCellNodes(CellPass& pass) {
  Skeleton& s = pass.skeleton;
  const BlockQuadtree& q = s.quadtree;
  if (q.empty()) return 0u;
  std::vector<Aabb> blockBoxes(pass.sides.size());
  for (std::uint32_t r : s.roots) blockBoxes[s.nodes[r].block] = s.nodes[r].bounds;
  std::unordered_map<glm::dvec3, std::vector<std::uint32_t>, PositionHash> seamOwners;
  for (std::uint32_t b = 0; b < pass.seams.size(); ++b)
    for (const glm::dvec3& p : pass.seams[b]) seamOwners[p + glm::dvec3(0.0)].push_back(b);

  const auto firstCell = std::uint32_t(s.nodes.size());
  std::vector<Cell> cells;                                     // per cell node
  std::vector<std::uint32_t> nodeOf(q.cells.size(), kNoNode);  // what stands for a quadtree cell
  const auto blocksBelow = [&](std::uint32_t n) {
    return n >= firstCell ? cells[n - firstCell].blocks
                          : std::vector<std::uint32_t>{s.nodes[n].block};
  };
  // Children after their parents in q.cells: from the end, every cell after its children.
  for (std::size_t i = q.cells.size(); i-- > 0;) {
    if (pass.progress) pass.progress(q.cells.size() - 1 - i, q.cells.size());
    const QuadCell& c = q.cells[i];
    Cell cell;
    for (std::uint32_t k = c.firstBlock; k < c.firstBlock + c.blockCount; ++k)
      cell.children.push_back(q.blocks[k].root);
    for (std::uint32_t k = c.firstChild; k < c.firstChild + c.childCount; ++k)
      cell.children.push_back(nodeOf[k]);
    if (cell.children.size() == 1) {
      nodeOf[i] = cell.children.front();
      continue;
    }
    for (std::uint32_t n : cell.children) {
      const std::vector<std::uint32_t> below = blocksBelow(n);
      cell.blocks.insert(cell.blocks.end(), below.begin(), below.end());
    }
    std::sort(cell.blocks.begin(), cell.blocks.end());
    auto info = buildCell(pass, cell, blockBoxes, seamOwners);
    if (!info) return info.error();
    if (s.nodes.size() + 1 >= kNoNode) return makeError("too many nodes");
    nodeOf[i] = std::uint32_t(s.nodes.size());
    s.nodes.push_back(*info);
    cells.push_back(std::move(cell));
  }
  if (cells.empty()) return 0u;

  // Breadth-first from the top: parents before children, each node's children contiguous.
  const std::uint32_t top = nodeOf[0];
  assert(top >= firstCell);
  std::vector<std::uint32_t> order{top}, newIndex(s.nodes.size(), kNoNode);
  newIndex[top] = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::uint32_t n = order[i];
    const NodeInfo& info = s.nodes[n];
    const auto enqueue = [&](std::uint32_t child) {
      newIndex[child] = std::uint32_t(order.size());
      order.push_back(child);
    };
    if (n >= firstCell) {
      for (std::uint32_t c : cells[n - firstCell].children) enqueue(c);
    } else {
      for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c)
        enqueue(c);
    }
  }
  assert(order.size() == s.nodes.size());
  std::vector<NodeInfo> nodes(s.nodes.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    const std::uint32_t n = order[i];
    NodeInfo info = s.nodes[n];
    if (n >= firstCell) {
      const Cell& cell = cells[n - firstCell];
      info.firstChild = newIndex[cell.children.front()];
      info.childCount = std::uint32_t(cell.children.size());
      for (std::uint32_t c : cell.children) s.nodes[c].parent = n;
    } else if (info.childCount > 0) {
      info.firstChild = newIndex[info.firstChild];
    }
    nodes[i] = info;
  }
  // Parents last: a cell sets its children's parent above, which may come after the child.
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    const std::uint32_t parent = s.nodes[order[i]].parent;
    nodes[i].parent = parent == kNoNode ? kNoNode : newIndex[parent];
  }
  s.nodes = std::move(nodes);
  s.roots = {0};
  BlockQuadtree& tree = s.quadtree;
  for (QuadBlock& b : tree.blocks) b.root = newIndex[b.root];
  for (const QuadCell& c : tree.cells)
    std::sort(tree.blocks.begin() + c.firstBlock, tree.blocks.begin() + c.firstBlock + c.blockCount,
              [](const QuadBlock& a, const QuadBlock& b) { return a.root < b.root; });
  return std::uint32_t(cells.size());
}

}  // namespace hlod
