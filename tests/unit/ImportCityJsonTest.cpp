// CityJSON import: hand-built files with counts worked out by hand, the 2.0 conformance cases and
// the Rotterdam 0.2 example from shared/data (skipped with a message when absent), and malformed
// files that must each give an Error naming the problem.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "ImportTestUtil.h"
#include "SharedData.h"
#include "hlod/geodesy/Epsg.h"
#include "hlod/geodesy/Geodesy.h"
#include "hlod/import/CityJsonPalette.h"
#include "hlod/import/Import.h"

namespace hlod {
namespace {

using nlohmann::json;
using testing::TempDir;

json readJson(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return json::parse(ss.str());
}

// A CityJSON 2.0 document with identity transform, the given vertices and city objects.
json doc(json vertices, json objects) {
  return {{"type", "CityJSON"},
          {"version", "2.0"},
          {"transform", {{"scale", {1.0, 1.0, 1.0}}, {"translate", {0.0, 0.0, 0.0}}}},
          {"vertices", std::move(vertices)},
          {"CityObjects", std::move(objects)}};
}

const json kCube = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                    {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
// The unit cube's shell, every face counter-clockwise seen from outside.
const json kCubeShell = {{{0, 3, 2, 1}}, {{4, 5, 6, 7}}, {{0, 1, 5, 4}},
                         {{1, 2, 6, 5}}, {{2, 3, 7, 6}}, {{3, 0, 4, 7}}};

json object(json geometries) {
  return {{"type", "Building"}, {"geometry", std::move(geometries)}};
}

Result<Model> importText(const TempDir& dir, const std::string& text,
                         const ImportOptions& options = {},
                         const std::string& name = "m.city.json") {
  return importModel(dir.write(name, text), options);
}

const Mesh* meshNamed(const Model& m, const std::string& name) {
  for (const auto& mesh : m.meshes)
    if (mesh.name == name) return &mesh;
  return nullptr;
}

double signedVolume(const Model& m) {
  double v = 0.0;
  for (const auto& mesh : m.meshes)
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const auto &a = mesh.positions[mesh.indices[t]], &b = mesh.positions[mesh.indices[t + 1]],
                 &c = mesh.positions[mesh.indices[t + 2]];
      v += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
  return v;
}

#define EXPECT_ERROR_HAS(result, fragment)                                    \
  do {                                                                        \
    ASSERT_FALSE((result).ok()) << "expected an error with: " << (fragment);  \
    EXPECT_NE((result).message().find(fragment), std::string::npos)           \
        << "message: " << (result).message() << "\nexpected: " << (fragment); \
  } while (0)

TEST(CityJsonImport, AUnitCubeSolidGivesTwelveOutwardOneSidedTriangles) {
  TempDir dir;
  auto m = importText(
      dir,
      doc(kCube, {{"c", object({{{"type", "Solid"}, {"lod", "1"}, {"boundaries", {kCubeShell}}}})}})
          .dump());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->triangleCount(), 12u);
  EXPECT_EQ(m->format, "CityJSON 2.0");
  EXPECT_EQ(m->cityObjects, 1u);
  EXPECT_TRUE(m->zUp);
  EXPECT_NEAR(signedVolume(*m), 1.0, 1e-12);
  for (const auto& mesh : m->meshes) EXPECT_TRUE(mesh.oneSided) << mesh.name;
  // No semantics: the orientation colours the faces (top roof, bottom ground, sides walls).
  ASSERT_NE(meshNamed(*m, "roof (closed solids)"), nullptr);
  EXPECT_EQ(meshNamed(*m, "roof (closed solids)")->triangleCount(), 2u);
  EXPECT_EQ(meshNamed(*m, "ground (closed solids)")->triangleCount(), 2u);
  EXPECT_EQ(meshNamed(*m, "wall (closed solids)")->triangleCount(), 8u);
  const Aabb b = m->bounds();
  EXPECT_EQ(b.min, glm::dvec3(0.0));
  EXPECT_EQ(b.max, glm::dvec3(1.0));
}

TEST(CityJsonImport, EachTriangleKeepsItsCityObjectAsRunsPerMesh) {
  // Three cubes, each its own building: their triangles spread over the roof, wall and ground
  // meshes, and the runs say which building each came from.
  json vertices = json::array();
  for (int b = 0; b < 3; ++b)
    for (const auto& v : kCube) vertices.push_back({v[0].get<int>() + 3 * b, v[1], v[2]});
  json objects;
  for (int b = 0; b < 3; ++b) {
    json shell = kCubeShell;
    for (auto& face : shell)
      for (auto& ring : face)
        for (auto& i : ring) i = i.get<int>() + 8 * b;
    objects["b" + std::to_string(b)] =
        object({{{"type", "Solid"}, {"lod", "1"}, {"boundaries", {shell}}}});
  }
  TempDir dir;
  auto m = importText(dir, doc(vertices, objects).dump());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->cityObjects, 3u);
  std::vector<std::size_t> trianglesOf(3, 0);
  std::vector<std::vector<std::uint8_t>> covered(m->meshes.size());
  for (std::size_t k = 0; k < m->meshes.size(); ++k)
    covered[k].assign(m->meshes[k].triangleCount(), 0);
  for (const ObjectRun& r : m->objectRuns) {
    ASSERT_LT(r.object, 3u);
    ASSERT_LT(r.mesh, m->meshes.size());
    const Mesh& mesh = m->meshes[r.mesh];
    ASSERT_LE(r.firstTriangle + r.triangleCount, mesh.triangleCount());
    trianglesOf[r.object] += r.triangleCount;
    for (std::uint32_t t = r.firstTriangle; t < r.firstTriangle + r.triangleCount; ++t) {
      ++covered[r.mesh][t];
      // The object's cube: x in [3b, 3b + 1].
      for (int c = 0; c < 3; ++c) {
        const double x = mesh.positions[mesh.indices[3 * t + c]].x;
        EXPECT_GE(x, 3.0 * r.object);
        EXPECT_LE(x, 3.0 * r.object + 1.0);
      }
    }
  }
  EXPECT_EQ(trianglesOf, (std::vector<std::size_t>{12, 12, 12}));
  for (const auto& mesh : covered)
    for (std::uint8_t c : mesh) EXPECT_EQ(c, 1);
}

TEST(CityJsonImport, ASolidWoundInwardsIsTurnedOutwards) {
  json shell = kCubeShell;
  for (auto& surface : shell) std::reverse(surface[0].begin(), surface[0].end());
  TempDir dir;
  auto m = importText(
      dir, doc(kCube, {{"c", object({{{"type", "Solid"}, {"lod", 2}, {"boundaries", {shell}}}})}})
               .dump());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_NEAR(signedVolume(*m), 1.0, 1e-12);
  // Turned before it is coloured: the top is the roof.
  ASSERT_NE(meshNamed(*m, "roof (closed solids)"), nullptr);
  EXPECT_EQ(meshNamed(*m, "roof (closed solids)")->bounds().min.z, 1.0);
  ASSERT_EQ(m->warnings.size(), 1u);
  EXPECT_NE(m->warnings[0].find("1 solid shells wound inwards"), std::string::npos);
}

TEST(CityJsonImport, AnOpenSolidShellIsDrawnTwoSided) {
  json shell = kCubeShell;
  shell.erase(shell.begin());  // no bottom
  TempDir dir;
  auto m = importText(
      dir, doc(kCube, {{"c", object({{{"type", "Solid"}, {"lod", 2}, {"boundaries", {shell}}}})}})
               .dump());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->triangleCount(), 10u);
  for (const auto& mesh : m->meshes) EXPECT_FALSE(mesh.oneSided) << mesh.name;
}

