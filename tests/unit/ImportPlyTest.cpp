// PLY import and writePly: hand-made files in every encoding, exact values, broken files.
#include <gtest/gtest.h>
#include <unistd.h>

#include "ImportTestUtil.h"
#include "hlod/export/PlyWriter.h"
#include "hlod/import/Import.h"

namespace hlod {
namespace {

using testing::putBytes;
using testing::TempDir;

const std::string kAsciiQuad =
    "ply\n"
    "format ascii 1.0\n"
    "comment a unit quad with an unknown property and element\n"
    "element vertex 4\n"
    "property float x\nproperty float y\nproperty float z\n"
    "property uchar red\n"
    "property float s\nproperty float t\n"
    "element face 1\n"
    "property list uchar int vertex_indices\n"
    "element edge 1\n"
    "property int vertex1\nproperty int vertex2\n"
    "end_header\n"
    "0 0 0 255 0 0\n"
    "1 0 0 255 1 0\n"
    "1 1 0 255 1 1\n"
    "0 1 0 255 0 0.25\n"
    "4 0 1 2 3\n"
    "0 1\n";

TEST(PlyImport, ReadsAsciiQuadAsTwoTrianglesWithFlippedV) {
  TempDir dir;
  auto model = importModel(dir.write("quad.ply", kAsciiQuad));
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_EQ(model->meshes.size(), 1u);
  const Mesh& m = model->meshes[0];
  EXPECT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(m.positions[2], glm::dvec3(1, 1, 0));
  ASSERT_EQ(m.texCoords.size(), 4u);
  EXPECT_FLOAT_EQ(m.texCoords[1].x, 1.0f);
  EXPECT_FLOAT_EQ(m.texCoords[1].y, 1.0f);  // v = 0 (bottom) -> 1
  EXPECT_FLOAT_EQ(m.texCoords[3].y, 0.75f);
  EXPECT_TRUE(m.normals.empty());
  EXPECT_EQ(m.name, "quad");
}

// Builds a binary PLY with double coordinates, normals, u/v and a uint index list.
std::string binaryPly(bool big, const std::vector<glm::dvec3>& pts, int faceIndexOffset = 0) {
  std::string s = std::string("ply\nformat ") +
                  (big ? "binary_big_endian" : "binary_little_endian") + " 1.0\nelement vertex " +
                  std::to_string(pts.size()) +
                  "\nproperty double x\nproperty double y\nproperty double z\n"
                  "property float nx\nproperty float ny\nproperty float nz\n"
                  "property short flags\n"
                  "property float u\nproperty float v\n"
                  "element face 1\nproperty uchar intensity\n"
                  "property list uchar uint vertex_indices\nend_header\n";
  for (std::size_t i = 0; i < pts.size(); ++i) {
    putBytes(s, pts[i].x, big);
    putBytes(s, pts[i].y, big);
    putBytes(s, pts[i].z, big);
    putBytes(s, 0.0f, big);
    putBytes(s, 0.0f, big);
    putBytes(s, 1.0f, big);
    putBytes(s, std::int16_t(-7), big);
    putBytes(s, 0.5f, big);
    putBytes(s, 0.25f, big);
  }
  putBytes(s, std::uint8_t(9), big);
  putBytes(s, std::uint8_t(3), big);
  for (int i = 0; i < 3; ++i) putBytes(s, std::uint32_t(i + faceIndexOffset), big);
  return s;
}

const std::vector<glm::dvec3> kFarPoints = {
    {6378137.123456789, -0.1, 1e-300}, {6378138.000000001, 2.5, 3.0}, {1.0 / 3.0, 7.0, -9.0}};

TEST(PlyImport, KeepsDoublePrecisionCoordinatesInBothEndiannesses) {
  for (bool big : {false, true}) {
    TempDir dir;
    auto model = importModel(dir.write("far.ply", binaryPly(big, kFarPoints)));
    ASSERT_TRUE(model.ok()) << model.message();
    const Mesh& m = model->meshes[0];
    ASSERT_EQ(m.positions.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(m.positions[i], kFarPoints[i]) << "big=" << big;
    EXPECT_EQ(m.positions[0].x, 6378137.123456789);
    ASSERT_EQ(m.normals.size(), 3u);
    EXPECT_EQ(m.normals[1], glm::vec3(0, 0, 1));
    ASSERT_EQ(m.texCoords.size(), 3u);
    EXPECT_EQ(m.texCoords[0], glm::vec2(0.5f, 0.75f));
    EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2}));
  }
}

