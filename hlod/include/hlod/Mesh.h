#pragma once
// Core mesh types shared by import, city generation, the HLOD builder and the renderer.
//
// Coordinates: world positions are doubles (Mesh). A LocalMesh keeps float positions relative to
// its own double-precision centre: this is what nodes store and what the renderer uploads, so a
// model far from the origin keeps full precision (docs/architecture.md, Formats: Coordinates).
//
// Texture coordinates follow glTF: (0,0) is the top-left of the image, v grows downwards; Image
// row 0 is the top row. Importers of formats with v up (OBJ, PLY) flip v.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Progression.h"
#include "hlod/Splat.h"

namespace hlod {

// 8-bit RGBA image, row 0 at the top.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 4

  bool empty() const { return width <= 0 || height <= 0; }
};

struct Aabb {
  glm::dvec3 min{std::numeric_limits<double>::max()};
  glm::dvec3 max{std::numeric_limits<double>::lowest()};

  bool empty() const { return min.x > max.x; }
  void extend(const glm::dvec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void extend(const Aabb& b) {
    if (!b.empty()) {
      extend(b.min);
      extend(b.max);
    }
  }
  glm::dvec3 centre() const { return (min + max) * 0.5; }
  glm::dvec3 size() const { return empty() ? glm::dvec3(0.0) : max - min; }
};

// A triangle mesh in world coordinates (double precision).
struct Mesh {
  std::string name;
  std::vector<glm::dvec3> positions;
  std::vector<glm::vec3> normals;      // empty, or one per position
  std::vector<glm::vec2> texCoords;    // empty, or one per position
  std::vector<std::uint32_t> indices;  // three per triangle
  glm::vec4 baseColor{0.8f, 0.8f, 0.8f, 1.0f};
  std::shared_ptr<const Image> texture;  // optional base-colour texture
  // Every triangle is wound counter-clockwise seen from the side that can be seen (closed solids,
  // ground): back faces may be culled. Scanned and CAD data (mixed winding) leave it false and are
  // drawn two-sided.
  bool oneSided = false;
  // How the triangles simplify further without re-simplifying (Parry; empty for the other
  // simplifiers). Whoever renumbers the vertices or reorders the triangles must drop it.
  Progression progression;

  std::size_t triangleCount() const { return indices.size() / 3; }
  Aabb bounds() const;
};

// The coordinate reference system a geo-referenced import declared (CityJSON's metadata), and
// what the import did with it: for `hlodr info` and the user, never consulted by the builder.
struct ModelCrs {
  int epsg = 0;             // 0: none declared (or not an EPSG code)
  std::string description;  // e.g. "EPSG:7415 (projected): coordinates kept as they are"
  // Geographic and earth-centred data are converted into a local east-north-up frame (metres,
  // X east, Y north, Z up) at this origin: degrees and metres above the WGS84 ellipsoid.
  bool toEnu = false;
  double originLat = 0.0, originLon = 0.0, originHeight = 0.0;
};

// The triangles of one city object in one mesh: [firstTriangle, firstTriangle + triangleCount)
// of meshes[mesh] came from city object `object` (CityJSON keeps each building whole this way,
// so that the builder can group buildings into blocks).
struct ObjectRun {
  std::uint32_t object = 0;
  std::uint32_t mesh = 0;
  std::uint32_t firstTriangle = 0;
  std::uint32_t triangleCount = 0;
};

// Several meshes: a glTF scene, an OBJ with several materials, a city.
struct Model {
  std::vector<Mesh> meshes;
  // What the file was ("CityJSON 2.0"); empty for the plain mesh formats.
  std::string format;
  ModelCrs crs;
  std::size_t cityObjects = 0;  // CityJSON: city objects with imported geometry
  // Every triangle's object, as runs (objects numbered from 0): the "objects" of Manocha sec. 2,
  // the lowest level of organisation above the triangles. CityJSON: its city objects
  // (0..cityObjects-1); glTF: each node instance with a mesh; OBJ: each o/g group. Empty for the
  // formats without objects (PLY, OFF, STL): the file is one object.
  std::vector<ObjectRun> objectRuns;
  std::string lod;   // CityJSON: the level(s) of detail imported
  bool zUp = false;  // true for city models (CityJSON); mesh files are Y-up
  // What the import skipped without failing (a texture it could not load, a material library
  // outside the model's folder): for the caller to show. The library never prints.
  std::vector<std::string> warnings;

  std::size_t triangleCount() const;
  Aabb bounds() const;
  // The objects objectRuns number (the largest number + 1), or 1 without runs.
  std::size_t objectCount() const;
};

// A mesh with float positions relative to a double-precision centre: the render/storage form.
struct LocalMesh {
  glm::dvec3 centre{0.0};
  std::vector<glm::vec3> positions;  // relative to centre
  std::vector<glm::vec3> normals;    // one per position (always filled by toLocal)
  std::vector<glm::vec2> texCoords;  // empty, or one per position
  std::vector<std::uint32_t> indices;
  glm::vec4 baseColor{0.8f, 0.8f, 0.8f, 1.0f};
  std::shared_ptr<const Image> texture;
  bool oneSided = false;      // as Mesh::oneSided
  Progression progression;    // as Mesh::progression
  std::vector<Splat> splats;  // empty: the node is never drawn as splats

  std::size_t triangleCount() const { return indices.size() / 3; }
};

// n normalised, or fallback when n has no length (opposite normals cancel) or is not finite.
inline glm::vec3 normalizedOr(const glm::vec3& n, const glm::vec3& fallback) {
  const float len = glm::length(n);
  return len > 1e-12f && std::isfinite(len) ? n / len : fallback;
}

// Area-weighted per-vertex normals (computed in double; degenerate triangles add nothing, a
// vertex with no area gets +Z so that no NaN reaches the GPU).
std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::dvec3>& positions,
                                            const std::vector<std::uint32_t>& indices);

// Converts to the local form around the bounding-box centre; computes normals if missing.
LocalMesh toLocal(const Mesh& mesh);

}  // namespace hlod