TEST(CityJsonImport, AWallWithAWindowHoleGivesEightTriangles) {
  // A 10 x 6 wall in the plane y = 0 with a 2 x 2 window: 8 points, 1 hole -> 8 - 2 + 2.
  const json v = {{0, 0, 0}, {10, 0, 0}, {10, 0, 6}, {0, 0, 6},
                  {4, 0, 2}, {4, 0, 4},  {6, 0, 4},  {6, 0, 2}};
  const json g = {{"type", "MultiSurface"},
                  {"lod", "2"},
                  {"boundaries", {{{0, 1, 2, 3}, {4, 5, 6, 7}}}},
                  {"semantics", {{"surfaces", {{{"type", "WallSurface"}}}}, {"values", {0}}}}};
  TempDir dir;
  auto m = importText(dir, doc(v, {{"w", object(json::array({g}))}}).dump());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->triangleCount(), 8u);
  ASSERT_EQ(m->meshes.size(), 1u);
  EXPECT_EQ(m->meshes[0].name, "wall");
  EXPECT_FALSE(m->meshes[0].oneSided);  // a MultiSurface's winding is not trusted
  EXPECT_EQ(m->meshes[0].baseColor, surfaceColour(SurfaceClass::Wall));
}

TEST(CityJsonImport, AMaterialDiffuseColourIsChosenOverSemantics) {
  json d = doc(
      {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}},
      {{"r", object({{{"type", "MultiSurface"},
                      {"lod", "2"},
                      {"boundaries", {{{0, 1, 2}}}},
                      {"semantics", {{"surfaces", {{{"type", "RoofSurface"}}}}, {"values", {0}}}},
                      {"material", {{"paint", {{"values", {0}}}}}}}})}});
  d["appearance"] = {{"materials", {{{"name", "blue"}, {"diffuseColor", {0.1, 0.2, 0.9}}}}}};
  TempDir dir;
  auto m = importText(dir, d.dump());
  ASSERT_TRUE(m.ok()) << m.message();
  ASSERT_EQ(m->meshes.size(), 1u);
  EXPECT_EQ(m->meshes[0].name, "material blue");
  EXPECT_FLOAT_EQ(m->meshes[0].baseColor.b, 0.9f);
  // Without the material the roof palette colours it.
  d["CityObjects"]["r"]["geometry"][0].erase("material");
  auto r = importText(dir, d.dump());
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->meshes[0].name, "roof");
  EXPECT_EQ(r->meshes[0].baseColor, surfaceColour(SurfaceClass::Roof));
}

