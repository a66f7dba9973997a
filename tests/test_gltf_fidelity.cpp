// Issue 22 §2 (glTF): a glTF written as glTF keeps its vertex counts per mesh, its animations and
// its references; an output that would lose something is refused unless --allow-loss.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "scenes/scenes.h"
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
using testing::write_text;

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

// A binary glTF 2 file written by hand: one node, one mesh, a primitive with POSITION (with
// min/max), TEXCOORD_0 and uint32 indices in the BIN chunk, in that order.
struct Glb {
  std::string bytes;
  std::size_t positions_at = 0, positions_end = 0;  // the POSITION bytes, in the file
  std::size_t json_at = 0, json_length = 0;         // the JSON chunk's data
};

void put_u32(std::string& out, std::uint32_t u) { out.append(reinterpret_cast<const char*>(&u), 4); }
std::uint32_t u32_at(const std::string& bytes, std::size_t at) {
  std::uint32_t u = 0;
  std::memcpy(&u, bytes.data() + at, 4);
  return u;
}

// Bytes where `a` and `b` (of equal size) differ: in all, and outside the ranges [from, to).
struct Differing {
  std::size_t all = 0, outside = 0;
};
Differing differing_bytes(const std::string& a, const std::string& b,
                          const std::vector<std::pair<std::size_t, std::size_t>>& ranges) {
  Differing d;
  for (std::size_t k = 0; k < a.size() && k < b.size(); ++k) {
    if (a[k] == b[k]) continue;
    ++d.all;
    bool inside = false;
    for (const auto& [from, to] : ranges) inside = inside || (k >= from && k < to);
    d.outside += inside ? 0 : 1;
  }
  return d;
}

