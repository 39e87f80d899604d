// Mesh import of OFF, STL, OBJ and glTF, and loadImage: hand-made files with exact expectations,
// and broken files that must give an Error naming the file (never a crash).
#include "hlod/export/ImageWriter.h"
#include "hlod/import/Import.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <tuple>

#include "ImportTestUtil.h"

namespace hlod {
namespace {

using testing::putBytes;
using testing::TempDir;

template <class T>
bool mentions(const Result<T>& r, const std::string& text) {
  return !r.ok() && r.message().find(text) != std::string::npos;
}

// ---- dispatch and generic failures ----

TEST(Import, RecognisesMeshExtensionsCaseInsensitively) {
  EXPECT_TRUE(isMeshFile("a.OBJ"));
  EXPECT_TRUE(isMeshFile("dir/b.ply"));
  EXPECT_TRUE(isMeshFile("c.Glb"));
  EXPECT_TRUE(isMeshFile("d.gltf"));
  EXPECT_TRUE(isMeshFile("e.off"));
  EXPECT_TRUE(isMeshFile("f.stl"));
  EXPECT_FALSE(isMeshFile("g.fbx"));
  EXPECT_FALSE(isMeshFile("noext"));
}

TEST(Import, RejectsUnknownExtensionNamingTheFile) {
  TempDir dir;
  auto model = importModel(dir.write("thing.fbx", "whatever"));
  EXPECT_TRUE(mentions(model, "thing.fbx: unknown mesh format")) << model.message();
}

TEST(Import, RejectsMissingAndEmptyFilesOfEveryFormat) {
  TempDir dir;
  for (std::string ext : {".obj", ".ply", ".off", ".stl", ".gltf", ".glb"}) {
    auto missing = importModel(dir.file("nothere" + ext));
    EXPECT_TRUE(mentions(missing, "nothere" + ext + ": ")) << missing.message();
    auto empty = importModel(dir.write("empty" + ext, ""));
    EXPECT_TRUE(mentions(empty, "empty" + ext + ": ")) << ext;
  }
}

TEST(Import, RejectsGarbageBytesOfEveryFormatWithoutCrashing) {
  TempDir dir;
  std::string garbage;
  unsigned state = 12345;
  for (int i = 0; i < 4096; ++i) {
    state = state * 1103515245u + 12345u;
    garbage.push_back(static_cast<char>(state >> 16));
  }
  for (std::string ext : {".obj", ".ply", ".off", ".stl", ".gltf", ".glb"}) {
    auto model = importModel(dir.write("garbage" + ext, garbage));
    EXPECT_TRUE(mentions(model, "garbage" + ext + ": ")) << ext;
  }
}

// ---- OFF ----

TEST(OffImport, ReadsCommentsQuadsAndTriangles) {
  TempDir dir;
  auto model = importModel(dir.write("shape.off",
                                     "OFF\n# a comment\n5 2 0\n"
                                     "0 0 0\n1 0 0\n1 1 0\n0 1 0 # trailing comment\n"
                                     "0.5 0.5 6378137.123456789\n"
                                     "4 0 1 2 3\n3 0 1 4 255 0 0\n"));
  ASSERT_TRUE(model.ok()) << model.message();
  const Mesh& m = model->meshes[0];
  EXPECT_EQ(m.positions.size(), 5u);
  EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 1, 4}));
  EXPECT_EQ(m.positions[4].z, 6378137.123456789);
}

TEST(OffImport, ReadsCountsOnKeywordLineAndColouredAndNormalVariants) {
  TempDir dir;
  auto coff =
      importModel(dir.write("c.off",
                            "COFF 3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n"
                            "3 0 1 2\n"));
  ASSERT_TRUE(coff.ok()) << coff.message();
  EXPECT_EQ(coff->meshes[0].positions[1], glm::dvec3(1, 0, 0));
  auto noff = importModel(
      dir.write("n.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 1 0\n3 0 1 2\n"));
  ASSERT_TRUE(noff.ok()) << noff.message();
  ASSERT_EQ(noff->meshes[0].normals.size(), 3u);
  EXPECT_EQ(noff->meshes[0].normals[2], glm::vec3(0, 1, 0));
  auto st = importModel(dir.write("st.off",
                                  "STCOFF\n3 1 0\n0 0 0 1 1 1 1 0 0.25\n1 0 0 1 1 1 1 1 0\n"
                                  "0 1 0 1 1 1 1 0 1\n3 0 1 2\n"));
  ASSERT_TRUE(st.ok()) << st.message();
  ASSERT_EQ(st->meshes[0].texCoords.size(), 3u);
  EXPECT_EQ(st->meshes[0].texCoords[0], glm::vec2(0.0f, 0.75f));
}