TEST(PlyImport, AcceptsVertexIndexNameAndOtherListTypes) {
  TempDir dir;
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 5\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list ushort short vertex_index\nend_header\n";
  for (int i = 0; i < 5; ++i) {
    putBytes(s, float(i));
    putBytes(s, float(i * i));
    putBytes(s, 0.0f);
  }
  putBytes(s, std::uint16_t(5));
  for (int i = 0; i < 5; ++i) putBytes(s, std::int16_t(i));
  auto model = importModel(dir.write("pent.ply", s));
  ASSERT_TRUE(model.ok()) << model.message();
  EXPECT_EQ(model->triangleCount(), 3u);
  EXPECT_EQ(model->meshes[0].indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4}));
  EXPECT_EQ(model->meshes[0].positions[4], glm::dvec3(4, 16, 0));
}

TEST(PlyImport, RejectsTruncatedBinaryFileNamingIt) {
  TempDir dir;
  std::string s = binaryPly(false, kFarPoints);
  auto model = importModel(dir.write("cut.ply", s.substr(0, s.size() - 6)));
  ASSERT_FALSE(model.ok());
  EXPECT_NE(model.message().find("cut.ply"), std::string::npos) << model.message();
}

TEST(PlyImport, RejectsFaceIndexOutOfRange) {
  TempDir dir;
  auto model = importModel(dir.write("bad.ply", binaryPly(true, kFarPoints, 1)));
  ASSERT_FALSE(model.ok());
  EXPECT_NE(model.message().find("bad.ply"), std::string::npos);
  EXPECT_NE(model.message().find("face index 3 out of range (3 vertices)"), std::string::npos)
      << model.message();
}

TEST(PlyImport, RejectsNanCoordinateNamingTheVertex) {
  TempDir dir;
  std::string s = kAsciiQuad;
  s.replace(s.find("1 1 0 255"), 9, "1 nan 0 255");
  auto model = importModel(dir.write("nan.ply", s));
  ASSERT_FALSE(model.ok());
  EXPECT_NE(model.message().find("nan.ply: vertex 2"), std::string::npos) << model.message();
}

TEST(PlyImport, RejectsAbsurdVertexCountBeforeAllocating) {
  TempDir dir;
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  s += std::string(1000, '\0');
  auto model = importModel(dir.write("huge.ply", s));
  ASSERT_FALSE(model.ok());
  EXPECT_NE(model.message().find("huge.ply"), std::string::npos);
  EXPECT_NE(model.message().find("1000000000000"), std::string::npos) << model.message();
}

// Found by the ply fuzz target (corpus/ply/crash-propertyless-face-count-reserved-48gb.ply): a
// face element without properties takes no bytes, so its count passed the size check, and the
// reader reserved room for 4294967295 faces (48 GB) and failed as "out of memory".
TEST(PlyImport, AFaceElementWithoutPropertiesReservesNothingForItsCount) {
  TempDir dir;
  for (const char* format : {"ascii", "binary_little_endian"}) {
    const std::string s =
        std::string("ply\nformat ") + format + " 1.0\nelement face 4294967295\nend_header\n0 0 0\n";
    auto model = importModel(dir.write("faces.ply", s));
    ASSERT_FALSE(model.ok()) << format;
    EXPECT_EQ(model.message().find("out of memory"), std::string::npos) << model.message();
    EXPECT_NE(model.message().find("no 'vertex' element"), std::string::npos) << model.message();
  }
}

