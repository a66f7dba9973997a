// Issue 22 §3: obstacles by name inside one file (--obstacle-name, --movable-name), in OBJ by
// `o`/`g` names and in glTF by mesh and node names; the obstacles' bytes kept in the output.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"
#include "untangle/error.h"
#include "untangle/read_meshes.h"
#include "untangle/roles_by_name.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;
using testing::write_text;

const fs::path kMakehuman = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman";

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

// The `v` lines of an OBJ text, in order.
std::vector<std::string> v_lines(const std::string& text) {
  std::vector<std::string> out;
  for (const std::string& l : lines_of(text))
    if (l.rfind("v ", 0) == 0) out.push_back(l);
  return out;
}

// One OBJ holding the MakeHuman body (`o body`) and then the garment (`o garment`), each with its
// vertices, texture coordinates and faces (indices shifted by what comes before).
std::string body_and_garment_obj() {
  std::string out = "mtllib none.mtl\n";
  std::size_t v_before = 0, vt_before = 0;
  for (const auto& [name, file] : {std::pair<std::string, std::string>{"body", "male_generic.obj"},
                                   {"garment", "male_casualsuit04.obj"}}) {
    out += "o " + name + "\n";
    std::size_t v = 0, vt = 0;
    for (const std::string& line : lines_of(read_text((kMakehuman / file).string()))) {
      if (line.rfind("v ", 0) == 0) {
        out += line + "\n";
        ++v;
      } else if (line.rfind("vt ", 0) == 0) {
        out += line + "\n";
        ++vt;
      } else if (line.rfind("f ", 0) == 0) {
        std::istringstream corners(line.substr(2));
        std::string corner, face = "f";
        while (corners >> corner) {
          const std::size_t slash = corner.find('/');
          face += " " + std::to_string(std::stoul(corner.substr(0, slash)) + v_before);
          if (slash != std::string::npos)
            face += "/" + std::to_string(std::stoul(corner.substr(slash + 1)) + vt_before);
        }
        out += face + "\n";
      }
    }
    v_before += v;
    vt_before += vt;
  }
  return out;
}

// Positions and triangles of the mesh in `file` (OBJ), for writing it into a glTF.
Mesh read_one(const fs::path& file) { return read_meshes(file.string(), Role::kMovable).front(); }

// A glTF 2 file of the given meshes, each a mesh and a node of its name, positions float32 and
// indices uint32 in one external buffer `<stem>.bin`.
void write_gltf(const std::string& path, const std::vector<std::pair<std::string, Mesh>>& meshes) {
  nlohmann::ordered_json j;
  j["asset"] = {{"version", "2.0"}};
  std::string bin;
  nlohmann::ordered_json nodes = nlohmann::json::array(), gl_meshes = nlohmann::json::array(),
                         accessors = nlohmann::json::array(), views = nlohmann::json::array();
  for (const auto& [name, mesh] : meshes) {
    std::array<float, 3> lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    const std::size_t position_offset = bin.size();
    for (const Vec3& p : mesh.positions) {
      for (int c = 0; c < 3; ++c) {
        const float f = static_cast<float>(p[c]);
        lo[c] = std::min(lo[c], f);
        hi[c] = std::max(hi[c], f);
        char bytes[4];
        std::memcpy(bytes, &f, 4);
        bin.append(bytes, 4);
      }
    }
    const std::size_t index_offset = bin.size();
    for (const Triangle& t : mesh.triangles) {
      for (std::uint32_t v : t) {
        char bytes[4];
        std::memcpy(bytes, &v, 4);
        bin.append(bytes, 4);
      }
    }
    const std::size_t a = accessors.size();
    views.push_back({{"buffer", 0}, {"byteOffset", position_offset},
                     {"byteLength", index_offset - position_offset}, {"target", 34962}});
    views.push_back({{"buffer", 0}, {"byteOffset", index_offset},
                     {"byteLength", bin.size() - index_offset}, {"target", 34963}});
    accessors.push_back({{"bufferView", a}, {"componentType", 5126},
                         {"count", mesh.positions.size()}, {"type", "VEC3"},
                         {"min", {lo[0], lo[1], lo[2]}}, {"max", {hi[0], hi[1], hi[2]}}});
    accessors.push_back({{"bufferView", a + 1}, {"componentType", 5125},
                         {"count", mesh.triangles.size() * 3}, {"type", "SCALAR"}});
    gl_meshes.push_back({{"name", name},
                         {"primitives", {{{"attributes", {{"POSITION", a}}}, {"indices", a + 1}}}}});
    nodes.push_back({{"name", name + "_node"}, {"mesh", gl_meshes.size() - 1}});
  }
  const std::string bin_name = fs::path(path).stem().string() + ".bin";
  j["buffers"] = {{{"uri", bin_name}, {"byteLength", bin.size()}}};
  j["bufferViews"] = views;
  j["accessors"] = accessors;
  j["meshes"] = gl_meshes;
  j["nodes"] = nodes;
  nlohmann::ordered_json roots = nlohmann::json::array();
  for (std::size_t k = 0; k < nodes.size(); ++k) roots.push_back(k);
  j["scenes"] = {{{"nodes", roots}}};
  j["scene"] = 0;
  write_text(path, j.dump(1));
  write_text((fs::path(path).parent_path() / bin_name).string(), bin);
}

