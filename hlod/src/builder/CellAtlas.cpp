// A cell node's atlas baked from its children (builder/CellAtlas.h).
#include "builder/CellAtlas.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "builder/SimplifierImpl.h"
#include "hlod/metrics/TriangleBvh.h"

namespace hlod {

namespace {

constexpr int kGutter = 2;            // texels around each chart, filled from its edge
constexpr double kPlanFacing = 0.5;   // |normal . up| at least this: the plan chart
constexpr double kPatchCos = 0.9063;  // cos 25 degrees: a patch's normals
constexpr std::uint32_t kNone = 0xffffffffu;

struct Chart {
  bool plan = false;
  std::vector<std::uint32_t> triangles;
  glm::dvec3 normal{0.0};             // a patch's (unit): the cast looks along -normal
  glm::dvec3 axisU{0.0}, axisV{0.0};  // world directions of the chart's s and t
  double minU = 0.0, minV = 0.0, maxU = 0.0, maxV = 0.0;  // the triangles' extent along them
  int width = 0, height = 0;                              // texels, gutter included
  int x = 0, y = 0;                                       // its place in the atlas
};

glm::dvec3 faceNormal(const Mesh& m, std::uint32_t t) {
  const glm::dvec3& a = m.positions[m.indices[3 * t]];
  const glm::dvec3 n =
      glm::cross(m.positions[m.indices[3 * t + 1]] - a, m.positions[m.indices[3 * t + 2]] - a);
  const double len = glm::length(n);
  return len > 0.0 && std::isfinite(len) ? n / len : glm::dvec3(0.0);
}

// The plan chart and the patches, each with its projection axes and extent.
std::vector<Chart> makeCharts(const Mesh& m, const glm::dvec3& up) {
  const auto triangles = std::uint32_t(m.triangleCount());
  std::vector<glm::dvec3> normals(triangles);
  for (std::uint32_t t = 0; t < triangles; ++t) normals[t] = faceNormal(m, t);
  std::vector<Chart> charts(1);
  charts[0].plan = true;
  std::vector<std::uint32_t> chartOf(triangles, kNone);
  for (std::uint32_t t = 0; t < triangles; ++t)
    if (std::abs(glm::dot(normals[t], up)) >= kPlanFacing || normals[t] == glm::dvec3(0.0))
      chartOf[t] = 0, charts[0].triangles.push_back(t);
  // Edges by their two positions: triangles sharing one are neighbours.
  std::unordered_map<glm::dvec3, std::uint32_t, PositionHash> id;
  const auto positionId = [&](std::uint32_t v) {
    return id.try_emplace(m.positions[v] + glm::dvec3(0.0), std::uint32_t(id.size())).first->second;
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> edgeTriangles;
  for (std::uint32_t t = 0; t < triangles; ++t) {
    if (chartOf[t] != kNone) continue;
    std::uint32_t p[3];
    for (int k = 0; k < 3; ++k) p[k] = positionId(m.indices[3 * t + k]);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = std::min(p[k], p[(k + 1) % 3]), b = std::max(p[k], p[(k + 1) % 3]);
      edgeTriangles[std::uint64_t(a) << 32 | b].push_back(t);
    }
  }
  std::unordered_map<std::uint32_t, std::vector<std::uint64_t>> edgesOf;
  for (const auto& [edge, ts] : edgeTriangles)
    for (std::uint32_t t : ts) edgesOf[t].push_back(edge);
  for (std::uint32_t seed = 0; seed < triangles; ++seed) {
    if (chartOf[seed] != kNone) continue;
    const auto c = std::uint32_t(charts.size());
    charts.emplace_back();
    std::vector<std::uint32_t> queue{seed};
    chartOf[seed] = c;
    for (std::size_t i = 0; i < queue.size(); ++i)
      for (std::uint64_t edge : edgesOf[queue[i]])
        for (std::uint32_t n : edgeTriangles[edge])
          if (chartOf[n] == kNone && glm::dot(normals[n], normals[seed]) >= kPatchCos)
            chartOf[n] = c, queue.push_back(n);
    charts[c].triangles = std::move(queue);
  }
  // Axes: the plan looks down (s along the first horizontal axis, t against the second, so that
  // the image is a map with the second axis up); a patch is seen from the front, s horizontal.
  int e0 = 0;
  for (int k = 0; k < 3; ++k)
    if (up[k] != 0.0) e0 = (k + 1) % 3;
  const int e1 = (e0 + 1) % 3;
  for (Chart& chart : charts) {
    if (chart.plan) {
      chart.normal = up;
      chart.axisU = glm::dvec3(0.0), chart.axisV = glm::dvec3(0.0);
      chart.axisU[e0] = 1.0;
      chart.axisV[e1] = -1.0;
    } else {
      glm::dvec3 n(0.0);
      for (std::uint32_t t : chart.triangles) {
        const glm::dvec3& a = m.positions[m.indices[3 * t]];
        n += glm::cross(m.positions[m.indices[3 * t + 1]] - a,
                        m.positions[m.indices[3 * t + 2]] - a);
      }
      chart.normal = glm::length(n) > 0.0 ? glm::normalize(n) : normals[chart.triangles[0]];
      glm::dvec3 u = glm::cross(up, chart.normal);
      if (!(glm::length(u) > 1e-9)) u = chart.axisU;
      chart.axisU = glm::normalize(u);
      chart.axisV = glm::cross(chart.normal, chart.axisU) * -1.0;  // rows go down the wall
    }
    chart.minU = chart.minV = std::numeric_limits<double>::max();
    chart.maxU = chart.maxV = std::numeric_limits<double>::lowest();
    for (std::uint32_t t : chart.triangles)
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3& p = m.positions[m.indices[3 * t + k]];
        const double u = glm::dot(p, chart.axisU), v = glm::dot(p, chart.axisV);
        chart.minU = std::min(chart.minU, u), chart.maxU = std::max(chart.maxU, u);
        chart.minV = std::min(chart.minV, v), chart.maxV = std::max(chart.maxV, v);
      }
  }
  if (charts[0].triangles.empty()) charts.erase(charts.begin());
  return charts;
}

// Sizes the charts at `texel` and packs them on shelves, tallest first, into an atlas about
// square; returns its size (0 x 0 without charts).
glm::ivec2 pack(std::vector<Chart>& charts, double texel) {
  double area = 0.0;
  int widest = 1;
  for (Chart& c : charts) {
    c.width = int(std::ceil((c.maxU - c.minU) / texel)) + 1 + 2 * kGutter;
    c.height = int(std::ceil((c.maxV - c.minV) / texel)) + 1 + 2 * kGutter;
    area += double(c.width) * c.height;
    widest = std::max(widest, c.width);
  }
  if (charts.empty()) return {0, 0};
  std::vector<std::size_t> order(charts.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return charts[a].height > charts[b].height; });
  const int side = std::max(widest, int(std::ceil(std::sqrt(area * 1.1))));
  int x = 0, y = 0, shelf = 0, used = 0;
  for (std::size_t i : order) {
    Chart& c = charts[i];
    if (x + c.width > side) x = 0, y += shelf, shelf = 0;
    c.x = x, c.y = y;
    x += c.width;
    shelf = std::max(shelf, c.height);
    used = std::max(used, x);
  }
  return {used, y + shelf};
}