TEST(OffImport, RejectsBadFaceIndexWithLineNumber) {
  TempDir dir;
  auto model = importModel(dir.write("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 40000\n"));
  EXPECT_TRUE(mentions(model, "bad.off: line 6: face index 40000 out of range (3 vertices)"))
      << model.message();
}

TEST(OffImport, RejectsTruncatedFileNanAndAbsurdCounts) {
  TempDir dir;
  auto cut = importModel(dir.write("cut.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1"));
  EXPECT_TRUE(mentions(cut, "cut.off: ")) << cut.message();
  auto nan = importModel(dir.write("nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"));
  EXPECT_TRUE(mentions(nan, "nan.off: vertex 1 has a non-finite coordinate")) << nan.message();
  auto inf = importModel(dir.write("inf.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 1e999\n3 0 1 2\n"));
  EXPECT_TRUE(mentions(inf, "inf.off: vertex 2")) << inf.message();
  auto huge = importModel(dir.write("huge.off", "OFF\n1000000000000 1 0\n0 0 0\n"));
  EXPECT_TRUE(mentions(huge, "huge.off: header claims 1000000000000 vertices")) << huge.message();
  auto none = importModel(dir.write("none.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"));
  EXPECT_TRUE(mentions(none, "none.off: mesh has no triangles")) << none.message();
}

// ---- STL ----

std::string binaryStl(const std::string& header80, int triangles, bool twoSharing = true) {
  std::string s = header80;
  s.resize(80, ' ');
  putBytes(s, std::uint32_t(triangles));
  const float tris[2][9] = {{0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, 0}};
  for (int t = 0; t < triangles; ++t) {
    for (int k = 0; k < 3; ++k) putBytes(s, 0.0f);  // normal
    for (int k = 0; k < 9; ++k) putBytes(s, twoSharing ? tris[t % 2][k] : tris[0][k] + t);
    putBytes(s, std::uint16_t(0));
  }
  return s;
}

TEST(StlImport, ReadsBinaryEvenWhenHeaderSaysSolidAndMergesVertices) {
  TempDir dir;
  auto model = importModel(dir.write("quad.stl", binaryStl("solid but binary", 2)));
  ASSERT_TRUE(model.ok()) << model.message();
  const Mesh& m = model->meshes[0];
  EXPECT_EQ(m.triangleCount(), 2u);
  EXPECT_EQ(m.positions.size(), 4u);  // 6 corners, 2 shared
  EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(m.positions[3], glm::dvec3(0, 1, 0));
}

TEST(StlImport, ReadsAsciiAndMergesVertices) {
  TempDir dir;
  const std::string ascii =
      "solid quad\n"
      "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n"
      "      vertex 1 1 0\n    endloop\n  endfacet\n"
      "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 1 0\n"
      "      vertex 0 1 -0\n    endloop\n  endfacet\n"
      "endsolid quad\n";
  auto model = importModel(dir.write("quad.stl", ascii));
  ASSERT_TRUE(model.ok()) << model.message();
  EXPECT_EQ(model->meshes[0].positions.size(), 4u);
  EXPECT_EQ(model->meshes[0].indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  auto cut = importModel(dir.write("cut.stl", ascii.substr(0, ascii.size() / 2)));
  EXPECT_TRUE(mentions(cut, "cut.stl: ")) << cut.message();
  auto noEnd = importModel(dir.write("noend.stl", ascii.substr(0, ascii.find("endsolid"))));
  EXPECT_TRUE(mentions(noEnd, "noend.stl: unexpected end of file")) << noEnd.message();
}

TEST(StlImport, RejectsTruncatedBinaryByItsSize) {
  TempDir dir;
  std::string s = binaryStl("solid exporter", 3, false);
  auto model = importModel(dir.write("cut.stl", s.substr(0, s.size() - 20)));
  EXPECT_TRUE(mentions(model, "cut.stl: binary STL header claims 3 triangles")) << model.message();
  auto tiny = importModel(dir.write("tiny.stl", "abc"));
  EXPECT_TRUE(mentions(tiny, "tiny.stl: ")) << tiny.message();
}

TEST(StlImport, RejectsNanCoordinate) {
  TempDir dir;
  std::string s = binaryStl("x", 1);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&s[84 + 12 + 12], &nan, 4);  // second corner x
  auto model = importModel(dir.write("nan.stl", s));
  EXPECT_TRUE(mentions(model, "nan.stl: vertex 1 has a non-finite coordinate")) << model.message();
}

