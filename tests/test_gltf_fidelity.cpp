// Issue 22 §2 (glTF): a glTF written as glTF keeps its vertex counts per mesh, its animations and
// its references; an output that would lose something is refused unless --allow-loss.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.h"
#include "untangle/read_meshes.h"
#include "untangle/write_meshes.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;

// glTF 1.0, from Debian's assimp-testmodels: a truck of three primitives sharing one position
// accessor of 2,392 vertices, two wheels placed by two nodes, two animations, one texture.
const std::string kTruck = "/usr/share/assimp/models/glTF/CesiumMilkTruck/CesiumMilkTruck.gltf";

TEST(GltfFidelity, GltfOneKeepsCountsAnimationsAndReferences) {
  if (!fs::exists(kTruck)) GTEST_SKIP() << "assimp-testmodels is not installed";
  TempDir dir;
  const std::string out = dir.file("truck.gltf");
  const auto r = run_cli("fix " + quote(kTruck) + " -o " + quote(out));
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 5) << r.err;
  const std::vector<Mesh> before = read_meshes(kTruck, Role::kMovable);
  const std::vector<Mesh> after = read_meshes(out, Role::kMovable);
  ASSERT_EQ(before.size(), after.size());
  std::size_t moved = 0;
  for (std::size_t m = 0; m < before.size(); ++m) {
    EXPECT_EQ(before[m].name, after[m].name);
    ASSERT_EQ(before[m].positions.size(), after[m].positions.size()) << before[m].name;
    EXPECT_EQ(before[m].triangles, after[m].triangles) << before[m].name;
    for (std::size_t v = 0; v < before[m].positions.size(); ++v)
      moved += before[m].positions[v] != after[m].positions[v] ? 1 : 0;
  }
  EXPECT_GT(moved, 0u);
  // The JSON is the input's but for buffer, image and shader URIs and accessor bounds.
  nlohmann::json in = nlohmann::json::parse(read_text(kTruck));
  nlohmann::json written = nlohmann::json::parse(read_text(out));
  EXPECT_EQ(written["animations"], in["animations"]);
  EXPECT_EQ(written["animations"].size(), 2u);
  EXPECT_EQ(written["materials"], in["materials"]);
  EXPECT_EQ(written["nodes"], in["nodes"]);
  EXPECT_EQ(written["buffers"].begin()->at("uri"), "truck.bin");
  // Every image and shader the output names exists from the output's folder (the originals).
  for (const char* kind : {"images", "shaders"}) {
    for (const auto& item : written[kind]) {
      const fs::path target = fs::path(out).parent_path() / item["uri"].get<std::string>();
      EXPECT_TRUE(fs::exists(target)) << target;
    }
  }
  // Outside the positions every byte of the buffer is kept: the animation data, indices, normals.
  const std::string bin_in = read_text(fs::path(kTruck).replace_extension(".bin").string());
  const std::string bin_out = read_text(dir.file("truck.bin"));
  ASSERT_EQ(bin_in.size(), bin_out.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < bin_in.size(); ++k) differing += bin_in[k] != bin_out[k] ? 1 : 0;
  EXPECT_GT(differing, 0u);
  EXPECT_LE(differing, moved * 12);
  // check reads what fix wrote with the same counts fix verified.
  const auto fixed = run_cli("fix " + quote(kTruck) + " -o " + quote(out) +
                             " --overwrite --report -");
  const auto check = run_cli("check " + quote(out) + " --report -");
  const auto jf = nlohmann::json::parse(fixed.out), jc = nlohmann::json::parse(check.out);
  EXPECT_EQ(jf["after"]["crossings"], jc["before"]["crossings"]);
}

TEST(GltfFidelity, LossIsRefusedUnlessAllowed) {
  if (!fs::exists(kTruck)) GTEST_SKIP() << "assimp-testmodels is not installed";
  // assimp does not import glTF 1.0 animations: any output through its exporter loses them.
  EXPECT_EQ(export_loss(kTruck, "x.glb"), "2 animations");
  EXPECT_EQ(export_loss(kTruck, "x.gltf"), "");
  EXPECT_EQ(export_loss(kTruck, "x.ply"), "2 animations, 1 texture");
  TempDir dir;
  const std::string out = dir.file("truck.glb");
  const auto refused = run_cli("fix " + quote(kTruck) + " -o " + quote(out));
  EXPECT_EQ(refused.exit_code, 4);
  EXPECT_EQ(refused.err, "error: " + out + ": would lose 2 animations of " + kTruck +
                             " (not carried by this format or by assimp); --allow-loss writes it "
                             "anyway\n");
  EXPECT_FALSE(fs::exists(out));
  const auto allowed =
      run_cli("fix " + quote(kTruck) + " -o " + quote(out) + " --allow-loss --max-iterations 1");
  EXPECT_TRUE(allowed.exit_code == 0 || allowed.exit_code == 5) << allowed.err;
  ASSERT_TRUE(fs::exists(out));
  // The texture is referenced from the output's folder (the file's JSON chunk follows the
  // 12-byte header and the chunk's length and type).
  const std::string glb = read_text(out);
  std::uint32_t length = 0;
  ASSERT_GT(glb.size(), 20u);
  std::memcpy(&length, glb.data() + 12, 4);
  const nlohmann::json j = nlohmann::json::parse(glb.substr(20, length));
  ASSERT_TRUE(j.contains("images"));
  std::size_t referenced = 0;
  for (const auto& image : j["images"]) {
    if (!image.contains("uri")) continue;
    ++referenced;
    const fs::path target = fs::path(out).parent_path() / image["uri"].get<std::string>();
    EXPECT_TRUE(fs::exists(target)) << target;
  }
  EXPECT_EQ(referenced, 1u);
  // OBJ to OBJ keeps everything.
  EXPECT_EQ(export_loss("a.obj", "b.obj"), "");
}

}  // namespace
}  // namespace untangle