json twoLods() {
  // LoD 1: a unit square (2 triangles); LoD 2.2: a pentagon (3 triangles).
  return doc(
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 1.5, 0}},
      {{"b",
        object(
            {{{"type", "MultiSurface"}, {"lod", "1"}, {"boundaries", {{{0, 1, 2, 3}}}}},
             {{"type", "MultiSurface"}, {"lod", "2.2"}, {"boundaries", {{{0, 1, 2, 4, 3}}}}}})}});
}

TEST(CityJsonImport, TheHighestLodOfEachObjectIsTheDefault) {
  TempDir dir;
  auto m = importText(dir, twoLods().dump());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->triangleCount(), 3u);
  EXPECT_EQ(m->lod, "highest of each object (2.2)");
}

TEST(CityJsonImport, AChosenLodImportsOnlyThatLevel) {
  TempDir dir;
  ImportOptions one;
  one.lod = "1";
  auto m = importText(dir, twoLods().dump(), one);
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->triangleCount(), 2u);
  EXPECT_EQ(m->lod, "1");
  ImportOptions three;
  three.lod = "3";
  EXPECT_ERROR_HAS(importText(dir, twoLods().dump(), three),
                   "no city object has geometry at LoD 3");
}

TEST(CityJsonImport, GeometryInstancesPlaceTheirTemplateScaledAtTheReferencePoint) {
  SKIP_IF_SHARED_ABSENT("cityjson-v2/geometry_instance.city.json");
  // The conformance case instances a MultiPoint: nothing to draw, and a clear error says so.
  TempDir dir;
  EXPECT_ERROR_HAS(importModel(test::sharedData("cityjson-v2/geometry_instance.city.json")),
                   "no surfaces to triangulate (1 city objects");
  // With a unit square as the template: instance 0 scales it by 2 at (0,0,0), instance 1 keeps
  // it at (2,2,2).
  json d = readJson(test::sharedData("cityjson-v2/geometry_instance.city.json"));
  d["geometry-templates"]["templates"][0] = {
      {"type", "MultiSurface"}, {"lod", "1"}, {"boundaries", {{{0, 1, 2, 3}}}}};
  d["geometry-templates"]["vertices-templates"] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  auto m = importText(dir, d.dump());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->triangleCount(), 4u);
  const Aabb b = m->bounds();
  EXPECT_EQ(b.min, glm::dvec3(0, 0, 0));
  EXPECT_EQ(b.max, glm::dvec3(3, 3, 2));
}