// The bytes of accessor `a` of a glTF 2 file with external buffers.
std::string accessor_bytes(const std::string& gltf, std::size_t a) {
  const nlohmann::json j = nlohmann::json::parse(read_text(gltf));
  const auto& accessor = j["accessors"][a];
  const auto& view = j["bufferViews"][accessor["bufferView"].get<std::size_t>()];
  const std::string bin = read_text(
      (fs::path(gltf).parent_path() / j["buffers"][view["buffer"].get<std::size_t>()]["uri"].get<std::string>())
          .string());
  const std::size_t stride = view.value("byteStride", 0);
  const std::size_t size = accessor["type"] == "VEC3" ? 12 : 4;
  const std::size_t start = view.value("byteOffset", 0) + accessor.value("byteOffset", 0);
  std::string out;
  for (std::size_t k = 0; k < accessor["count"].get<std::size_t>(); ++k)
    out += bin.substr(start + k * (stride ? stride : size), size);
  return out;
}

// The index of the accessor holding the positions of the glTF mesh named `name`.
std::size_t position_accessor(const std::string& gltf, const std::string& name) {
  const nlohmann::json j = nlohmann::json::parse(read_text(gltf));
  for (const auto& m : j["meshes"])
    if (m.value("name", "") == name) return m["primitives"][0]["attributes"]["POSITION"];
  ADD_FAILURE() << "no mesh " << name << " in " << gltf;
  return 0;
}

