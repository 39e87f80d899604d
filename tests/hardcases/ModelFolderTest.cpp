// Files a model refers to are read only from inside its folder (docs/architecture.md, Formats): OBJ
// mtllib, MTL map_Kd, PLY TextureFile, glTF buffer and image URIs, city blocks. They were once
// opened wherever they pointed, a glTF error reported the outside file's size, and a glTF buffer
// missing beside the file was looked up in the current directory. An outside texture is a
// warning (drawn without it), an outside buffer an error; neither says anything about the
// outside file.
#include <string>

#include "HardcaseFolder.h"

namespace {

using hardcase::Folder;
using nlohmann::json;
namespace fs = std::filesystem;

class ModelFolder : public Folder {
 protected:
  void SetUp() override {
    Folder::SetUp();
    model = dir / "model";
    fs::create_directories(model);
    write("secret/tex.bmp", hardcase::tinyBmp());
    write("secret/quad.bin", hardcase::quadBuffer());
    write("secret/wrong-size.bin", std::string(1234, 'x'));
    write("secret/evil.mtl", "newmtl red\nKd 1 0 0\n");
  }
  gltest::Run build(const fs::path& file, const std::string& env = "") {
    return gltest::runHlodr(
        "build " + file.string() + " -o " + (dir / "s.hlod").string() + " --quiet", env);
  }
  // An OBJ quad with texture coordinates, using material "m" from `mtllib` (if any).
  fs::path obj(const std::string& mtllib) {
    std::string text = mtllib.empty() ? "" : "mtllib " + mtllib + "\n";
    text +=
        "usemtl m\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
    return write("model/quad.obj", text);
  }
  fs::path gltf(const json& g) { return write("model/scene.gltf", g.dump()); }
  static json withNode(json g) {
    g["nodes"].push_back({{"mesh", 0}});
    return g;
  }
  fs::path model;
};

TEST_F(ModelFolder, AnObjMaterialLibraryThatClimbsOutIsNotRead) {
  const auto r = build(obj("../secret/evil.mtl"));
  EXPECT_EQ(r.status, 0) << r.output;  // the geometry builds, without the material
  EXPECT_TRUE(mentions(r, "material library not loaded: '../secret/evil.mtl' lies outside"))
      << r.output;
}

TEST_F(ModelFolder, AnObjMaterialLibraryAtAnAbsolutePathIsNotRead) {
  const std::string abs = (dir / "secret" / "evil.mtl").string();
  const auto r = build(obj(abs));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(mentions(r, "'" + abs + "' lies outside")) << r.output;
}

TEST_F(ModelFolder, AnMtlTextureOutsideTheFolderIsSkippedWithAWarning) {
  const std::string names[] = {"../secret/tex.bmp", (dir / "secret" / "tex.bmp").string(),
                               "..\\secret\\tex.bmp"};
  for (const std::string& name : names) {
    write("model/m.mtl", "newmtl m\nKd 1 1 1\nmap_Kd " + name + "\n");
    const auto r = build(obj("m.mtl"));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(mentions(r, "texture not loaded: '")) << name << ": " << r.output;
    EXPECT_TRUE(mentions(r, "lies outside the model's folder")) << name << ": " << r.output;
  }
}

TEST_F(ModelFolder, ALinkInsideTheFolderThatLeadsOutCountsAsOutside) {
  fs::create_symlink(dir / "secret" / "tex.bmp", model / "tex.bmp");
  fs::create_directory_symlink(dir / "secret", model / "textures");
  for (const std::string name : {"tex.bmp", "textures/tex.bmp"}) {
    write("model/m.mtl", "newmtl m\nKd 1 1 1\nmap_Kd " + name + "\n");
    const auto r = build(obj("m.mtl"));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(mentions(r, "'" + name + "' goes through a link that leaves the model's folder"))
        << r.output;
  }
}

TEST_F(ModelFolder, TexturesInsideTheFolderAndBelowAreReadAsBefore) {
  write("model/textures/tex.bmp", hardcase::tinyBmp());
  fs::create_symlink("textures/tex.bmp", model / "alias.bmp");  // a link that stays inside
  for (const std::string name :
       {"textures/tex.bmp", "./textures/../textures/tex.bmp", "alias.bmp"}) {
    write("model/m.mtl", "newmtl m\nKd 1 1 1\nmap_Kd " + name + "\n");
    const auto r = build(obj("m.mtl"));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_FALSE(mentions(r, "warning")) << name << ": " << r.output;
  }
}

TEST_F(ModelFolder, APlyTextureFileOutsideTheFolderIsSkippedWithAWarning) {
  const fs::path ply = write("model/quad.ply",
                             "ply\nformat ascii 1.0\ncomment TextureFile ../secret/tex.bmp\n"
                             "element vertex 4\nproperty double x\nproperty double y\n"
                             "property double z\nproperty float s\nproperty float t\n"
                             "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
                             "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n3 0 1 2\n3 0 2 3\n");
  const auto r = build(ply);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(mentions(r, "texture not loaded: '../secret/tex.bmp' lies outside")) << r.output;
}

TEST_F(ModelFolder, GltfBufferUrisThatLeaveTheFolderAreRefusedHoweverSpelled) {
  const std::string uris[] = {"../secret/quad.bin", "..%2Fsecret%2Fquad.bin",
                              "sub/../../secret/quad.bin", (dir / "secret" / "quad.bin").string()};
  for (const std::string& uri : uris) {
    const auto r = build(gltf(withNode(hardcase::quadGltf(uri))));
    EXPECT_EQ(r.status, 1) << uri << ": " << r.output;
    EXPECT_TRUE(mentions(r, "lies outside the model's folder")) << uri << ": " << r.output;
  }
}

TEST_F(ModelFolder, AGltfBufferLinkedFromOutsideIsRefused) {
  fs::create_symlink(dir / "secret" / "quad.bin", model / "quad.bin");
  const auto r = build(gltf(withNode(hardcase::quadGltf("quad.bin"))));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "'quad.bin' goes through a link that leaves")) << r.output;
}