TEST(CityJsonImport, ASolidWithSemanticsIsColouredByThemAndByItsFaces) {
  SKIP_IF_SHARED_ABSENT("cityjson-v2/geometry_semantics_solid.city.json");
  // A tetrahedron (0,0,0) (1,0,0) (0,1,0) (0,0,1), wound inwards in the file; three faces are
  // WallSurface, one has no semantics. Turned outwards: the "wall" at z = 0 faces down (ground),
  // the slanted one faces up (n.z = 0.58: roof), y = 0 stays a wall, and the unlabelled x = 0
  // face is a wall by its orientation.
  auto m = importModel(test::sharedData("cityjson-v2/geometry_semantics_solid.city.json"));
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->triangleCount(), 4u);
  EXPECT_NEAR(signedVolume(*m), 1.0 / 6.0, 1e-12);
  ASSERT_NE(meshNamed(*m, "ground (closed solids)"), nullptr);
  EXPECT_EQ(meshNamed(*m, "ground (closed solids)")->triangleCount(), 1u);
  EXPECT_EQ(meshNamed(*m, "roof (closed solids)")->triangleCount(), 1u);
  EXPECT_EQ(meshNamed(*m, "wall (closed solids)")->triangleCount(), 2u);
  EXPECT_EQ(meshNamed(*m, "ground (closed solids)")->bounds().max.z, 0.0);
  EXPECT_EQ(meshNamed(*m, "roof (closed solids)")->bounds().max.z, 1.0);
  EXPECT_LT(meshNamed(*m, "ground (closed solids)")->normals[0].z, -0.99f);
  EXPECT_EQ(m->bounds().max, glm::dvec3(1.0));
}

TEST(CityJsonImport, Wgs84CoordinatesBecomeEastNorthUpMetres) {
  SKIP_IF_SHARED_ABSENT("cityjson-v2/coordinates_precision_wgs84.city.json");
  // The case's five vertices are (lon, lat, h): (0,0,0), (180,90,10), (-180,-90,-10),
  // (180,-90,0), (-180,90,0); it has no surfaces and names no CRS, so the test adds EPSG:4979 and
  // the triangle equator - north pole (h 10) - south pole (h 0).
  json d = readJson(test::sharedData("cityjson-v2/coordinates_precision_wgs84.city.json"));
  d["metadata"] = {{"referenceSystem", "https://www.opengis.net/def/crs/EPSG/0/4979"}};
  d["CityObjects"] = {
      {"t", object({{{"type", "MultiSurface"}, {"lod", "1"}, {"boundaries", {{{0, 1, 3}}}}}})}};
  TempDir dir;
  auto m = importText(dir, d.dump());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->crs.epsg, 4979);
  EXPECT_TRUE(m->crs.toEnu);
  EXPECT_EQ(m->crs.originLat, 0.0);  // the centre of the data's box
  EXPECT_EQ(m->crs.originLon, 0.0);
  const Aabb b = m->bounds();
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(b.min[i]) && std::isfinite(b.max[i]));
  // North: from the south pole (-b) to the north pole (b + 10 m); up: the poles lie a (the
  // equatorial radius) below the origin's horizon. Metres, not degrees.
  const glm::dvec3 size = b.size();
  EXPECT_NEAR(size.x, 0.0, 1e-6);
  EXPECT_NEAR(size.y, 2.0 * kWgs84B + 10.0, 1e-3);
  EXPECT_NEAR(size.z, kWgs84A, 1e-3);
  bool warned = false;
  for (const auto& w : m->warnings) warned = warned || w.find("longitude, latitude") != w.npos;
  EXPECT_TRUE(warned) << "x past 90 degrees is read as longitude";
}

