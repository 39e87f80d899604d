// Parry et al. sec. 5: faces simplified with their outlines kept, over one sphere hierarchy of the
// piece's positions.
#include "hlod/parry/ParryPiece.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <unordered_map>

namespace hlod {

namespace {

struct ExactHash {
  std::size_t operator()(const glm::dvec3& p) const {
    std::uint64_t h = 1469598103934665603ull;
    unsigned char bytes[sizeof p];
    std::memcpy(bytes, &p, sizeof p);
    for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
    return std::size_t(h);
  }
};

std::uint64_t pairKey(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t(a) << 32) | b;
}

struct UnionFind {
  std::vector<std::uint32_t> up;
  explicit UnionFind(std::size_t n) : up(n) { std::iota(up.begin(), up.end(), 0u); }
  std::uint32_t find(std::uint32_t v) {
    while (up[v] != v) v = up[v] = up[up[v]];
    return v;
  }
  void join(std::uint32_t a, std::uint32_t b) { up[find(a)] = find(b); }
};

// The outer outline of one face: of the loops its outline edges (edges one of its triangles
// uses, by position) form, the longest. Per position on it, its neighbours along it.
std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> outerOutline(
    const std::vector<std::uint32_t>& triangles, const std::vector<std::uint32_t>& leafIndices,
    const std::vector<glm::dvec3>& at) {
  std::unordered_map<std::uint64_t, int> uses;
  for (std::uint32_t t : triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = leafIndices[3 * t + k], b = leafIndices[3 * t + (k + 1) % 3];
      ++uses[pairKey(std::min(a, b), std::max(a, b))];
    }
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> nb;
  for (const auto& [key, n] : uses) {
    if (n != 1) continue;
    const auto a = std::uint32_t(key >> 32), b = std::uint32_t(key & 0xffffffffu);
    nb[a].push_back(b);
    nb[b].push_back(a);
  }
  // Loops: connected components of the outline; each one's length.
  std::unordered_map<std::uint32_t, std::uint32_t> loopOf;
  std::vector<double> length;
  for (const auto& [start, unused] : nb) {
    if (loopOf.count(start)) continue;
    const auto loop = std::uint32_t(length.size());
    length.push_back(0.0);
    std::vector<std::uint32_t> stack{start};
    loopOf[start] = loop;
    while (!stack.empty()) {
      const std::uint32_t p = stack.back();
      stack.pop_back();
      for (std::uint32_t q : nb[p]) {
        length[loop] += 0.5 * glm::length(at[p] - at[q]);  // each edge seen from both ends
        if (loopOf.try_emplace(q, loop).second) stack.push_back(q);
      }
    }
  }
  if (length.empty()) return {};
  const auto outer = std::uint32_t(std::max_element(length.begin(), length.end()) - length.begin());
  for (auto it = nb.begin(); it != nb.end();)
    it = loopOf[it->first] == outer ? std::next(it) : nb.erase(it);
  return nb;
}

// Least squares for the affine map a * s + b * t + c through (s, t) -> value; zero slopes when
// the points do not span the plane.
glm::dvec3 fitAffine(const std::vector<glm::dvec3>& st1, const std::vector<double>& value) {
  glm::dmat3 m(0.0);
  glm::dvec3 r(0.0);
  for (std::size_t i = 0; i < st1.size(); ++i) {
    m += glm::outerProduct(st1[i], st1[i]);
    r += st1[i] * value[i];
  }
  const double det = glm::determinant(m);
  const double scale = std::max(1e-300, m[0][0] * m[1][1] * m[2][2]);
  if (!(std::abs(det) > 1e-9 * scale)) {
    const double mean = value.empty() ? 0.0 : r.z / double(value.size());
    return {0.0, 0.0, mean};
  }
  return glm::inverse(m) * r;
}

// The root of a leaf's tree in the forest.
std::uint32_t rootOf(const SphereHierarchy& h, std::uint32_t leaf) {
  while (h.nodes[leaf].parent != kNoSphere) leaf = h.nodes[leaf].parent;
  return leaf;
}

// Each straight run of an outline ends in corners (silhouette vertices, never combined): its root
// combines into the corner at its end nearest to it (on equal distances the lower leaf), so that
// at the coarsest a facade face is the polygon of its corners. A run that meets no corner (a
// closed outline that never turns) stays.
void mergeRunsIntoCorners(SphereHierarchy& h, const std::vector<std::uint8_t>& silhouette,
                          const std::vector<std::pair<std::uint32_t, std::uint32_t>>& runEdges) {
  std::map<std::uint32_t, std::uint32_t> cornerOf;  // run root -> corner leaf
  for (const auto& [p, q] : runEdges) {
    if (bool(silhouette[p]) == bool(silhouette[q])) continue;
    const std::uint32_t corner = silhouette[p] ? p : q;
    const std::uint32_t root = rootOf(h, silhouette[p] ? q : p);
    const auto [it, fresh] = cornerOf.try_emplace(root, corner);
    if (fresh) continue;
    const double d = glm::length(h.nodes[corner].centre - h.nodes[root].centre);
    const double best = glm::length(h.nodes[it->second].centre - h.nodes[root].centre);
    if (d < best || (d == best && corner < it->second)) it->second = corner;
  }
  const std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs(cornerOf.begin(),
                                                                   cornerOf.end());
  mergeIntoCorners(h, pairs);
}

}  // namespace