// ---- OBJ ----

// A 3x1-pixel PPM: red, green, blue (OpenImageIO and stb_image both read PNM).
const std::string kPpm =
    std::string("P6\n3 1\n255\n") + std::string("\xff\x00\x00\x00\xff\x00\x00\x00\xff", 9);

// 20,000 usemtl names over three colours: the materials that draw alike are one mesh each (they
// were 20,000 meshes, one draw call each, and the name lookup was quadratic).
TEST(ObjImport, ManyMaterialNamesOfFewColoursBecomeOneMeshPerColour) {
  TempDir dir;
  std::string mtl, obj = "mtllib m.mtl\n";
  const char* colours[3] = {"1 0 0", "0 1 0", "0 0 1"};
  constexpr int kNames = 20000;
  for (int i = 0; i < kNames; ++i) {
    mtl += "newmtl m" + std::to_string(i) + "\nKd " + colours[i % 3] + "\n";
    obj += "v " + std::to_string(i) + " 0 0\nv " + std::to_string(i) + " 1 0\nv " +
           std::to_string(i) + " 0 1\nusemtl m" + std::to_string(i) + "\nf -3 -2 -1\n";
  }
  dir.write("m.mtl", mtl);
  auto model = importModel(dir.write("many.obj", obj));
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_EQ(model->meshes.size(), 3u);
  std::size_t triangles = 0;
  for (const Mesh& m : model->meshes) {
    triangles += m.triangleCount();
    EXPECT_EQ(m.triangleCount(), m.baseColor.b > 0.5f ? 6666u : 6667u);  // i % 3 of 0..19999
  }
  EXPECT_EQ(triangles, std::size_t(kNames));
  // The triangles keep their own corners: the last red one is where the file put it.
  const Mesh& red = model->meshes[0];
  EXPECT_EQ(red.baseColor, glm::vec4(1, 0, 0, 1));
  EXPECT_EQ(red.positions[red.indices.back()], glm::dvec3(kNames - 2, 0, 1));
}

TEST(ObjImport, ReadsAllIndexFormsNegativeIndicesAndTriangulatesQuads) {
  TempDir dir;
  auto model = importModel(dir.write("quad.obj",
                                     "# quad\n"
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 6378137.123456789\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                     "vn 0 0 1\n"
                                     "f -4/-4/-1 -3/-3/-1 -2/-2/-1 -1/-1/-1\n"
                                     "f 1/1/1 3/3/1 4/4/1\n"));
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_EQ(model->meshes.size(), 1u);
  const Mesh& m = model->meshes[0];
  EXPECT_EQ(m.positions.size(), 4u);  // the second face reuses the (v, vt, vn) tuples
  EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 2, 3}));
  EXPECT_EQ(m.positions[3].z, 6378137.123456789);
  ASSERT_EQ(m.texCoords.size(), 4u);
  EXPECT_EQ(m.texCoords[1], glm::vec2(1, 1));  // OBJ v = 0 is the bottom: flipped to 1
  EXPECT_EQ(m.texCoords[3], glm::vec2(0, 0));
  ASSERT_EQ(m.normals.size(), 4u);
  EXPECT_EQ(m.normals[0], glm::vec3(0, 0, 1));
}