TEST(CityJsonImport, EcefCoordinatesBecomeEastNorthUpMetresAtTheDataCentre) {
  // A 10 m square on the ground at 52 N, 4 E, in ECEF.
  const EnuFrame frame(LatLon{52.0, 4.0, 0.0});
  json v = json::array();
  for (auto [e, n] : {std::pair{0.0, 0.0}, {10.0, 0.0}, {10.0, 10.0}, {0.0, 10.0}}) {
    const glm::dvec3 p = frame.toEcef({e, n, 0.0});
    v.push_back({p.x, p.y, p.z});
  }
  json d = doc(
      v, {{"s",
           object({{{"type", "MultiSurface"}, {"lod", "0"}, {"boundaries", {{{0, 1, 2, 3}}}}}})}});
  d["transform"]["scale"] = {1e-3, 1e-3, 1e-3};
  for (auto& p : d["vertices"])
    for (auto& c : p) c = std::llround(c.get<double>() * 1e3);
  d["metadata"] = {{"referenceSystem", "urn:ogc:def:crs:EPSG::4978"}};
  TempDir dir;
  auto m = importText(dir, d.dump());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_TRUE(m->crs.toEnu);
  EXPECT_NEAR(m->crs.originLat, 52.0, 1e-3);
  const glm::dvec3 size = m->bounds().size();
  EXPECT_NEAR(size.x, 10.0, 1e-2);
  EXPECT_NEAR(size.y, 10.0, 1e-2);
  EXPECT_NEAR(size.z, 0.0, 1e-2);
}

TEST(CityJsonImport, ReferenceSystemsOfEveryVersionNameTheirEpsgCode) {
  EXPECT_EQ(epsgFromReference("https://www.opengis.net/def/crs/EPSG/0/7415"), 7415);
  EXPECT_EQ(epsgFromReference("http://www.opengis.net/def/crs/EPSG/0/4979"), 4979);
  EXPECT_EQ(epsgFromReference("urn:ogc:def:crs:EPSG::28992"), 28992);
  EXPECT_EQ(epsgFromReference("EPSG:4326"), 4326);
  EXPECT_EQ(epsgFromReference("urn:ogc:def:crs:OGC:1.3:CRS84"), 0);
  EXPECT_EQ(epsgFromReference(""), 0);
  EXPECT_EQ(crsKind(4326), CrsKind::Geographic);
  EXPECT_EQ(crsKind(4978), CrsKind::Geocentric);
  EXPECT_EQ(crsKind(7415), CrsKind::Projected);
}

TEST(CityJsonImport, OldVersionsWithFloatVerticesAndArraySemanticsAreRead) {
  // 0.9 style: no transform, float vertices, "lod" a number, semantics per surface (0.x array
  // form, as in the Rotterdam example).
  const json d = {{"type", "CityJSON"},
                  {"version", "0.9"},
                  {"metadata", {{"crs", {{"epsg", 28992}}}}},
                  {"vertices", {{0.5, 0.5, 3.0}, {1.5, 0.5, 3.0}, {1.5, 1.5, 3.0}}},
                  {"CityObjects",
                   {{"r",
                     {{"type", "Building"},
                      {"geometry",
                       {{{"type", "MultiSurface"},
                         {"lod", 2},
                         {"boundaries", {{{0, 1, 2}}}},
                         {"semantics", {{{"type", "RoofSurface"}}}}}}}}}}}};
  TempDir dir;
  auto m = importText(dir, d.dump(), {}, "old.json");
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->format, "CityJSON 0.9");
  EXPECT_EQ(m->crs.epsg, 28992);
  EXPECT_FALSE(m->crs.toEnu);
  ASSERT_EQ(m->meshes.size(), 1u);
  EXPECT_EQ(m->meshes[0].name, "roof");
  EXPECT_EQ(m->bounds().min, glm::dvec3(0.5, 0.5, 3.0));
}