glm::vec4 sample(const LocalMesh& child, std::uint32_t triangle, double u, double v) {
  if (!child.texture || child.texture->empty() || child.texCoords.size() != child.positions.size())
    return child.baseColor;
  const Image& img = *child.texture;
  const std::uint32_t* tri = &child.indices[3 * triangle];
  const glm::dvec2 uv = (1.0 - u - v) * glm::dvec2(child.texCoords[tri[0]]) +
                        u * glm::dvec2(child.texCoords[tri[1]]) +
                        v * glm::dvec2(child.texCoords[tri[2]]);
  // Bilinear between texel centres, wrapping (a repeating texture).
  const double fx = uv.x * img.width - 0.5, fy = uv.y * img.height - 0.5;
  const double x0 = std::floor(fx), y0 = std::floor(fy);
  const double ax = fx - x0, ay = fy - y0;
  const auto wrap = [](double i, int n) {
    const double r = std::fmod(i, double(n));
    return std::size_t(r < 0.0 ? r + n : r);
  };
  glm::dvec4 colour(0.0);
  for (int dy = 0; dy <= 1; ++dy)
    for (int dx = 0; dx <= 1; ++dx) {
      const std::uint8_t* p = &img.pixels[(wrap(y0 + dy, img.height) * std::size_t(img.width) +
                                           wrap(x0 + dx, img.width)) *
                                          4];
      const double w = (dx ? ax : 1.0 - ax) * (dy ? ay : 1.0 - ay);
      colour += w * glm::dvec4(p[0], p[1], p[2], p[3]);
    }
  return glm::vec4(colour / 255.0) * child.baseColor;
}