TEST(ObjImport, SplitsVerticesThatDifferInTexCoordOrNormal) {
  TempDir dir;
  auto model =
      importModel(dir.write("seam.obj",
                            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
                            "f 1/1 2/2 3/3\nf 1/4 3/3 2/2\nf 1/a/1 2 3\n"));
  ASSERT_FALSE(model.ok());
  EXPECT_TRUE(mentions(model, "seam.obj: line 10: bad face corner")) << model.message();
  auto ok = importModel(dir.write("seam2.obj",
                                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
                                  "f 1/1 2/2 3/3\nf 1/4 3/3 2/2\nf 1 2 3\n"));
  ASSERT_TRUE(ok.ok()) << ok.message();
  // (1,1) (2,2) (3,3) (1,4) and the three texture-less corners: 7 vertices.
  EXPECT_EQ(ok->meshes[0].positions.size(), 7u);
  EXPECT_EQ(ok->meshes[0].texCoords.size(), 7u);
  EXPECT_TRUE(ok->meshes[0].normals.empty());
}

// A texture wider than GL draws (16384 on llvmpipe and most GPUs) was drawn black with exit 0:
// it is resized to fit, with a warning that names it.
TEST(ObjImport, ATextureWiderThanGlDrawsIsResizedWithAWarning) {
  TempDir dir;
  Image wide;
  wide.width = 16400;
  wide.height = 2;
  wide.pixels.assign(std::size_t(wide.width) * wide.height * 4, 200);
  ASSERT_TRUE(writeImageFile(dir.file("wide.png"), wide, {.alpha = true}).ok());
  dir.write("m.mtl", "newmtl w\nKd 1 1 1\nmap_Kd wide.png\n");
  auto model = importModel(dir.write("w.obj",
                                     "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n"
                                     "vt 0 1\nusemtl w\nf 1/1 2/2 3/3\n"));
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_EQ(model->meshes.size(), 1u);
  ASSERT_TRUE(model->meshes[0].texture);
  EXPECT_EQ(model->meshes[0].texture->width, 16384);
  EXPECT_EQ(model->meshes[0].texture->height, 1);
  EXPECT_EQ(model->meshes[0].texture->pixels[0], 200);
  ASSERT_EQ(model->warnings.size(), 1u);
  EXPECT_NE(model->warnings[0].find("16400x2"), std::string::npos) << model->warnings[0];
  EXPECT_NE(model->warnings[0].find("resized to 16384x1"), std::string::npos);
}

TEST(ObjImport, MakesOneMeshPerMaterialWithColourAndTexture) {
  TempDir dir;
  dir.write("tex.ppm", kPpm);
  dir.write("mats.mtl",
            "newmtl red\nKd 1 0 0\n\nnewmtl textured\nKd 0.5 0.5 0.5\nmap_Kd -s 1 1 1 tex.ppm\n"
            "newmtl lost\nKd 0 0 1\nd 0.5\nmap_Kd missing.png\n");
  auto model = importModel(dir.write("cube.obj",
                                     "mtllib mats.mtl\n"
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                     "usemtl red\nf 1 2 3\n"
                                     "usemtl textured\nf 1 3 4\n"
                                     "usemtl red\nf 2 3 4\n"
                                     "usemtl lost\nf 1 2 4\n"));
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_EQ(model->meshes.size(), 3u);
  const Mesh& red = model->meshes[0];
  EXPECT_EQ(red.name, "red");
  EXPECT_EQ(red.triangleCount(), 2u);
  EXPECT_EQ(red.baseColor, glm::vec4(1, 0, 0, 1));
  EXPECT_FALSE(red.texture);
  const Mesh& textured = model->meshes[1];
  ASSERT_TRUE(textured.texture);
  EXPECT_EQ(textured.texture->width, 3);
  EXPECT_EQ(textured.texture->height, 1);
  EXPECT_EQ(textured.texture->pixels,
            (std::vector<std::uint8_t>{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255}));
  const Mesh& lost = model->meshes[2];  // missing texture: a warning, not a failure
  EXPECT_FALSE(lost.texture);
  EXPECT_EQ(lost.baseColor, glm::vec4(0, 0, 1, 0.5f));
  // The warning is the caller's to show, in the model (the library prints nothing).
  ASSERT_EQ(model->warnings.size(), 1u);
  EXPECT_NE(model->warnings[0].find("texture not loaded"), std::string::npos) << model->warnings[0];
}