TEST(CityJsonImport, CityJsonIsRecognisedByNameAndByContent) {
  TempDir dir;
  EXPECT_TRUE(isMeshFile("a.city.json"));
  EXPECT_TRUE(isMeshFile("a.CityJSON"));
  EXPECT_TRUE(isMeshFile(dir.write("model.json", twoLods().dump())));
  EXPECT_FALSE(isMeshFile(dir.write("city.json", R"({"blocks": []})")));
  EXPECT_ERROR_HAS(importModel(dir.file("city.json")), "not CityJSON");
}

// ---- malformed input: an Error naming the file and the place, never a crash -------------------

TEST(CityJsonImport, MalformedFilesGiveErrorsThatNameTheProblem) {
  TempDir dir;
  const json quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  auto surfaces = [&](json boundaries, const std::string& type = "MultiSurface") {
    return doc(quad, {{"b", object({{{"type", type}, {"lod", "2"}, {"boundaries", boundaries}}})}})
        .dump();
  };
  const std::string good = surfaces({{{0, 1, 2, 3}}});
  ASSERT_TRUE(importText(dir, good).ok());

  EXPECT_ERROR_HAS(importText(dir, good.substr(0, good.size() / 2)), "not valid JSON");
  EXPECT_ERROR_HAS(importText(dir, surfaces({{{0, 1, 2, 3}}, {{0, 99, 2}}})),
                   "CityObjects[\"b\"].geometry[0].boundaries[1][0]: vertex index 99 out of "
                   "range (4 vertices)");
  // A huge index, as a file claiming far more vertices than it has would use.
  EXPECT_ERROR_HAS(importText(dir, surfaces({{{0, 1, 1099511627776LL}}})),
                   "vertex index 1099511627776 out of range (4 vertices)");
  EXPECT_ERROR_HAS(importText(dir, surfaces({{{0, 1, -1}}})), "vertex index -1 out of range");
  EXPECT_ERROR_HAS(importText(dir, surfaces({{{0, 1, 2.5}}})), "vertex index 2.5 is not a whole");
  // Wrong nesting: a MultiSurface's boundaries given to a Solid, and one level too many.
  EXPECT_ERROR_HAS(importText(dir, surfaces({{{0, 1, 2, 3}}}, "Solid")),
                   "boundaries[0][0][0]: expected a ring (an array of vertex indices), found a "
                   "number");
  EXPECT_ERROR_HAS(importText(dir, surfaces({{{{0, 1, 2, 3}}}})),
                   "boundaries[0][0]: expected a vertex index, found an array");
  EXPECT_ERROR_HAS(importText(dir, surfaces({1, 2})),
                   "boundaries[0]: expected a surface (an array of rings), found a number");

  json noTransform = json::parse(good);
  noTransform.erase("transform");
  EXPECT_ERROR_HAS(importText(dir, noTransform.dump()),
                   "transform: missing (CityJSON 2.0 requires it)");
  json noTransform10 = noTransform;
  noTransform10["version"] = "1.0";
  EXPECT_TRUE(importText(dir, noTransform10.dump()).ok()) << "1.0 may omit the transform";

  // NaN is not JSON; a number past double's range, or a scale that overflows, is not finite.
  std::string nan = good;
  nan.replace(nan.find("[0,0,0]"), 7, "[NaN,0,0]");
  EXPECT_ERROR_HAS(importText(dir, nan), "not valid JSON");
  std::string huge = good;
  huge.replace(huge.find("[0,0,0]"), 7, "[1e400,0,0]");
  EXPECT_ERROR_HAS(importText(dir, huge), "not valid JSON: number overflow parsing '1e400'");
  json overflow = json::parse(good);
  overflow["transform"]["scale"] = {1e308, 1.0, 1.0};
  overflow["vertices"][1] = {10, 0, 0};
  EXPECT_ERROR_HAS(importText(dir, overflow.dump()), "vertices[1][0]: coordinate is not finite");

  json pastPole = json::parse(good);
  pastPole["metadata"] = {{"referenceSystem", "urn:ogc:def:crs:EPSG::4326"}};
  pastPole["vertices"][3] = {95, 100, 0};  // neither coordinate can be a latitude
  EXPECT_ERROR_HAS(importText(dir, pastPole.dump()),
                   "vertices[3]: latitude past 90 degrees in geographic EPSG:4326");

  EXPECT_ERROR_HAS(importText(dir, std::string(200, '[') + std::string(200, ']')),
                   "JSON nested deeper than 128 levels");
  json notType = json::parse(good);
  notType["type"] = "FeatureCollection";
  EXPECT_ERROR_HAS(importText(dir, notType.dump()), "not a CityJSON file");
  json version = json::parse(good);
  version["version"] = "3.1";
  EXPECT_ERROR_HAS(importText(dir, version.dump()), "unsupported CityJSON version \"3.1\"");
  json objects = json::parse(good);
  objects["CityObjects"] = json::array();
  EXPECT_ERROR_HAS(importText(dir, objects.dump()), "CityObjects: missing (or not an object)");
  json badVertex = json::parse(good);
  badVertex["vertices"][2] = {1, "x", 0};
  EXPECT_ERROR_HAS(importText(dir, badVertex.dump()),
                   "vertices[2][1]: expected a number, found a string");
  json instance = json::parse(good);
  instance["CityObjects"]["b"]["geometry"][0] = {
      {"type", "GeometryInstance"}, {"template", 3}, {"boundaries", {0}}};
  EXPECT_ERROR_HAS(importText(dir, instance.dump()), "geometry[0].template: not the index");
}