Glb glb_of(const Mesh& mesh) {
  std::string bin;
  std::array<float, 3> lo{}, hi{};
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    for (int c = 0; c < 3; ++c) {
      const float f = static_cast<float>(mesh.positions[v][c]);
      bin.append(reinterpret_cast<const char*>(&f), 4);
      lo[c] = v == 0 ? f : std::min(lo[c], f);
      hi[c] = v == 0 ? f : std::max(hi[c], f);
    }
  }
  const std::size_t position_bytes = bin.size();
  for (const Vec3& p : mesh.positions) {
    for (double x : {p[0] * 0.25 + 0.5, p[1] * 0.25 + 0.5}) {
      const float f = static_cast<float>(x);
      bin.append(reinterpret_cast<const char*>(&f), 4);
    }
  }
  const std::size_t uv_bytes = bin.size() - position_bytes;
  for (const Triangle& t : mesh.triangles)
    for (std::uint32_t v : t) put_u32(bin, v);
  const std::size_t index_bytes = bin.size() - position_bytes - uv_bytes;
  const std::size_t nv = mesh.positions.size();
  using Json = nlohmann::ordered_json;
  const Json primitive = {{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}};
  Json j;
  j["asset"] = {{"version", "2.0"}, {"generator", "untangle tests"}};
  j["scene"] = 0;
  j["scenes"] = Json::array({Json{{"nodes", Json::array({0})}}});
  j["nodes"] = Json::array({Json{{"mesh", 0}, {"name", "sheet"}}});
  j["meshes"] = Json::array({Json{{"name", "sheet"}, {"primitives", Json::array({primitive})}}});
  j["buffers"] = Json::array({Json{{"byteLength", bin.size()}}});
  j["bufferViews"] = Json::array(
      {Json{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", position_bytes}},
       Json{{"buffer", 0}, {"byteOffset", position_bytes}, {"byteLength", uv_bytes}},
       Json{{"buffer", 0}, {"byteOffset", position_bytes + uv_bytes}, {"byteLength", index_bytes}}});
  j["accessors"] = Json::array(
      {Json{{"bufferView", 0}, {"componentType", 5126}, {"count", nv}, {"type", "VEC3"},
            {"min", Json::array({lo[0], lo[1], lo[2]})}, {"max", Json::array({hi[0], hi[1], hi[2]})}},
       Json{{"bufferView", 1}, {"componentType", 5126}, {"count", nv}, {"type", "VEC2"}},
       Json{{"bufferView", 2}, {"componentType", 5125}, {"count", 3 * mesh.triangles.size()},
            {"type", "SCALAR"}}});
  std::string text = j.dump();
  text.append((4 - text.size() % 4) % 4, ' ');
  bin.append((4 - bin.size() % 4) % 4, '\0');
  Glb g;
  g.bytes = "glTF";
  put_u32(g.bytes, 2);
  put_u32(g.bytes, static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
  put_u32(g.bytes, static_cast<std::uint32_t>(text.size()));
  put_u32(g.bytes, 0x4E4F534A);
  g.json_at = g.bytes.size();
  g.json_length = text.size();
  g.bytes += text;
  put_u32(g.bytes, static_cast<std::uint32_t>(bin.size()));
  put_u32(g.bytes, 0x004E4942);
  g.positions_at = g.bytes.size();
  g.positions_end = g.positions_at + position_bytes;
  g.bytes += bin;
  return g;
}

// Issue 22 §2: a .glb written as .glb is its own bytes with the moved positions patched in the
// BIN chunk. A saddle sheet (z = 0.4 x y, corners at z = +-0.9) through a small sphere near its
// flat middle: the part inside moves out by about the sphere's radius, within the sheet's bounds,
// so the JSON chunk is kept byte for byte. A flat sheet through it: the moved part leaves the
// stored bounds, so the JSON chunk is written again with the POSITION accessor's new min/max and
// nothing else changed. Each output re-read has the input's vertex count and triangles and is
// detected free of crossings with the obstacle.
TEST(GltfFidelity, GlbWrittenInPlace) {
  for (const bool saddle : {true, false}) {
    SCOPED_TRACE(saddle ? "saddle" : "flat");
    TempDir dir;
    Mesh sheet = scenes::grid_sheet(25, 25, {-1.5, -1.5, 0.0}, {3.0, 0.0, 0.0}, {0.0, 3.0, 0.0}, "sheet");
    if (saddle)
      for (Vec3& p : sheet.positions) p[2] = 0.4 * p[0] * p[1];
    const Glb glb = glb_of(sheet);
    const std::string in = dir.file("sheet.glb"), obstacle = dir.file("sphere.obj");
    write_text(in, glb.bytes);
    scenes::write_obj(scenes::uv_sphere({0.011, 0.017, 0.013}, 0.35, 24, 16, "sphere"), obstacle);
    EXPECT_EQ(export_loss(in, dir.file("x.glb")), "");
    fs::create_directories(dir.path() / "out");
    const std::string out = dir.file("out/sheet.glb");
    const auto r = run_cli("fix " + quote(in) + " --obstacle " + quote(obstacle) + " -o " + quote(out) + " -q");
    ASSERT_TRUE(testing::intersection_free(r.exit_code)) << r.exit_code << r.err;

    const std::string written = read_text(out);
    const std::vector<Mesh> before = read_meshes(in, Role::kMovable);
    const std::vector<Mesh> after = read_meshes(out, Role::kMovable);
    ASSERT_EQ(before.size(), 1u);
    ASSERT_EQ(after.size(), 1u);
    ASSERT_EQ(after[0].positions.size(), before[0].positions.size());
    EXPECT_EQ(after[0].triangles, before[0].triangles);
    std::size_t moved = 0;
    for (std::size_t v = 0; v < before[0].positions.size(); ++v)
      moved += before[0].positions[v] != after[0].positions[v] ? 1 : 0;
    EXPECT_GT(moved, 0u);
    const auto check = run_cli("check " + quote(out) + " --obstacle " + quote(obstacle) + " --report -");
    EXPECT_EQ(check.exit_code, 0) << check.err;
    EXPECT_EQ(nlohmann::json::parse(check.out)["before"]["crossings"], 0);

    // The JSON chunk: kept (saddle), or the input's but for the POSITION bounds (flat).
    ASSERT_GE(written.size(), 28u);
    EXPECT_EQ(written.substr(0, 4), "glTF");
    EXPECT_EQ(u32_at(written, 4), 2u);
    EXPECT_EQ(u32_at(written, 8), written.size());
    const std::size_t json_length = u32_at(written, 12);
    ASSERT_LE(20 + json_length + 8, written.size());
    const std::string json_in = glb.bytes.substr(glb.json_at, glb.json_length);
    const std::string json_out = written.substr(20, json_length);
    nlohmann::json j_in = nlohmann::json::parse(json_in), j_out = nlohmann::json::parse(json_out);
    if (saddle) {
      EXPECT_EQ(json_out, json_in);
    } else {
      EXPECT_TRUE(j_out["accessors"][0]["min"] != j_in["accessors"][0]["min"] ||
                  j_out["accessors"][0]["max"] != j_in["accessors"][0]["max"]);
      // The new bounds are those of the positions written.
      for (int c = 0; c < 3; ++c) {
        float lo = 0, hi = 0;
        for (std::size_t v = 0; v < after[0].positions.size(); ++v) {
          const float f = static_cast<float>(after[0].positions[v][c]);
          lo = v == 0 ? f : std::min(lo, f);
          hi = v == 0 ? f : std::max(hi, f);
        }
        EXPECT_EQ(static_cast<float>(j_out["accessors"][0]["min"][c].get<double>()), lo) << c;
        EXPECT_EQ(static_cast<float>(j_out["accessors"][0]["max"][c].get<double>()), hi) << c;
      }
      for (auto* j : {&j_in, &j_out}) {
        (*j)["accessors"][0].erase("min");
        (*j)["accessors"][0].erase("max");
      }
      EXPECT_EQ(j_out, j_in);
    }
    // After the JSON chunk every byte is the input's but for the positions of moved vertices.
    const std::size_t shift = json_length - glb.json_length;
    const std::string rest_in = glb.bytes.substr(glb.json_at + glb.json_length);
    const std::string rest_out = written.substr(20 + json_length);
    ASSERT_EQ(rest_out.size(), rest_in.size());
    const std::size_t rest_at = glb.json_at + glb.json_length;
    const Differing d =
        differing_bytes(rest_in, rest_out, {{glb.positions_at - rest_at, glb.positions_end - rest_at}});
    EXPECT_GT(d.all, 0u);
    EXPECT_LE(d.all, moved * 12);
    EXPECT_EQ(d.outside, 0u);
    EXPECT_EQ(written.substr(0, 8), glb.bytes.substr(0, 8));
    if (saddle) {
      EXPECT_EQ(shift, 0u);
    }
  }
}

// The same on a real file, assimp-testmodels' BoxTextured.glb (glTF 2: NORMAL, POSITION and
// TEXCOORD_0 interleaved in views, indices, an embedded PNG in the BIN chunk): a sphere through one
// side pushes the box aside, beyond its stored bounds. The JSON chunk differs only in the POSITION
// accessor's min/max, the rest of the file only in the POSITION bytes.
TEST(GltfFidelity, TestModelsGlbWrittenInPlace) {
  const std::string box = "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb";
  if (!fs::exists(box)) GTEST_SKIP() << "assimp-testmodels is not installed";
  TempDir dir;
  const std::string obstacle = dir.file("sphere.obj"), out = dir.file("box.glb");
  scenes::write_obj(scenes::uv_sphere({0.45, 0.02, 0.03}, 0.3, 24, 16, "sphere"), obstacle);
  const auto r = run_cli("fix " + quote(box) + " --obstacle " + quote(obstacle) + " -o " + quote(out) + " -q");
  ASSERT_TRUE(testing::intersection_free(r.exit_code)) << r.exit_code << r.err;
  const auto check = run_cli("check " + quote(out) + " --obstacle " + quote(obstacle) + " --report -");
  EXPECT_EQ(check.exit_code, 0) << check.err;
  EXPECT_EQ(nlohmann::json::parse(check.out)["before"]["crossings"], 0);

  const std::string in_bytes = read_text(box), out_bytes = read_text(out);
  ASSERT_GE(out_bytes.size(), 20u);
  const std::size_t in_json = u32_at(in_bytes, 12), out_json = u32_at(out_bytes, 12);
  nlohmann::json j_in = nlohmann::json::parse(in_bytes.substr(20, in_json));
  nlohmann::json j_out = nlohmann::json::parse(out_bytes.substr(20, out_json));
  EXPECT_EQ(u32_at(out_bytes, 8), out_bytes.size());
  // The POSITION bytes, as offsets into the BIN chunk's data.
  std::vector<std::pair<std::size_t, std::size_t>> positions;
  std::set<std::size_t> position_accessors;
  for (const auto& mesh : j_in["meshes"]) {
    for (const auto& primitive : mesh["primitives"]) {
      const std::size_t a = primitive["attributes"]["POSITION"].get<std::size_t>();
      position_accessors.insert(a);
      const auto& accessor = j_in["accessors"][a];
      const auto& view = j_in["bufferViews"][accessor["bufferView"].get<std::size_t>()];
      const std::size_t start = view.value("byteOffset", 0) + accessor.value("byteOffset", 0);
      const std::size_t stride = view.value("byteStride", 12);
      // Into the rest of the file: the BIN chunk's length and type come first.
      positions.push_back({8 + start, 8 + start + (accessor["count"].get<std::size_t>() - 1) * stride + 12});
    }
  }
  for (std::size_t a : position_accessors) {
    for (auto* j : {&j_in, &j_out}) {
      (*j)["accessors"][a].erase("min");
      (*j)["accessors"][a].erase("max");
    }
  }
  EXPECT_EQ(j_out, j_in);
  const std::string rest_in = in_bytes.substr(20 + in_json), rest_out = out_bytes.substr(20 + out_json);
  ASSERT_EQ(rest_out.size(), rest_in.size());
  const Differing d = differing_bytes(rest_in, rest_out, positions);
  EXPECT_GT(d.all, 0u);
  EXPECT_EQ(d.outside, 0u);
}

}  // namespace
}  // namespace untangle