TEST(ObjImport, KeepsEachObjectAndGroupAsAnObject) {
  TempDir dir;
  dir.write("m.mtl", "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n");
  // Faces before any o/g, then o pump (g body red, g body blue, g wheel), o valve, back to pump.
  auto model = importModel(dir.write("parts.obj",
                                     "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                     "usemtl red\nf 1 2 3\n"
                                     "o pump\ng body\nf 1 2 3 4\nusemtl blue\nf 1 3 4\n"
                                     "g wheel\nf 2 3 4\n"
                                     "o valve\nf 1 2 4\n"
                                     "o pump\ng body\nusemtl red\nf 1 3 4\n"));
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_EQ(model->meshes.size(), 2u);  // one per material still
  // Objects by (o, g) pair in first-seen order: 0 before either, pump/"" 1 (no faces), pump/body
  // 2, pump/wheel 3, valve/wheel 4. The last faces are pump/body's again: its red run goes on.
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>> runs;
  for (const ObjectRun& r : model->objectRuns)
    runs.emplace_back(r.object, r.mesh, r.firstTriangle, r.triangleCount);
  const std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>> want{
      {0, 0, 0, 1}, {2, 0, 1, 3}, {2, 1, 0, 1}, {3, 1, 1, 1}, {4, 1, 2, 1}};
  std::sort(runs.begin(), runs.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<1>(a), std::get<2>(a)) < std::tie(std::get<1>(b), std::get<2>(b));
  });
  EXPECT_EQ(runs, want);
  EXPECT_EQ(model->objectCount(), 5u);
  // A file without o or g is one object: no runs.
  auto plain = importModel(dir.write("plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  ASSERT_TRUE(plain.ok()) << plain.message();
  EXPECT_TRUE(plain->objectRuns.empty());
  EXPECT_EQ(plain->objectCount(), 1u);
}

TEST(ObjImport, MissingMaterialLibraryIsOnlyAWarning) {
  TempDir dir;
  auto model = importModel(
      dir.write("t.obj", "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n"));
  ASSERT_TRUE(model.ok()) << model.message();
  EXPECT_EQ(model->triangleCount(), 1u);
}

TEST(ObjImport, RejectsOutOfRangeAndZeroIndicesWithLineNumbers) {
  TempDir dir;
  auto big = importModel(dir.write("big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"));
  EXPECT_TRUE(mentions(big, "big.obj: line 4: face index 4 out of range (3 vertices)"))
      << big.message();
  auto neg = importModel(dir.write("neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"));
  EXPECT_TRUE(mentions(neg, "neg.obj: line 4: face index -4 out of range")) << neg.message();
  auto zero = importModel(dir.write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"));
  EXPECT_TRUE(mentions(zero, "zero.obj: line 4")) << zero.message();
  auto vt = importModel(dir.write("vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n"));
  EXPECT_TRUE(mentions(vt, "vt.obj: line 5: texture coordinate index 2")) << vt.message();
  auto nan = importModel(dir.write("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n"));
  EXPECT_TRUE(mentions(nan, "nan.obj: vertex 2 has a non-finite")) << nan.message();
  auto bad = importModel(dir.write("bad.obj", "v 0 0 0\nv 1 zero 0\n"));
  EXPECT_TRUE(mentions(bad, "bad.obj: line 2")) << bad.message();
  auto none = importModel(dir.write("none.obj", "v 0 0 0\nv 1 0 0\n"));
  EXPECT_TRUE(mentions(none, "none.obj: mesh has no triangles")) << none.message();
}

// ---- glTF ----

// Builds a .glb from JSON and a binary chunk.
std::string glb(std::string gltfText, std::string bin) {
  while (gltfText.size() % 4) gltfText.push_back(' ');
  while (bin.size() % 4) bin.push_back('\0');
  std::string s;
  putBytes(s, std::uint32_t(0x46546C67));
  putBytes(s, std::uint32_t(2));
  putBytes(s, std::uint32_t(12 + 8 + gltfText.size() + 8 + bin.size()));
  putBytes(s, std::uint32_t(gltfText.size()));
  putBytes(s, std::uint32_t(0x4E4F534A));
  s += gltfText;
  putBytes(s, std::uint32_t(bin.size()));
  putBytes(s, std::uint32_t(0x004E4942));
  s += bin;
  return s;
}

// Three vertices (float VEC3), three UNSIGNED_SHORT indices; a parent node translated far away,
// a child node scaled by 2 that holds the mesh; a second, non-indexed primitive.
std::string triangleGltfJson(int bufferBytes, const std::string& uri, int maxIndex = 2) {
  (void)maxIndex;
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"translation":[6378137.5,0,0],"children":[1]},{"scale":[2,2,2],"mesh":0}],
    "meshes":[{"name":"tri","primitives":[
       {"attributes":{"POSITION":0,"TEXCOORD_0":2},"indices":1,"material":0},
       {"attributes":{"POSITION":0}}]}],
    "materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.25,0.5,0.75,1.0]}}],
    "buffers":[{"byteLength":)" +
         std::to_string(bufferBytes) + (uri.empty() ? "" : R"(,"uri":")" + uri + "\"") +
         R"(}],
    "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},
                   {"buffer":0,"byteOffset":36,"byteLength":6},
                   {"buffer":0,"byteOffset":44,"byteLength":24}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                  "min":[0,0,0],"max":[1,1,0]},
                 {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"},
                 {"bufferView":2,"componentType":5126,"count":3,"type":"VEC2"}]})";
}

