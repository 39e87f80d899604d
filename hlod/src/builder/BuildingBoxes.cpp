// Buildings as boxes (builder/BuildingBoxes.h).
#include "builder/BuildingBoxes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "builder/SimplifierImpl.h"

namespace hlod {

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
  std::vector<Part> parts;  // in the order of their first triangles
  std::unordered_map<std::uint32_t, std::uint32_t> partOf;
  for (std::uint32_t t = 0; t * 3 < mesh.indices.size(); ++t) {
    const auto [at, added] =
        partOf.try_emplace(find(pid[mesh.indices[3 * t]]), std::uint32_t(parts.size()));
    if (added) parts.emplace_back();
    Part& part = parts[at->second];
    part.triangles.push_back(t);
    for (int k = 0; k < 3; ++k) part.box.extend(mesh.positions[mesh.indices[3 * t + k]]);
  }
  const auto flat = [&](const Aabb& box) {
    const glm::dvec3 size = box.size();
    return size[u] * kGroundAspect < std::max(size[e0], size[e1]);
  };
  // A simplified building's roof (and what stands on it) need not share a position with its
  // walls: a cornice or parapet between them is gone. A part lying over a building part's
  // footprint (at least kOnFootprint of its own), its bottom above that part's by kRoofLift of
  // its height and not above its top, is taken into it; otherwise the roof would count as
  // ground and the walls as no box.
  const auto footprintArea = [&](const Aabb& a) {
    return (a.max[e0] - a.min[e0]) * (a.max[e1] - a.min[e1]);
  };
  // The building parts by the start of their boxes along e0: a part's candidates end where
  // they start past its own box.
  std::vector<std::uint32_t> walls;
  for (std::uint32_t w = 0; w < parts.size(); ++w)
    if (!flat(parts[w].box)) walls.push_back(w);
  std::sort(walls.begin(), walls.end(), [&](std::uint32_t a, std::uint32_t b) {
    return parts[a].box.min[e0] < parts[b].box.min[e0];
  });
  std::vector<std::uint32_t> into(parts.size());
  for (std::uint32_t q = 0; q < parts.size(); ++q) {
    into[q] = q;
    const Aabb& a = parts[q].box;
    double best = kOnFootprint * std::max(footprintArea(a), 0.0);
    for (std::uint32_t w : walls) {
      const Aabb& b = parts[w].box;
      if (b.min[e0] >= a.max[e0]) break;
      const double height = b.max[u] - b.min[u];
      if (w == q || !(height > a.max[u] - a.min[u]) || a.min[u] < b.min[u] + kRoofLift * height ||
          a.min[u] > b.max[u])
        continue;
      const double dx = std::min(a.max[e0], b.max[e0]) - std::max(a.min[e0], b.min[e0]);
      const double dy = std::min(a.max[e1], b.max[e1]) - std::max(a.min[e1], b.min[e1]);
      // Of equal overlaps, the part made last (the walls, not a ledge on them, in a block's order).
      if (!(dx > 0.0 && dy > 0.0)) continue;
      if (dx * dy > best || (dx * dy == best && (into[q] == q || w > into[q])))
        best = dx * dy, into[q] = w;
    }
  }
  // Chains (a unit on a roof on its walls) end at a part taken into none.
  for (std::uint32_t q = 0; q < parts.size(); ++q) {
    std::uint32_t w = into[q];
    for (int hops = 0; into[w] != w && hops < 64; ++hops) w = into[w];
    if (w == q) continue;
    Part& target = parts[w];
    target.triangles.insert(target.triangles.end(), parts[q].triangles.begin(),
                            parts[q].triangles.end());
    target.box.extend(parts[q].box);
    parts[q].triangles.clear();
  }
  std::vector<BuildingBox> out;
  std::vector<std::uint8_t> taken(mesh.triangleCount(), 0);
  for (Part& part : parts) {
    if (part.triangles.empty() || flat(part.box)) continue;  // taken into another, or ground
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

}  // namespace hlod