ParryPiece organisePiece(const Mesh& mesh, const std::vector<std::uint8_t>& locked,
                         const ParryParams& params) {
  ParryPiece piece;
  const std::size_t triangles = mesh.triangleCount();
  // Leaves: the distinct positions.
  std::unordered_map<glm::dvec3, std::uint32_t, ExactHash> id;
  std::vector<glm::dvec3> at;
  piece.positionOf.resize(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    auto [it, fresh] =
        id.try_emplace(mesh.positions[v] + glm::dvec3(0.0), std::uint32_t(at.size()));
    if (fresh) at.push_back(mesh.positions[v]);
    piece.positionOf[v] = it->second;
  }
  const std::size_t leaves = at.size();
  std::vector<std::uint32_t> leafIndices(3 * triangles);
  for (std::size_t i = 0; i < leafIndices.size(); ++i)
    leafIndices[i] = piece.positionOf[mesh.indices[i]];

  piece.faces = segmentFaces(mesh, params.faces);
  const FaceSegmentation& seg = piece.faces;
  std::vector<std::vector<std::uint32_t>> faceTriangles(seg.faces.size());
  for (std::uint32_t t = 0; t < triangles; ++t) faceTriangles[seg.faceOf[t]].push_back(t);
  double area = 0.0;
  for (const Face& f : seg.faces) area += f.area;

  // Silhouette vertices and runs: the outer outlines of the facade faces.
  piece.silhouette.assign(leaves, 0);
  for (std::size_t v = 0; v < locked.size() && v < mesh.positions.size(); ++v)
    if (locked[v]) piece.silhouette[piece.positionOf[v]] = 1;
  const double turnCos = std::cos(params.silhouetteAngleDegrees * M_PI / 180.0);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> runEdges;
  std::vector<std::uint8_t> onOutline(leaves, 0);
  const auto isMajor = [&](std::size_t f) { return seg.faces[f].area >= kMajorFace * area; };
  for (std::size_t f = 0; f < seg.faces.size(); ++f) {
    if (!isMajor(f)) continue;
    for (const auto& [p, nb] : outerOutline(faceTriangles[f], leafIndices, at)) {
      onOutline[p] = 1;
      bool corner = nb.size() != 2;
      if (!corner) {
        const glm::dvec3 d0 = glm::normalize(at[p] - at[nb[0]]);
        const glm::dvec3 d1 = glm::normalize(at[nb[1]] - at[p]);
        corner = !(glm::dot(d0, d1) >= turnCos);  // a NaN (an edge of no length) is a turn
      }
      if (corner) piece.silhouette[p] = 1;
      for (std::uint32_t q : nb)
        if (p < q) runEdges.emplace_back(p, q);
    }
  }
  UnionFind runs(leaves);
  for (const auto& [p, q] : runEdges)
    if (!piece.silhouette[p] && !piece.silhouette[q]) runs.join(p, q);
  // The rest: the group of the largest face that uses the position, or of its detail (below).
  std::vector<std::uint32_t> largestFace(leaves, 0xffffffffu);
  for (std::uint32_t t = 0; t < triangles; ++t)
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& f = largestFace[leafIndices[3 * t + k]];
      if (f == 0xffffffffu || seg.faces[seg.faceOf[t]].area > seg.faces[f].area) f = seg.faceOf[t];
    }
  // A detail: minor faces joined through the vertices they own, of minor area all together (a
  // rooftop unit, a ledge standing free of its wall). It is one group, so it simplifies away to
  // one vertex; as a group per face it kept a triangle between every three of its faces.
  UnionFind details(seg.faces.size());
  for (std::uint32_t t = 0; t < triangles; ++t) {
    const std::uint32_t f = seg.faceOf[t];
    if (isMajor(f)) continue;
    for (int k = 0; k < 3; ++k)
      if (const std::uint32_t g = largestFace[leafIndices[3 * t + k]]; !isMajor(g))
        details.join(f, g);
  }
  std::vector<double> detailArea(seg.faces.size(), 0.0);
  for (std::uint32_t f = 0; f < seg.faces.size(); ++f)
    detailArea[details.find(f)] += seg.faces[f].area;
  const auto groupFace = [&](std::uint32_t f) {
    const std::uint32_t d = details.find(f);
    return !isMajor(f) && detailArea[d] < kMajorFace * area ? d : f;
  };

  const std::vector<glm::vec3> normals = computeVertexNormals(at, leafIndices);
  std::vector<double> longest(leaves, 0.0);
  for (std::size_t t = 0; t < triangles; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = leafIndices[3 * t + k], b = leafIndices[3 * t + (k + 1) % 3];
      const double l = glm::length(at[a] - at[b]);
      longest[a] = std::max(longest[a], l);
      longest[b] = std::max(longest[b], l);
    }
  std::vector<SphereVertex> vertices(leaves);
  for (std::uint32_t p = 0; p < leaves; ++p) {
    SphereVertex& s = vertices[p];
    s.position = at[p];
    s.normal = normals[p];
    s.radius = 0.5 * longest[p];
    s.silhouette = piece.silhouette[p] != 0;
    // Runs are numbered by their root position, the rest after them by face.
    s.group = onOutline[p] ? runs.find(p) : std::uint32_t(leaves) + groupFace(largestFace[p]);
  }
  piece.hierarchy = buildSphereHierarchy(vertices);
  mergeRunsIntoCorners(piece.hierarchy, piece.silhouette, runEdges);
  piece.arrays = buildSimplificationArrays(piece.hierarchy, leafIndices);

  // Each face's texture mapping, affine over its plane.
  const bool hasUv = mesh.texCoords.size() == mesh.positions.size();
  piece.frames.resize(seg.faces.size());
  for (std::size_t f = 0; f < seg.faces.size(); ++f) {
    ParryPiece::FaceFrame& fr = piece.frames[f];
    const glm::dvec3 n = seg.faces[f].normal;
    fr.origin = mesh.positions[mesh.indices[3 * faceTriangles[f].front()]];
    fr.s = glm::normalize(
        glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    fr.t = glm::cross(n, fr.s);
    if (!hasUv) continue;
    std::vector<glm::dvec3> st1;
    std::vector<double> us, vs;
    fr.uvMin = glm::vec2(std::numeric_limits<float>::max());
    fr.uvMax = glm::vec2(std::numeric_limits<float>::lowest());
    for (std::uint32_t t : faceTriangles[f])
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = mesh.indices[3 * t + k];
        const glm::dvec3 d = mesh.positions[v] - fr.origin;
        st1.emplace_back(glm::dot(d, fr.s), glm::dot(d, fr.t), 1.0);
        us.push_back(mesh.texCoords[v].x);
        vs.push_back(mesh.texCoords[v].y);
        fr.uvMin = glm::min(fr.uvMin, mesh.texCoords[v]);
        fr.uvMax = glm::max(fr.uvMax, mesh.texCoords[v]);
      }
    fr.u = fitAffine(st1, us);
    fr.v = fitAffine(st1, vs);
  }
  return piece;
}