TEST(CityJsonImport, DegenerateSurfacesAreSkippedWithACountedWarning) {
  TempDir dir;
  const json v = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}};
  auto m = importText(
      dir, doc(v, {{"b", object({{{"type", "MultiSurface"},
                                  {"lod", "2"},
                                  {"boundaries", {{{0, 1, 2}}, {{0, 1, 3}}, {{0, 0, 1, 1}}}}}})}})
               .dump());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->triangleCount(), 1u);
  ASSERT_FALSE(m->warnings.empty());
  EXPECT_NE(m->warnings[0].find("2 surfaces without area skipped"), std::string::npos);
}

// ---- shared data --------------------------------------------------------------------------

// Each CityJSON 2.0 conformance case: the triangles it gives, or the error it must give. Most
// cases test one feature on vertices along a line (no surface has area) or have no surfaces.
TEST(CityJsonImport, EveryConformanceCaseImportsOrGivesItsExpectedError) {
  SKIP_IF_SHARED_ABSENT("cityjson-v2");
  const std::string none = "no surfaces to triangulate";
  const std::string flat = "surfaces have no area";
  const std::map<std::string, std::string> expected = {
      {"appearance_complete", "4"},
      {"cityjson_extended", none},
      {"cityjson_fake_complete", "17"},
      {"cityjson_minimal", none},
      {"cityobject_all_types", none},
      {"cityobject_building_address", none},
      {"cityobject_complete", none},
      {"cityobject_extended", none},
      {"coordinates_precision_ecef", none},
      {"coordinates_precision_local", none},
      {"coordinates_precision_stateplane", none},
      {"coordinates_precision_utm", none},
      {"coordinates_precision_wgs84", none},
      {"coordinates_precision_worst", none},
      {"extension", none},
      {"geometry_instance", none},
      {"geometry_material_multisolid", "8"},
      {"geometry_material_multisurface", "4"},
      {"geometry_material_solid", "4"},
      {"geometry_semantics_multilinestring", none},
      {"geometry_semantics_multipoint", none},
      {"geometry_semantics_multisolid", "8"},
      {"geometry_semantics_multisurface", flat},
      {"geometry_semantics_solid", "4"},
      {"geometry_texture_multisolid", flat},
      {"geometry_texture_multisurface", flat},
      {"geometry_texture_solid", flat},
      {"metadata_complete", none},
      {"metadata_extra_properties", none},
      {"semantic_all_types", flat},
      {"semantic_complete", flat},
      {"semantic_extended", flat},
      {"vertices", none},
  };
  std::size_t seen = 0, imported = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::sharedData("cityjson-v2"))) {
    std::string name = entry.path().filename().string();
    name = name.substr(0, name.find('.'));
    const auto it = expected.find(name);
    if (it == expected.end()) {
      ADD_FAILURE() << "a conformance case this test does not know: " << name;
      continue;
    }
    ++seen;
    EXPECT_TRUE(isMeshFile(entry.path())) << name;
    auto m = importModel(entry.path());
    if (std::isdigit(static_cast<unsigned char>(it->second[0]))) {
      ASSERT_TRUE(m.ok()) << name << ": " << m.message();
      EXPECT_EQ(m->triangleCount(), std::stoul(it->second)) << name;
      ++imported;
    } else {
      EXPECT_ERROR_HAS(m, it->second);
      if (!m.ok()) {
        EXPECT_NE(m.message().find(entry.path().string()), std::string::npos);
      }
    }
  }
  EXPECT_EQ(seen, expected.size());
  std::printf("[ cityjson ] %zu conformance cases: %zu import, %zu give their expected error\n",
              seen, imported, seen - imported);
}

