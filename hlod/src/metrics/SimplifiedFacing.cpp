#include "hlod/metrics/SimplifiedFacing.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "hlod/metrics/TriangleBvh.h"

namespace hlod::metrics {

namespace {

// Twice the area below this share of the longest edge squared: a needle, no area.
constexpr double kNeedle = 1e-9;
constexpr double kOpposing = -1e-3;

struct Faces {
  std::vector<Triangle> triangles;
  std::vector<glm::dvec3> normals;  // unit; zero for a triangle without area
};

Result<Faces> faces(const Mesh& mesh, const char* role) {
  const std::string what = std::string("facing check: ") + role + " mesh";
  if (mesh.indices.empty()) return makeError(what + " has no triangles");
  if (mesh.indices.size() % 3 != 0) return makeError(what + ": index count not a multiple of 3");
  for (const glm::dvec3& p : mesh.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return makeError(what + " has a non-finite position");
  Faces out;
  out.triangles.reserve(mesh.indices.size() / 3);
  out.normals.reserve(mesh.indices.size() / 3);
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    Triangle t;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.indices[i + k];
      if (v >= mesh.positions.size()) return makeError(what + ": index out of range");
      t[k] = mesh.positions[v];
    }
    const glm::dvec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
    const double len = glm::length(n);
    double edge2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 e = t[(k + 1) % 3] - t[k];
      edge2 = std::max(edge2, glm::dot(e, e));
    }
    out.triangles.push_back(t);
    out.normals.push_back(len > kNeedle * edge2 && std::isfinite(len) ? n / len : glm::dvec3(0.0));
  }
  return out;
}

}  // namespace

struct FacingChecker::Index {
  std::vector<glm::dvec3> normals;  // of the original's faces with area, in the BVH's ids
  double slack = 0.0;
  TriangleBvh bvh;
};

FacingChecker::FacingChecker(std::unique_ptr<Index> index) : index_(std::move(index)) {}
FacingChecker::FacingChecker(FacingChecker&&) noexcept = default;
FacingChecker& FacingChecker::operator=(FacingChecker&&) noexcept = default;
FacingChecker::~FacingChecker() = default;

Result<FacingChecker> FacingChecker::create(const Mesh& original) {
  Result<Faces> ref = faces(original, "original");
  if (!ref) return ref.error();
  // Only faces with area stand for a surface (and have a normal to compare with).
  std::vector<Triangle>& triangles = ref->triangles;
  std::vector<glm::dvec3>& normals = ref->normals;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    if (normals[i] == glm::dvec3(0.0)) continue;
    triangles[kept] = triangles[i];
    normals[kept++] = normals[i];
  }
  triangles.resize(kept);
  normals.resize(kept);
  if (triangles.empty()) return makeError("facing check: the original mesh has no area");
  const double slack = 1e-6 * glm::length(original.bounds().size());
  return FacingChecker(
      std::make_unique<Index>(Index{std::move(normals), slack, TriangleBvh(std::move(triangles))}));
}

Result<std::vector<TriangleFacing>> FacingChecker::check(const Mesh& simplified,
                                                         double offLimit) const {
  Result<Faces> test = faces(simplified, "simplified");
  if (!test) return test.error();
  const TriangleBvh& bvh = index_->bvh;
  std::vector<TriangleFacing> out(test->triangles.size());
  std::vector<std::uint32_t> near;
  // Neighbouring points are near the same face.
  std::uint32_t hint = TriangleBvh::kNoHint, nearHint = TriangleBvh::kNoHint;
  const double offLimit2 = offLimit * offLimit;
  for (std::size_t i = 0; i < test->triangles.size(); ++i) {
    const glm::dvec3& n = test->normals[i];
    if (n == glm::dvec3(0.0)) continue;
    const Triangle& t = test->triangles[i];
    const glm::dvec3 centroid = (t[0] + t[1] + t[2]) / 3.0;
    double centroid2 = 0.0;
    bvh.nearest(centroid, index_->slack, near, &centroid2, &nearHint);
    double best = -2.0;
    for (std::uint32_t id : near) best = std::max(best, glm::dot(index_->normals[id], n));
    // The centroid's distance is the nearest search's own; the edge midpoints are measured.
    double off = offLimit > 0.0 && centroid2 <= offLimit2 ? 0.0 : std::sqrt(centroid2);
    const glm::dvec3 midpoints[3] = {0.5 * (t[0] + t[1]), 0.5 * (t[1] + t[2]), 0.5 * (t[2] + t[0])};
    for (const glm::dvec3& p : midpoints)
      if (!(offLimit > 0.0 && bvh.within2(p, offLimit2, hint)))
        off = std::max(off, bvh.distance(p));
    out[i] = {true, best < kOpposing, off};
  }
  return out;
}

Result<std::vector<TriangleFacing>> triangleFacing(const Mesh& original, const Mesh& simplified) {
  Result<FacingChecker> checker = FacingChecker::create(original);
  if (!checker) return checker.error();
  return checker->check(simplified);
}

Result<FacingReport> checkFacing(const Mesh& original, const Mesh& simplified, double offLimit) {
  Result<FacingChecker> checker = FacingChecker::create(original);
  if (!checker) return checker.error();
  return checkFacing(*checker, simplified, offLimit);
}

Result<FacingReport> checkFacing(const FacingChecker& checker, const Mesh& simplified,
                                 double offLimit) {
  Result<std::vector<TriangleFacing>> each = checker.check(simplified);
  if (!each) return each.error();
  FacingReport r;
  for (std::size_t i = 0; i < each->size(); ++i) {
    const TriangleFacing& f = (*each)[i];
    if (!f.hasArea) continue;
    const glm::dvec3& a = simplified.positions[simplified.indices[3 * i]];
    const glm::dvec3& b = simplified.positions[simplified.indices[3 * i + 1]];
    const glm::dvec3& c = simplified.positions[simplified.indices[3 * i + 2]];
    const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
    ++r.triangles;
    r.area += area;
    if (f.flipped) ++r.flipped, r.flippedArea += area;
    if (f.off > offLimit) ++r.standingOff;
    r.maxOff = std::max(r.maxOff, f.off);
  }
  return r;
}

}  // namespace hlod::metrics