TEST_F(ModelFolder, TheGltfErrorSaysNothingOfTheOutsideFile) {
  // An outside file of the wrong size was once reported with its size; one that exists and one
  // that does not now give the same message but for the name.
  const auto existing = build(gltf(withNode(hardcase::quadGltf("../secret/wrong-size.bin"))));
  const auto missing = build(gltf(withNode(hardcase::quadGltf("../secret/no-such-file.bin"))));
  EXPECT_EQ(existing.status, 1) << existing.output;
  EXPECT_FALSE(mentions(existing, "1234")) << existing.output;
  std::string renamed = missing.output;
  const std::string from = "no-such-file.bin", to = "wrong-size.bin";
  renamed.replace(renamed.find(from), from.size(), to);
  EXPECT_EQ(existing.output, renamed);
}

TEST_F(ModelFolder, AGltfBufferMissingBesideTheFileIsNotTakenFromTheCurrentDirectory) {
  write("cwd/quad.bin", hardcase::quadBuffer());
  const auto r =
      build(gltf(withNode(hardcase::quadGltf("quad.bin"))), "cd " + (dir / "cwd").string() + " &&");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "quad.bin")) << r.output;
}

TEST_F(ModelFolder, AGltfBufferBesideTheFileIsReadWhateverTheCurrentDirectory) {
  write("model/quad.bin", hardcase::quadBuffer());
  const auto r = build(gltf(withNode(hardcase::quadGltf("quad.bin"))), "cd / &&");
  EXPECT_EQ(r.status, 0) << r.output;
}

TEST_F(ModelFolder, AGltfImageOutsideTheFolderIsSkippedWithAWarning) {
  write("model/quad.bin", hardcase::quadBuffer());
  json g = withNode(hardcase::quadGltf("quad.bin"));
  g["images"] = json::array({{{"uri", "../secret/tex.bmp"}}});
  g["textures"] = json::array({{{"source", 0}}});
  g["materials"] =
      json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  g["meshes"][0]["primitives"][0]["material"] = 0;
  const auto r = build(gltf(g));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(mentions(r, "'../secret/tex.bmp' lies outside the model's folder")) << r.output;
}

TEST_F(ModelFolder, ACityBlockLinkedFromOutsideTheCityFolderIsRefused) {
  ASSERT_EQ(gltest::runHlodr("city --blocks 1 --texture 64 --quiet -o " +
                             (dir / "secret" / "city").string())
                .status,
            0);
  fs::create_directories(dir / "city");
  fs::copy_file(dir / "secret" / "city" / "city.json", dir / "city" / "city.json");
  fs::copy_file(dir / "secret" / "city" / "block_0000.png", dir / "city" / "block_0000.png");
  fs::create_symlink(dir / "secret" / "city" / "block_0000.ply", dir / "city" / "block_0000.ply");
  const auto r = build(dir / "city");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "'block_0000.ply' goes through a link that leaves")) << r.output;
}

}  // namespace