TEST(PlyImport, RejectsAsciiGarbageAndMissingHeaderEnd) {
  TempDir dir;
  std::string bad = kAsciiQuad;
  bad.replace(bad.find("4 0 1 2 3"), 9, "4 0 1 x 3");
  auto a = importModel(dir.write("garbage.ply", bad));
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.message().find("garbage.ply: line 21"), std::string::npos) << a.message();
  auto b = importModel(dir.write("nohead.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"));
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.message().find("nohead.ply"), std::string::npos);
  auto c = importModel(dir.write("notply.ply", std::string("\x01\x02\xff garbage", 11)));
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.message().find("notply.ply"), std::string::npos);
}

TEST(PlyImport, RejectsMeshWithoutTriangles) {
  TempDir dir;
  std::string s = kAsciiQuad;
  s.replace(s.find("4 0 1 2 3"), 9, "2 0 1    ");
  auto model = importModel(dir.write("lines.ply", s));
  ASSERT_FALSE(model.ok());
  EXPECT_NE(model.message().find("lines.ply: mesh has no triangles"), std::string::npos)
      << model.message();
}

TEST(PlyWriter, RoundTripsDoublesNormalsAndTexCoordsExactly) {
  TempDir dir;
  Mesh mesh;
  mesh.positions = {{6378137.123456789, 1e-12, -4.0000000000000001},
                    {-6378137.987654321, 0.1, 0.2},
                    {3.0, 4.0, 5.0},
                    {1.0 / 7.0, 2.0 / 3.0, 1e17}};
  mesh.normals = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}, {0.6f, 0.8f, 0}};
  mesh.texCoords = {{0, 0}, {1, 0}, {0.5f, 0.75f}, {0.125f, 1.0f}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  const auto path = dir.file("block.ply");
  auto status = writePly(path, mesh);
  ASSERT_TRUE(status.ok()) << status.message();
  auto back = importModel(path);
  ASSERT_TRUE(back.ok()) << back.message();
  ASSERT_EQ(back->meshes.size(), 1u);
  const Mesh& m = back->meshes[0];
  EXPECT_EQ(m.positions, mesh.positions);
  EXPECT_EQ(m.normals, mesh.normals);
  EXPECT_EQ(m.texCoords, mesh.texCoords);
  EXPECT_EQ(m.indices, mesh.indices);
  EXPECT_FALSE(m.texture);
}

TEST(PlyWriter, RoundTripsWithoutOptionalAttributes) {
  TempDir dir;
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  ASSERT_TRUE(writePly(dir.file("t.ply"), mesh).ok());
  auto back = importModel(dir.file("t.ply"));
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(back->meshes[0].normals.empty());
  EXPECT_TRUE(back->meshes[0].texCoords.empty());
  EXPECT_EQ(back->meshes[0].positions, mesh.positions);
}

TEST(PlyWriter, RejectsInconsistentArrays) {
  TempDir dir;
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.normals = {{0, 0, 1}};
  mesh.indices = {0, 1, 2};
  EXPECT_FALSE(writePly(dir.file("x.ply"), mesh).ok());
}

TEST(PlyWriter, WritesTextureFileCommentThatTheReaderLoads) {
  TempDir dir;
  // A 2x1 PPM: red, blue.
  dir.write("facade.ppm", std::string("P6\n2 1\n255\n") + std::string("\xff\0\0\0\0\xff", 6));
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.texCoords = {{0, 0}, {1, 0}, {0, 1}};
  mesh.indices = {0, 1, 2};
  ASSERT_TRUE(writePly(dir.file("block.ply"), mesh, "facade.ppm").ok());
  auto back = importModel(dir.file("block.ply"));
  ASSERT_TRUE(back.ok()) << back.message();
  ASSERT_TRUE(back->meshes[0].texture);
  EXPECT_EQ(back->meshes[0].texture->pixels,
            (std::vector<std::uint8_t>{255, 0, 0, 255, 0, 0, 255, 255}));
  EXPECT_EQ(back->meshes[0].texCoords, mesh.texCoords);
}

TEST(PlyWriter, FailsOnUnwritablePath) {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  auto status = writePly("/nonexistent-dir/x.ply", mesh);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("/nonexistent-dir/x.ply"), std::string::npos);
}

}  // namespace
}  // namespace hlod