TEST(RolesByName, ObjBodyAndGarmentInOneFileKeepsTheBodyBytes) {
  TempDir dir;
  const std::string both = dir.file("both.obj"), out = dir.file("out.obj");
  write_text(both, body_and_garment_obj());
  const auto r = run_cli("fix " + quote(both) + " --obstacle-name body -o " + quote(out));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("status: clean"), std::string::npos) << r.out;
  const std::vector<std::string> in_v = v_lines(read_text(both)), out_v = v_lines(read_text(out));
  ASSERT_EQ(in_v.size(), out_v.size());
  const std::size_t body_vertices = v_lines(read_text((kMakehuman / "male_generic.obj").string())).size();
  // The body (first in the file) is an obstacle: every one of its v lines is as it was.
  for (std::size_t k = 0; k < body_vertices; ++k) ASSERT_EQ(in_v[k], out_v[k]) << "body vertex " << k;
  std::size_t moved = 0;
  for (std::size_t k = body_vertices; k < in_v.size(); ++k) moved += in_v[k] != out_v[k] ? 1 : 0;
  EXPECT_GT(moved, 0u);
  // Every line but the garment's v lines is kept.
  const std::vector<std::string> in_lines = lines_of(read_text(both)), out_lines = lines_of(read_text(out));
  ASSERT_EQ(in_lines.size(), out_lines.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < in_lines.size(); ++k) {
    if (in_lines[k] == out_lines[k]) continue;
    ++differing;
    EXPECT_EQ(in_lines[k].rfind("v ", 0), 0u) << in_lines[k];
  }
  EXPECT_EQ(differing, moved);

  // The same scene as two files: the garment is repaired against the body alike, so its v lines
  // come out the same (the meshes in the same order, movable first, and the repair runs on a
  // canonical numbering).
  const std::string garment_out = dir.file("garment.obj");
  const auto two = run_cli("fix " + quote((kMakehuman / "male_casualsuit04.obj").string()) +
                           " --obstacle " + quote((kMakehuman / "male_generic.obj").string()) +
                           " -o " + quote(garment_out));
  EXPECT_EQ(two.exit_code, 0) << two.out << two.err;
  const std::vector<std::string> garment_v = v_lines(read_text(garment_out));
  ASSERT_EQ(garment_v.size(), in_v.size() - body_vertices);
  for (std::size_t k = 0; k < garment_v.size(); ++k)
    ASSERT_EQ(garment_v[k], out_v[body_vertices + k]) << "garment vertex " << k;

  // --movable-name garment gives the same roles, so the same bytes.
  const std::string out2 = dir.file("out2.obj");
  const auto m = run_cli("fix " + quote(both) + " --movable-name 'gar*' -o " + quote(out2));
  EXPECT_EQ(m.exit_code, 0) << m.out << m.err;
  EXPECT_EQ(read_text(out2), read_text(out));

  // check with the same roles agrees with check on the two files, and counts what crosses
  // between the two meshes, not within one.
  const auto c1 = run_cli("check " + quote(both) + " --obstacle-name body --report -");
  const auto c2 = run_cli("check " + quote((kMakehuman / "male_casualsuit04.obj").string()) +
                          " --obstacle " + quote((kMakehuman / "male_generic.obj").string()) +
                          " --report -");
  ASSERT_EQ(c1.exit_code, 5) << c1.err;
  ASSERT_EQ(c2.exit_code, 5) << c2.err;
  const auto j1 = nlohmann::json::parse(c1.out), j2 = nlohmann::json::parse(c2.out);
  EXPECT_EQ(j1["before"], j2["before"]) << c1.out.substr(0, 2000);
  EXPECT_GT(j1["before"]["inside_vertices"].get<std::size_t>(), 0u);
  EXPECT_EQ(j1["before"]["pairs"]["self"], 0);
  const auto after = run_cli("check " + quote(out) + " --obstacle-name body");
  EXPECT_EQ(after.exit_code, 0) << after.out << after.err;
}

TEST(RolesByName, GltfBodyAndGarmentKeepsTheBodyBuffer) {
  TempDir dir;
  const std::string both = dir.file("both.gltf"), out = dir.file("out.gltf");
  write_gltf(both, {{"body", read_one(kMakehuman / "male_generic.obj")},
                    {"garment", read_one(kMakehuman / "male_casualsuit04.obj")}});
  // By node name this time.
  const auto r = run_cli("fix " + quote(both) + " --obstacle-name 'body_n?de' -o " + quote(out));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("status: clean"), std::string::npos) << r.out;
  const std::string body_in = accessor_bytes(both, position_accessor(both, "body"));
  const std::string body_out = accessor_bytes(out, position_accessor(out, "body"));
  EXPECT_EQ(body_in.size(), 13652u * 12);
  EXPECT_TRUE(body_in == body_out) << "the body's positions changed";
  const std::string garment_in = accessor_bytes(both, position_accessor(both, "garment"));
  const std::string garment_out = accessor_bytes(out, position_accessor(out, "garment"));
  EXPECT_EQ(garment_in.size(), garment_out.size());
  EXPECT_FALSE(garment_in == garment_out) << "the garment did not move";
  const auto after = run_cli("check " + quote(out) + " --obstacle-name body");
  EXPECT_EQ(after.exit_code, 0) << after.out << after.err;
}