std::string triangleBin(std::uint16_t lastIndex = 2) {
  std::string bin;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) putBytes(bin, f);
  for (std::uint16_t i : {std::uint16_t(0), std::uint16_t(1), lastIndex}) putBytes(bin, i);
  bin += std::string(2, '\0');
  for (float f : {0.f, 0.f, 1.f, 0.f, 0.f, 1.f}) putBytes(bin, f);
  return bin;
}

void expectTriangleModel(const Result<Model>& model) {
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_EQ(model->meshes.size(), 2u);
  const Mesh& m = model->meshes[0];
  EXPECT_EQ(m.name, "tri#0");
  EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(m.positions[1], glm::dvec3(6378139.5, 0, 0));  // parent translate, child scale 2
  EXPECT_EQ(m.positions[2], glm::dvec3(6378137.5, 2, 0));
  EXPECT_EQ(m.baseColor, glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
  ASSERT_EQ(m.texCoords.size(), 3u);
  EXPECT_EQ(m.texCoords[1], glm::vec2(1, 0));  // glTF convention kept as is
  const Mesh& plain = model->meshes[1];
  EXPECT_EQ(plain.indices, (std::vector<std::uint32_t>{0, 1, 2}));  // non-indexed: 0..n-1
  EXPECT_TRUE(plain.texCoords.empty());
}

TEST(GltfImport, ReadsGlbWithNodeTransformsInDoublePrecision) {
  TempDir dir;
  const std::string bin = triangleBin();
  expectTriangleModel(importModel(dir.write("tri.glb", glb(triangleGltfJson(68, ""), bin))));
}

TEST(GltfImport, EachNodeInstanceWithAMeshIsAnObject) {
  TempDir dir;
  // The mesh (two primitives) instanced by two nodes under one parent: flattened into two
  // objects of two meshes each.
  std::string gltf = triangleGltfJson(68, "");
  gltf.replace(gltf.find(R"("nodes":[{"translation":[6378137.5,0,0],"children":[1]},)"),
               std::string(R"("nodes":[{"translation":[6378137.5,0,0],"children":[1]},)").size(),
               R"("nodes":[{"translation":[6378137.5,0,0],"children":[1,2]},{"mesh":0},)");
  auto model = importModel(dir.write("two.glb", glb(gltf, triangleBin())));
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_EQ(model->meshes.size(), 4u);
  ASSERT_EQ(model->objectRuns.size(), 4u);
  for (std::uint32_t m = 0; m < 4; ++m) {
    EXPECT_EQ(model->objectRuns[m].object, m / 2);
    EXPECT_EQ(model->objectRuns[m].mesh, m);
    EXPECT_EQ(model->objectRuns[m].firstTriangle, 0u);
    EXPECT_EQ(model->objectRuns[m].triangleCount, 1u);
  }
  EXPECT_EQ(model->objectCount(), 2u);
  EXPECT_EQ(model->cityObjects, 0u);  // objects, not buildings
}

TEST(GltfImport, ReadsGltfWithExternalBuffer) {
  TempDir dir;
  dir.write("tri.bin", triangleBin());
  expectTriangleModel(importModel(dir.write("tri.gltf", triangleGltfJson(68, "tri.bin"))));
}

TEST(GltfImport, DecodesBaseColorTextureToRgba) {
  TempDir dir;
  dir.write("tri.bin", triangleBin());
  dir.write("tex.ppm", kPpm);
  std::string gltfText = triangleGltfJson(68, "tri.bin");
  gltfText.replace(gltfText.find(R"("baseColorFactor")"), 0, R"("baseColorTexture":{"index":0},)");
  gltfText.insert(
      gltfText.rfind('}'),
      R"(,"textures":[{"source":0}],"images":[{"uri":"tex.ppm","mimeType":"image/png"}])");
  auto model = importModel(dir.write("tex.gltf", gltfText));
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_TRUE(model->meshes[0].texture);
  EXPECT_EQ(model->meshes[0].texture->width, 3);
  EXPECT_EQ(model->meshes[0].texture->pixels,
            (std::vector<std::uint8_t>{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255}));
}

TEST(GltfImport, RejectsIndexBeyondVertexCount) {
  TempDir dir;
  auto model = importModel(dir.write("bad.glb", glb(triangleGltfJson(68, ""), triangleBin(7))));
  EXPECT_TRUE(mentions(model, "bad.glb: mesh 0 ('tri') primitive 0: face index 7 out of range"))
      << model.message();
}

TEST(GltfImport, RejectsAccessorBeyondBuffer) {
  TempDir dir;
  std::string gltfText = triangleGltfJson(68, "");
  gltfText.replace(gltfText.find(R"("count":3,"type":"VEC2")"), 9, R"("count":9)");
  auto model = importModel(dir.write("over.glb", glb(gltfText, triangleBin())));
  EXPECT_TRUE(mentions(model, "over.glb: ")) << model.message();
}

TEST(GltfImport, RejectsGlbTruncatedInTheMiddle) {
  TempDir dir;
  const std::string full = glb(triangleGltfJson(68, ""), triangleBin());
  for (std::size_t cut : {full.size() / 2, full.size() - 10, std::size_t(30), std::size_t(11)}) {
    auto model = importModel(dir.write("cut.glb", full.substr(0, cut)));
    EXPECT_TRUE(mentions(model, "cut.glb: ")) << "cut at " << cut;
  }
}

TEST(GltfImport, RealEngineTruncatedInTheMiddleIsAnError) {
  const auto path = std::filesystem::path(HLODR_SHARED_DATA) / "2CylinderEngine.glb";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
  TempDir dir;
  std::string bytes(std::filesystem::file_size(path), '\0');
  std::FILE* f = std::fopen(path.c_str(), "rb");
  ASSERT_TRUE(f);
  ASSERT_EQ(std::fread(bytes.data(), 1, bytes.size(), f), bytes.size());
  std::fclose(f);
  auto model = importModel(dir.write("engine.glb", bytes.substr(0, bytes.size() / 2)));
  EXPECT_TRUE(mentions(model, "engine.glb: ")) << (model.ok() ? "loaded" : model.message());
}

// ---- loadImage ----

TEST(LoadImage, ExpandsGreyAndRgbToRgba) {
  TempDir dir;
  auto rgb = loadImage(dir.write("c.ppm", kPpm));
  ASSERT_TRUE(rgb.ok()) << rgb.message();
  EXPECT_EQ(rgb->width, 3);
  EXPECT_EQ(rgb->pixels[4 + 1], 255);  // green pixel
  EXPECT_EQ(rgb->pixels[4 + 3], 255);  // alpha added
  auto grey = loadImage(dir.write("g.pgm", std::string("P5\n1 2\n255\n\x10\x80", 13)));
  ASSERT_TRUE(grey.ok()) << grey.message();
  EXPECT_EQ(grey->height, 2);
  EXPECT_EQ(grey->pixels, (std::vector<std::uint8_t>{16, 16, 16, 255, 128, 128, 128, 255}));
}

TEST(LoadImage, RejectsMissingAndCorruptFilesNamingThem) {
  TempDir dir;
  auto missing = loadImage(dir.file("none.png"));
  EXPECT_TRUE(mentions(missing, "none.png: ")) << missing.message();
  auto corrupt = loadImage(dir.write("bad.png", "\x89PNG\r\n\x1a\n garbage"));
  EXPECT_TRUE(mentions(corrupt, "bad.png: ")) << corrupt.message();
}

}  // namespace
}  // namespace hlod