Mesh pieceAt(const Mesh& mesh, const ParryPiece& piece, std::size_t n, double* splatSize) {
  const ProgressiveCut cut = cutArrays(piece.hierarchy, piece.arrays, n);
  Mesh out;
  out.name = mesh.name;
  out.baseColor = mesh.baseColor;
  out.texture = mesh.texture;
  out.oneSided = mesh.oneSided;
  const bool hasUv = mesh.texCoords.size() == mesh.positions.size();
  const bool hasNormals = mesh.normals.size() == mesh.positions.size();
  const double keepCos = std::cos(30.0 * M_PI / 180.0);
  // Drawn vertices: one per (vertex of the cut, face).
  std::unordered_map<std::uint64_t, std::uint32_t> drawn;
  std::vector<std::vector<std::uint32_t>> facesAt(cut.vertices.size());
  const auto vertexFor = [&](std::uint32_t local, std::uint32_t face, std::uint32_t input) {
    auto [it, fresh] = drawn.try_emplace(pairKey(local, face), std::uint32_t(out.positions.size()));
    if (!fresh) return it->second;
    facesAt[local].push_back(face);
    const SphereNode& sphere = piece.hierarchy.nodes[cut.vertices[local]];
    out.positions.push_back(sphere.centre);
    if (sphere.isLeaf() && input != 0xffffffffu) {  // a vertex of the input, as it was
      out.normals.push_back(hasNormals ? mesh.normals[input] : sphere.normal);
      if (hasUv) out.texCoords.push_back(mesh.texCoords[input]);
      return it->second;
    }
    const glm::vec3 faceNormal(piece.faces.faces[face].normal);
    out.normals.push_back(glm::dot(sphere.normal, faceNormal) >= keepCos ? sphere.normal
                                                                         : faceNormal);
    if (hasUv) {
      const ParryPiece::FaceFrame& fr = piece.frames[face];
      const glm::dvec3 d = sphere.centre - fr.origin;
      const glm::dvec3 st1(glm::dot(d, fr.s), glm::dot(d, fr.t), 1.0);
      const glm::vec2 uv(float(glm::dot(fr.u, st1)), float(glm::dot(fr.v, st1)));
      out.texCoords.push_back(glm::clamp(uv, fr.uvMin, fr.uvMax));
    }
    return it->second;
  };
  out.indices.reserve(cut.indices.size());
  for (std::size_t k = 0; k < cut.triangleIds.size(); ++k) {
    const std::uint32_t t = cut.triangleIds[k];
    const std::uint32_t face = piece.faces.faceOf[t];
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t local = cut.indices[3 * k + c];
      // The input vertex at this corner, where the corner has not moved (a leaf).
      const std::uint32_t input = mesh.indices[3 * std::size_t(t) + c];
      out.indices.push_back(vertexFor(local, face, input));
    }
    // Combining vertices can fold a triangle over its face: turned, it faces as its face does
    // (drawn with back faces culled, it was a hole).
    const glm::dvec3& a = out.positions[out.indices[3 * k]];
    const glm::dvec3 facing = glm::cross(out.positions[out.indices[3 * k + 1]] - a,
                                         out.positions[out.indices[3 * k + 2]] - a);
    if (glm::dot(facing, piece.faces.faces[face].normal) < 0.0)
      std::swap(out.indices[3 * k + 1], out.indices[3 * k + 2]);
  }
  // The combinations left, per face: each face's copy of a child moves into its copy of the
  // parent.
  const Progression& p = cut.progression;
  std::size_t move = 0;
  for (std::size_t j = 0; j < p.increments.size(); ++j) {
    for (; move < p.moveEnd[j]; ++move) {
      const std::uint32_t child = p.moves[2 * move], parent = p.moves[2 * move + 1];
      const std::vector<std::uint32_t> faces = facesAt[child];
      for (std::uint32_t face : faces) {
        const std::uint32_t from = drawn.at(pairKey(child, face));
        const std::uint32_t into = vertexFor(parent, face, 0xffffffffu);
        out.progression.moves.insert(out.progression.moves.end(), {from, into});
      }
    }
    out.progression.moveEnd.push_back(std::uint32_t(out.progression.moves.size() / 2));
    out.progression.increments.push_back(p.increments[j]);
  }
  // A node drawn with no triangles is a splat node's job: its progression stops one triangle
  // short of that (NodeInfo::minTri 0 means "no progression").
  Progression& q = out.progression;
  while (!q.increments.empty() && q.decimated() >= out.triangleCount()) {
    q.increments.pop_back();
    q.moveEnd.pop_back();
    q.moves.resize(2 * std::size_t(q.moveEnd.empty() ? 0 : q.moveEnd.back()));
  }
  if (splatSize) *splatSize = cut.splatSize;
  return out;
}

}  // namespace hlod