TEST(CityJsonImport, RotterdamDelfshavenImportsItsBuildingsWithRoofsOnTop) {
  SKIP_IF_SHARED_ABSENT("rotterdam-delfshaven.cityjson.json");
  const auto start = std::chrono::steady_clock::now();
  auto m = importModel(test::sharedData("rotterdam-delfshaven.cityjson.json"));
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(m.ok()) << m.message();
  std::printf("[ import   ] rotterdam-delfshaven: %zu meshes, %zu triangles in %.1f ms\n",
              m->meshes.size(), m->triangleCount(), ms);
  EXPECT_EQ(m->format, "CityJSON 0.2");
  EXPECT_EQ(m->cityObjects, 853u);
  EXPECT_EQ(m->crs.epsg, 7415);
  EXPECT_FALSE(m->crs.toEnu);
  // 38,772 triangles if every ring of n points gave n - 2; 725 surfaces have no area (722 are
  // two points, each repeated) and are skipped.
  EXPECT_GE(m->triangleCount(), 37000u);
  EXPECT_LE(m->triangleCount(), 38800u);
  const Mesh* roof = meshNamed(*m, "roof");
  const Mesh* ground = meshNamed(*m, "ground");
  ASSERT_NE(roof, nullptr);
  ASSERT_NE(ground, nullptr);
  EXPECT_EQ(roof->baseColor, surfaceColour(SurfaceClass::Roof));
  EXPECT_GT(roof->triangleCount(), 5000u);
  // Roofs face up and lie above the ground surfaces.
  double nz = 0.0;
  for (const auto& n : roof->normals) nz += n.z;
  EXPECT_GT(nz / double(roof->normals.size()), 0.5);
  EXPECT_GT(roof->bounds().centre().z, ground->bounds().centre().z + 5.0);
  const Aabb b = m->bounds();
  EXPECT_NEAR(b.size().x, 1044.56, 0.01);  // metres of RD New (EPSG:28992 in 7415)
  EXPECT_NEAR(b.size().z, 41.158, 0.01);
}

}  // namespace
}  // namespace hlod