TEST(RolesByName, InfoListsTheNames) {
  TempDir dir;
  const std::string both = dir.file("both.gltf");
  write_gltf(both, {{"body", read_one(kMakehuman / "male_generic.obj")},
                    {"garment", read_one(kMakehuman / "male_casualsuit04.obj")}});
  const auto r = run_cli("info " + quote(both));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("names (mesh, node): body, body_node\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("names (mesh, node): garment, garment_node\n"), std::string::npos) << r.out;
  const std::string obj = dir.file("groups.obj");
  write_text(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\no shirt\ng left sleeve\nf 1 3 2\n"
                  "o skin\nf 1 2 4\n");
  const auto o = run_cli("info " + quote(obj));
  EXPECT_EQ(o.exit_code, 0) << o.err;
  EXPECT_NE(o.out.find("names (o and g): left sleeve, left, sleeve, shirt, skin\n"), std::string::npos)
      << o.out;
  // The object's name reaches its groups: the sleeve is an obstacle with the skin, the unnamed
  // first face stays movable.
  std::vector<Mesh> meshes = read_meshes(obj, Role::kMovable);
  NamePatterns patterns;
  patterns.obstacle = {"s[hk]i*"};
  const RoleSplit split = split_by_name(meshes, {}, patterns);
  ASSERT_EQ(split.meshes.size(), 2u);
  EXPECT_EQ(split.meshes[0].triangles.size(), 1u);
  EXPECT_EQ(split.meshes[1].triangles.size(), 2u);
  EXPECT_EQ(split.meshes[1].name, "left sleeve,skin");
}

TEST(RolesByName, PatternsThatMatchNothingOrBothAreUsageErrors) {
  TempDir dir;
  const std::string obj = dir.file("two.obj"), out = dir.file("out.obj");
  write_text(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\no body\nf 1 2 3\no garment\nf 1 2 4\n");
  const auto none = run_cli("fix " + quote(obj) + " --obstacle-name 'bod[xz]' -o " + quote(out));
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_EQ(none.err,
            "error: --obstacle-name bod[xz] matches no name in the movable inputs; names present: "
            "body, garment\n");
  const auto both = run_cli("check " + quote(obj) + " --obstacle-name '*' --movable-name garment");
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_EQ(both.err, "error: " + obj + ": group garment matches both --obstacle-name * and "
                      "--movable-name garment; give it one role\n");
  EXPECT_FALSE(fs::exists(out));
}

// Two groups sharing an edge: the split keeps each part's vertices in source order, pins the
// shared ones in the movable part, and puts moved positions back where they came from.
TEST(RolesByName, SplitPinsSharedVerticesAndMergesBack) {
  Mesh mesh;
  mesh.path = "m.obj";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 2, 0}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}, {3, 4, 2}};
  mesh.polygon = {0, 1, 2};
  mesh.source_faces = 3;
  mesh.group_names = {"cloth", "skin"};
  mesh.triangle_group = {0, 1, 0};
  NamePatterns patterns;
  patterns.obstacle = {"sk*"};
  RoleSplit split = split_by_name({mesh}, {{0, 0, 0, 0, 1}}, patterns);
  ASSERT_EQ(split.meshes.size(), 2u);
  EXPECT_EQ(split.meshes[0].role, Role::kMovable);
  EXPECT_EQ(split.meshes[1].role, Role::kObstacle);
  EXPECT_EQ(split.meshes[0].name, "cloth");
  EXPECT_EQ(split.meshes[1].name, "skin");
  EXPECT_EQ(split.parts[0].vertices, (std::vector<std::uint32_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(split.parts[1].vertices, (std::vector<std::uint32_t>{1, 2, 3}));
  EXPECT_EQ(split.meshes[0].triangles, (std::vector<Triangle>{{0, 1, 2}, {3, 4, 2}}));
  EXPECT_EQ(split.meshes[1].triangles, (std::vector<Triangle>{{0, 2, 1}}));
  EXPECT_EQ(split.meshes[0].polygon, (std::vector<std::uint32_t>{0, 2}));
  // Vertices 1, 2, 3 belong to the skin; vertex 4 was pinned by the caller.
  EXPECT_EQ(split.pins[0], (std::vector<std::uint8_t>{0, 1, 1, 1, 1}));
  split.meshes[0].positions[0] = {-1, -1, -1};
  std::vector<Mesh> sources{mesh};
  merge_positions(split, sources);
  EXPECT_EQ(sources[0].positions[0], (Vec3{-1, -1, -1}));
  EXPECT_EQ(sources[0].positions[3], (Vec3{1, 1, 0}));
  const std::vector<Mesh> again = apply_split(split, sources);
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again[0].positions[0], (Vec3{-1, -1, -1}));
  EXPECT_EQ(again[1].role, Role::kObstacle);
  // Without patterns nothing changes.
  const RoleSplit same = split_by_name({mesh}, {}, {});
  ASSERT_EQ(same.meshes.size(), 1u);
  EXPECT_EQ(same.meshes[0].role, Role::kMovable);
  EXPECT_TRUE(same.parts[0].vertices.empty());
}

}  // namespace
}  // namespace untangle