// Barycentric weights (of corners 1 and 2) of the point of triangle t nearest to p.
glm::dvec2 nearestWeights(const metrics::Triangle& t, const glm::dvec3& p) {
  const glm::dvec3 e1 = t[1] - t[0], e2 = t[2] - t[0], d = p - t[0];
  const double a = glm::dot(e1, e1), b = glm::dot(e1, e2), c = glm::dot(e2, e2);
  const double det = a * c - b * b;
  if (!(det > 0.0)) return {0.0, 0.0};
  double u = (c * glm::dot(d, e1) - b * glm::dot(d, e2)) / det;
  double v = (a * glm::dot(d, e2) - b * glm::dot(d, e1)) / det;
  // Outside: clamped into the triangle (close enough for a colour).
  u = std::max(0.0, u), v = std::max(0.0, v);
  if (u + v > 1.0) u /= u + v, v = 1.0 - u;
  return {u, v};
}

// What the plan chart's texels see from above: per texel centre, the highest child surface that
// faces up, found by drawing the children's triangles top-down into the chart (an orthographic
// render with a height buffer) instead of casting a ray per texel.
struct SeenFromAbove {
  double height = -std::numeric_limits<double>::infinity();
  std::uint32_t triangle = kNone;  // into the children's triangle list
  double u = 0.0, v = 0.0;         // barycentric weights of its second and third corners
};

std::vector<SeenFromAbove> drawFromAbove(const Chart& chart, double texel,
                                         const std::vector<metrics::Triangle>& triangles,
                                         const glm::dvec3& up) {
  std::vector<SeenFromAbove> seen(std::size_t(chart.width) * chart.height);
  for (std::uint32_t i = 0; i < triangles.size(); ++i) {
    const metrics::Triangle& tri = triangles[i];
    if (!(glm::dot(glm::cross(tri[1] - tri[0], tri[2] - tri[0]), up) > 0.0)) continue;
    glm::dvec2 st[3];
    double h[3];
    for (int k = 0; k < 3; ++k) {
      st[k] = {kGutter + (glm::dot(tri[k], chart.axisU) - chart.minU) / texel,
               kGutter + (glm::dot(tri[k], chart.axisV) - chart.minV) / texel};
      h[k] = glm::dot(tri[k], up);
    }
    const double area =
        (st[1].x - st[0].x) * (st[2].y - st[0].y) - (st[2].x - st[0].x) * (st[1].y - st[0].y);
    if (!(std::abs(area) > 1e-12)) continue;
    const int x0 = std::max(0, int(std::floor(std::min({st[0].x, st[1].x, st[2].x}))));
    const int x1 = std::min(chart.width - 1, int(std::ceil(std::max({st[0].x, st[1].x, st[2].x}))));
    const int y0 = std::max(0, int(std::floor(std::min({st[0].y, st[1].y, st[2].y}))));
    const int y1 =
        std::min(chart.height - 1, int(std::ceil(std::max({st[0].y, st[1].y, st[2].y}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double cx = x + 0.5, cy = y + 0.5;
        const double w1 =
            ((cx - st[0].x) * (st[2].y - st[0].y) - (st[2].x - st[0].x) * (cy - st[0].y)) / area;
        const double w2 =
            ((st[1].x - st[0].x) * (cy - st[0].y) - (cx - st[0].x) * (st[1].y - st[0].y)) / area;
        if (w1 < 0.0 || w2 < 0.0 || w1 + w2 > 1.0) continue;
        SeenFromAbove& s = seen[std::size_t(y) * chart.width + x];
        const double height = (1.0 - w1 - w2) * h[0] + w1 * h[1] + w2 * h[2];
        if (height > s.height) s = {height, i, w1, w2};
      }
  }
  return seen;
}

}  // namespace

CellAtlasStats bakeCellAtlas(Mesh& mesh, std::span<const LocalMesh> children,
                             const CellAtlasOptions& o) {
  CellAtlasStats stats;
  assert(mesh.indices.size() == mesh.positions.size());
  // The children's surface, in world coordinates, for the casts.
  std::vector<metrics::Triangle> triangles;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> owner;  // (child, triangle)
  Aabb childBounds;
  for (std::uint32_t c = 0; c < children.size(); ++c) {
    const LocalMesh& child = children[c];
    for (std::uint32_t t = 0; t * 3 + 2 < child.indices.size(); ++t) {
      metrics::Triangle tri;
      for (int k = 0; k < 3; ++k) {
        tri[k] = child.centre + glm::dvec3(child.positions[child.indices[3 * t + k]]);
        childBounds.extend(tri[k]);
      }
      triangles.push_back(tri);
      owner.emplace_back(c, t);
    }
  }
  if (triangles.empty() || mesh.indices.empty()) return stats;
  const std::vector<metrics::Triangle> corners = triangles;  // the BVH takes its own copy
  const metrics::TriangleBvh bvh(std::move(triangles));

  const glm::dvec3 up = upVector(o.up);
  std::vector<Chart> charts = makeCharts(mesh, up);
  double texel = std::max(o.texelSize, 1e-9);
  glm::ivec2 size = pack(charts, texel);
  for (int tries = 0; tries < 8 && std::max(size.x, size.y) > o.maxSide; ++tries) {
    texel *= 1.05 * double(std::max(size.x, size.y)) / o.maxSide;
    size = pack(charts, texel);
  }
  stats.charts = charts.size();
  stats.texelSize = texel;

  auto image = std::make_shared<Image>();
  image->width = std::max(1, size.x);
  image->height = std::max(1, size.y);
  image->pixels.assign(std::size_t(image->width) * image->height * 4, 0);
  std::vector<std::uint8_t> covered(std::size_t(image->width) * image->height, 0);
  const auto put = [&](int x, int y, const glm::vec4& c) {
    const std::size_t i = std::size_t(y) * image->width + x;
    for (int ch = 0; ch < 4; ++ch)
      image->pixels[4 * i + ch] = std::uint8_t(std::lround(std::clamp(c[ch], 0.0f, 1.0f) * 255.0f));
    covered[i] = 1;
  };
  // The colour of the children's surface a cast from `from` along `dir` meets first (facing it),
  // or of the one nearest to `at`.
  std::vector<std::uint32_t> near;
  std::uint32_t hint = metrics::TriangleBvh::kNoHint;
  const auto colourAt = [&](const glm::dvec3& from, const glm::dvec3& dir, double depth,
                            const glm::dvec3& at) {
    if (const auto hit = bvh.firstHit(from, dir, depth, true)) {
      const auto [c, t] = owner[hit.triangle];
      return sample(children[c], t, hit.u, hit.v);
    }
    // Of the nearest faces (within a texel of the nearest: over an edge, both), the one facing
    // most as the cast looked: a wall above a lower roof takes the wall's colour, not the roof's.
    ++stats.missed;
    bvh.nearest(at, texel, near, nullptr, &hint);
    std::uint32_t id = near.empty() ? 0 : near.front();
    double facing = -2.0;
    for (std::uint32_t k : near) {
      const metrics::Triangle& tri = corners[k];
      const glm::dvec3 n = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
      const double f = glm::length(n) > 0.0 ? -glm::dot(n, dir) / glm::length(n) : -2.0;
      if (f > facing) facing = f, id = k;
    }
    const glm::dvec2 w = nearestWeights(corners[id], at);
    const auto [c, t] = owner[id];
    return sample(children[c], t, w.x, w.y);
  };
  const double top = glm::dot(childBounds.max, up), bottom = glm::dot(childBounds.min, up);
  const double planTop = std::max(top, glm::dot(mesh.bounds().max, up)) + 1.0;
  const double planDepth = planTop - std::min(bottom, glm::dot(mesh.bounds().min, up)) + 1.0;

  // Texture coordinates, and the texels inside each triangle filled by their casts.
  mesh.texCoords.assign(mesh.positions.size(), glm::vec2(0.0f));
  for (const Chart& chart : charts) {
    std::size_t filled = 0;
    const std::vector<SeenFromAbove> above =
        chart.plan ? drawFromAbove(chart, texel, corners, up) : std::vector<SeenFromAbove>{};
    for (std::uint32_t t : chart.triangles) {
      glm::dvec2 st[3];
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = mesh.indices[3 * t + k];
        p[k] = mesh.positions[v];
        st[k] = {chart.x + kGutter + (glm::dot(p[k], chart.axisU) - chart.minU) / texel,
                 chart.y + kGutter + (glm::dot(p[k], chart.axisV) - chart.minV) / texel};
        mesh.texCoords[v] = glm::vec2(st[k].x / image->width, st[k].y / image->height);
      }
      const double area =
          (st[1].x - st[0].x) * (st[2].y - st[0].y) - (st[2].x - st[0].x) * (st[1].y - st[0].y);
      if (!(std::abs(area) > 1e-12)) continue;
      const int x0 = std::max(0, int(std::floor(std::min({st[0].x, st[1].x, st[2].x}))));
      const int x1 =
          std::min(image->width - 1, int(std::ceil(std::max({st[0].x, st[1].x, st[2].x}))));
      const int y0 = std::max(0, int(std::floor(std::min({st[0].y, st[1].y, st[2].y}))));
      const int y1 =
          std::min(image->height - 1, int(std::ceil(std::max({st[0].y, st[1].y, st[2].y}))));
      const glm::dvec3 n = chart.plan ? up : chart.normal;
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const glm::dvec2 c(x + 0.5, y + 0.5);
          const double w1 =
              ((c.x - st[0].x) * (st[2].y - st[0].y) - (st[2].x - st[0].x) * (c.y - st[0].y)) /
              area;
          const double w2 =
              ((st[1].x - st[0].x) * (c.y - st[0].y) - (c.x - st[0].x) * (st[1].y - st[0].y)) /
              area;
          const double w0 = 1.0 - w1 - w2;
          if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
          if (covered[std::size_t(y) * image->width + x]) continue;
          const glm::dvec3 at = w0 * p[0] + w1 * p[1] + w2 * p[2];
          glm::vec4 colour;
          if (chart.plan) {
            assert(x >= chart.x && x - chart.x < chart.width && y >= chart.y &&
                   y - chart.y < chart.height);
            const SeenFromAbove& a = above[std::size_t(y - chart.y) * chart.width + (x - chart.x)];
            if (a.triangle != kNone) {
              const auto [child, ct] = owner[a.triangle];
              colour = sample(children[child], ct, a.u, a.v);
            } else {
              const glm::dvec3 from = at + (planTop - glm::dot(at, up)) * up;
              colour = colourAt(from, -up, planDepth, at);
            }
          } else {
            colour = colourAt(at + o.castDepth * n, -n, 3.0 * o.castDepth, at);
          }
          put(x, y, colour);
          ++filled;
        }
    }
    // A chart too thin to hold a texel centre: its triangles' colour at their centroids, over
    // the whole chart.
    if (filled == 0) {
      glm::vec4 sum(0.0f);
      for (std::uint32_t t : chart.triangles) {
        const glm::dvec3 at =
            (mesh.positions[mesh.indices[3 * t]] + mesh.positions[mesh.indices[3 * t + 1]] +
             mesh.positions[mesh.indices[3 * t + 2]]) /
            3.0;
        const glm::dvec3 n = chart.plan ? up : chart.normal;
        sum += chart.plan ? colourAt(at + (planTop - glm::dot(at, up)) * up, -up, planDepth, at)
                          : colourAt(at + o.castDepth * n, -n, 3.0 * o.castDepth, at);
      }
      const glm::vec4 mean = sum / float(chart.triangles.size());
      for (int y = chart.y; y < chart.y + chart.height && y < image->height; ++y)
        for (int x = chart.x; x < chart.x + chart.width && x < image->width; ++x) put(x, y, mean);
    }
    stats.texels += filled;
  }
  // The gutters (and texels of a chart no triangle's centre test took), from their neighbours.
  for (int pass = 0; pass < kGutter + 1; ++pass) {
    std::vector<std::uint8_t> next = covered;
    for (int y = 0; y < image->height; ++y)
      for (int x = 0; x < image->width; ++x) {
        if (covered[std::size_t(y) * image->width + x]) continue;
        glm::vec4 sum(0.0f);
        int n = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= image->width || ny >= image->height) continue;
            const std::size_t j = std::size_t(ny) * image->width + nx;
            if (!covered[j]) continue;
            for (int ch = 0; ch < 4; ++ch) sum[ch] += image->pixels[4 * j + ch];
            ++n;
          }
        if (n == 0) continue;
        const std::size_t i = std::size_t(y) * image->width + x;
        for (int ch = 0; ch < 4; ++ch)
          image->pixels[4 * i + ch] = std::uint8_t(std::lround(sum[ch] / n));
        next[i] = 1;
      }
    covered = std::move(next);
  }
  mesh.texture = std::move(image);
  mesh.baseColor = glm::vec4(1.0f);
  return stats;
}

double texelSizeOf(std::span<const LocalMesh> children) {
  double area = 0.0, texels = 0.0;
  for (const LocalMesh& c : children) {
    if (!c.texture || c.texture->empty() || c.texCoords.size() != c.positions.size()) continue;
    for (std::size_t i = 0; i + 2 < c.indices.size(); i += 3) {
      const glm::dvec3 a(c.positions[c.indices[i]]);
      area += 0.5 * glm::length(glm::cross(glm::dvec3(c.positions[c.indices[i + 1]]) - a,
                                           glm::dvec3(c.positions[c.indices[i + 2]]) - a));
    }
    texels += double(c.texture->width) * c.texture->height;
  }
  return texels > 0.0 && area > 0.0 ? std::sqrt(area / texels) : 0.0;
}

}  // namespace hlod
