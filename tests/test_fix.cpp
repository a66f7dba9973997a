// untangle fix end to end: every generated scene ends intersection-free as re-read from the written
// files; only positions change; far vertices keep their bits; pins hold; bad outputs are refused.
#include <gtest/gtest.h>

#include <assimp/cexport.h>
#include <assimp/cimport.h>
#include <assimp/scene.h>
#include <dlfcn.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <set>
#include <sstream>
#include <type_traits>

#include "io/assimp_module.h"
#include "scenes/scenes.h"
#include "scene_files.h"
#include "test_support.h"
#include "untangle/intersections.h"
#include "untangle/read_meshes.h"

namespace untangle {
namespace {

using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;
using testing::write_text;

using Files = testing::SceneFiles;
using testing::write_scene;

// Crossings among the written outputs and the obstacles (obstacle pairs left out, as fix does).
IntersectionCounts detect_on_files(const std::vector<std::string>& movable,
                                   const std::vector<std::string>& obstacles) {
  std::vector<Mesh> meshes;
  for (const auto& p : movable)
    for (auto& m : read_meshes(p, Role::kMovable)) meshes.push_back(std::move(m));
  for (const auto& p : obstacles)
    for (auto& m : read_meshes(p, Role::kObstacle)) meshes.push_back(std::move(m));
  DetectOptions options;
  options.skip_obstacle_pairs = true;
  return find_intersections(meshes, options).counts;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// A sheet and an off-centre sphere, both movable: the sheet cuts a cap off the sphere (CL/CL).
scenes::Scene sheet_and_offcentre_sphere() {
  scenes::Scene scene;
  scene.name = "sheet_and_offcentre_sphere";
  scene.movable.push_back(scenes::grid_sheet(25, 25, {-2.0137, -2.0071, 0.0113}, {4, 0, 0}, {0, 4, 0}, "sheet"));
  scene.movable.push_back(scenes::uv_sphere({0.1031, -0.0523, 0.6127}, 1.0, 32, 16, "sphere"));
  return scene;
}

std::vector<scenes::Scene> fix_scenes() {
  std::vector<scenes::Scene> all;
  for (const auto& s : scenes::named_scenes())
    if (s.name != "folded_sheet" && s.name != "sheet_through_sphere") all.push_back(s);
  all.push_back(sheet_and_offcentre_sphere());
  return all;
}

// assimp's C API, reached through the assimp module (which links libassimp; no executable does):
// dlsym on the module's handle searches the libraries it loaded.
struct AssimpC {
  decltype(&aiImportFile) import_file = nullptr;
  decltype(&aiReleaseImport) release_import = nullptr;
  decltype(&aiGetErrorString) error_string = nullptr;
  decltype(&aiGetExportFormatCount) export_format_count = nullptr;
  decltype(&aiGetExportFormatDescription) export_format_description = nullptr;
  decltype(&aiReleaseExportFormatDescription) release_export_format_description = nullptr;
  decltype(&aiExportScene) export_scene = nullptr;

  static const AssimpC& get() {
    static const AssimpC c = [] {
      AssimpC a;
      void* module = dlopen(assimp_module::search_path().front().c_str(), RTLD_NOW | RTLD_LOCAL);
      if (module == nullptr) return a;
      auto find = [&](auto& f, const char* name) {
        f = reinterpret_cast<std::remove_reference_t<decltype(f)>>(dlsym(module, name));
      };
      find(a.import_file, "aiImportFile");
      find(a.release_import, "aiReleaseImport");
      find(a.error_string, "aiGetErrorString");
      find(a.export_format_count, "aiGetExportFormatCount");
      find(a.export_format_description, "aiGetExportFormatDescription");
      find(a.release_export_format_description, "aiReleaseExportFormatDescription");
      find(a.export_scene, "aiExportScene");
      return a;
    }();
    return c;
  }
  bool complete() const {
    return import_file && release_import && error_string && export_format_count &&
           export_format_description && release_export_format_description && export_scene;
  }
  // A scene read without post-processing (as Assimp::Importer::ReadFile(path, 0)), released
  // with its pointer.
  std::shared_ptr<const aiScene> read(const std::string& path) const {
    return std::shared_ptr<const aiScene>(import_file(path.c_str(), 0), [this](const aiScene* s) {
      if (s != nullptr) release_import(s);
    });
  }
};

class FixScene : public ::testing::TestWithParam<std::string> {};

TEST_P(FixScene, EndsCleanOnTheWrittenFiles) {
  scenes::Scene scene;
  for (const auto& s : fix_scenes())
    if (s.name == GetParam()) scene = s;
  TempDir dir;
  const Files files = write_scene(scene, dir);
  std::filesystem::create_directories(dir.file("out"));
  ASSERT_GT(detect_on_files(files.movable, files.obstacles).crossings, 0u) << "scene must start tangled";
  const auto r = run_cli("fix" + files.inputs_args() + " --output-dir " + quote(dir.file("out")) +
                         " --report " + quote(dir.file("report.json")));
  ASSERT_TRUE(testing::intersection_free(r.exit_code)) << r.out << r.err;
  std::vector<std::string> outputs;
  for (const auto& in : files.movable)
    outputs.push_back(dir.file("out/" + std::filesystem::path(in).filename().string()));
  EXPECT_EQ(detect_on_files(outputs, files.obstacles).crossings, 0u);
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const Mesh before = read_meshes(files.movable[i], Role::kMovable).front();
    const Mesh after = read_meshes(outputs[i], Role::kMovable).front();
    EXPECT_EQ(before.positions.size(), after.positions.size());
    EXPECT_EQ(before.triangles, after.triangles);
  }
  const auto report = nlohmann::json::parse(read_text(dir.file("report.json")));
  EXPECT_EQ(report["command"], "fix");
  EXPECT_TRUE(testing::intersection_free(report["status"].get<std::string>()));
  EXPECT_EQ(report["after"]["crossings"], 0);
  EXPECT_GT(report["before"]["crossings"].get<int>(), 0);
  for (const char* key : {"iterations", "history", "displacement", "before", "after", "timing_ms"})
    EXPECT_TRUE(report.contains(key)) << key;
  for (const char* key : {"max", "mean", "max_over_mean_edge"})
    EXPECT_TRUE(report["displacement"].contains(key)) << key;
  for (const char* key : {"resolve", "write"}) EXPECT_TRUE(report["timing_ms"].contains(key)) << key;
  const auto& first = report["history"][0];
  for (const char* key : {"iteration", "crossings", "contour_length", "elapsed_ms", "stage"})
    EXPECT_TRUE(first.contains(key)) << key;
}

INSTANTIATE_TEST_SUITE_P(Scenes, FixScene, ::testing::Values("strip_through_sheet", "sheets_corner",
                                                             "tube_around_body", "garment_four_loops",
                                                             "sheet_on_spikes",
                                                             "sheet_and_offcentre_sphere"),
                         [](const auto& info) { return info.param; });

// Vertices more than a few rings away from every initial crossing (and outside every illegal
// region, which on the spikes lies within those rings) keep their input line byte for byte.
TEST(Fix, FarVerticesKeepTheirBits) {
  const scenes::Scene scene = scenes::sheet_on_spikes();
  TempDir dir;
  const Files files = write_scene(scene, dir);
  std::vector<Mesh> meshes = scenes::scene_meshes(scene);
  const Intersections found = find_intersections(meshes);
  // Ring distance on the sheet (mesh 0) from every vertex of a crossing edge or face.
  const Mesh& sheet = meshes[0];
  std::vector<std::set<std::uint32_t>> neighbours(sheet.positions.size());
  for (const auto& t : sheet.triangles)
    for (int k = 0; k < 3; ++k) {
      neighbours[t[k]].insert(t[(k + 1) % 3]);
      neighbours[t[(k + 1) % 3]].insert(t[k]);
    }
  std::vector<int> ring(sheet.positions.size(), -1);
  std::vector<std::uint32_t> frontier;
  for (const Crossing& c : found.crossings) {
    std::vector<std::uint32_t> seeds;
    if (c.edge_mesh == 0) seeds = {c.edge_v0, c.edge_v1};
    if (c.face_mesh == 0) seeds.insert(seeds.end(), sheet.triangles[c.face].begin(), sheet.triangles[c.face].end());
    for (std::uint32_t v : seeds)
      if (ring[v] < 0) {
        ring[v] = 0;
        frontier.push_back(v);
      }
  }
  ASSERT_FALSE(frontier.empty());
  for (std::size_t i = 0; i < frontier.size(); ++i)
    for (std::uint32_t w : neighbours[frontier[i]])
      if (ring[w] < 0) {
        ring[w] = ring[frontier[i]] + 1;
        frontier.push_back(w);
      }
  // Without the shape relaxation nothing beyond 3 rings moves; the relaxation moves the moved
  // vertices' neighbourhood too (6 rings around them, relax_shape.cpp), and nothing beyond that.
  for (const auto& [extra, reach] : {std::pair<std::string, int>{" --no-relax", 3}, {"", 3 + 6}}) {
    SCOPED_TRACE(extra.empty() ? "relaxed" : "not relaxed");
    const auto r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("out.obj")) +
                           " --overwrite" + extra);
    ASSERT_TRUE(testing::intersection_free(r.exit_code)) << r.err;
    const auto in = lines_of(read_text(files.movable[0]));
    const auto out = lines_of(read_text(dir.file("out.obj")));
    ASSERT_EQ(in.size(), out.size());
    std::size_t vertex = 0, far = 0, moved_near = 0;
    for (std::size_t i = 0; i < in.size(); ++i) {
      if (in[i].rfind("v ", 0) != 0) continue;
      const bool is_far = ring[vertex] < 0 || ring[vertex] > reach;
      if (is_far) {
        ++far;
        EXPECT_EQ(in[i], out[i]) << "vertex " << vertex << " at ring " << ring[vertex] << " moved";
      } else if (in[i] != out[i]) {
        ++moved_near;
      }
      ++vertex;
    }
    // The test means something: many vertices are beyond 3 rings (the spikes' sheet has few
    // beyond 9).
    EXPECT_GT(far, reach == 3 ? 100u : 0u);
    EXPECT_GT(moved_near, 0u);
  }
}

// OBJ in, OBJ out: every line but the v lines is identical (UVs, normals, groups, materials, faces,
// comments), and the v lines keep their count and order.
TEST(Fix, ObjKeepsEverythingButPositions) {
  const scenes::Scene scene = scenes::sheet_on_spikes();
  TempDir dir;
  const Files files = write_scene(scene, dir);
  // Rewrite the sheet with comments, a material library, groups, UVs, normals and v/vt/vn faces.
  const Mesh& sheet = scene.movable[0];
  std::ostringstream obj;
  obj.precision(17);
  obj << "# a sheet with everything a garment file has\r\nmtllib cloth.mtl\n";
  for (const auto& p : sheet.positions) obj << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (std::size_t i = 0; i < sheet.positions.size(); ++i)
    obj << "vt " << (i % 7) / 7.0 << " " << (i % 11) / 11.0 << "\n";
  obj << "vn 0 0 1\ng front\nusemtl cotton\ns 1\n";
  for (std::size_t t = 0; t < sheet.triangles.size(); ++t) {
    if (t == sheet.triangles.size() / 2) obj << "g back\nusemtl silk\n";
    const auto& tri = sheet.triangles[t];
    obj << "f";
    for (auto v : tri) obj << " " << v + 1 << "/" << v + 1 << "/1";
    obj << "\n";
  }
  write_text(files.movable[0], obj.str());
  const auto r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("out.obj")));
  ASSERT_TRUE(testing::intersection_free(r.exit_code)) << r.err;
  const auto in = lines_of(read_text(files.movable[0]));
  const auto out = lines_of(read_text(dir.file("out.obj")));
  ASSERT_EQ(in.size(), out.size());
  std::size_t changed = 0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in[i].rfind("v ", 0) == 0) {
      ASSERT_EQ(out[i].rfind("v ", 0), 0u);
      changed += in[i] != out[i] ? 1 : 0;
    } else {
      EXPECT_EQ(in[i], out[i]) << "line " << i + 1;
    }
  }
  EXPECT_GT(changed, 0u);
  EXPECT_EQ(detect_on_files({dir.file("out.obj")}, files.obstacles).crossings, 0u);
}

// OFF is written by us (assimp has no OFF writer): only the coordinates of moved vertices change;
// comments, colours and faces stay byte for byte.
TEST(Fix, OffKeepsEverythingButPositions) {
  const scenes::Scene scene = scenes::sheet_on_spikes();
  TempDir dir;
  const Files files = write_scene(scene, dir);
  const Mesh& sheet = scene.movable[0];
  std::ostringstream off;
  off.precision(17);
  off << "OFF\n# a sheet with per-vertex colours\n" << sheet.positions.size() << " "
      << sheet.triangles.size() << " 0\n";
  for (const auto& p : sheet.positions) off << p[0] << " " << p[1] << " " << p[2] << " 0.5 0.25 1\n";
  for (const auto& t : sheet.triangles) off << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  write_text(dir.file("sheet.off"), off.str());
  const auto r = run_cli("fix " + quote(dir.file("sheet.off")) + " --obstacle " + quote(files.obstacles[0]) +
                         " -o " + quote(dir.file("out.off")));
  ASSERT_TRUE(testing::intersection_free(r.exit_code)) << r.err;
  const auto in = lines_of(read_text(dir.file("sheet.off")));
  const auto out = lines_of(read_text(dir.file("out.off")));
  ASSERT_EQ(in.size(), out.size());
  std::size_t changed = 0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const bool vertex_line = i >= 3 && i < 3 + sheet.positions.size();
    if (!vertex_line) {
      EXPECT_EQ(in[i], out[i]) << "line " << i + 1;
    } else if (in[i] != out[i]) {
      ++changed;
      EXPECT_EQ(out[i].substr(out[i].size() - 11), " 0.5 0.25 1") << out[i];
    }
  }
  EXPECT_GT(changed, 0u);
  EXPECT_EQ(detect_on_files({dir.file("out.off")}, files.obstacles).crossings, 0u);
}

// Other formats through assimp: vertex count and order, faces, UVs and normals come back unchanged.
class FixFormat : public ::testing::TestWithParam<std::string> {};

TEST_P(FixFormat, KeepsTopologyUvsAndNormals) {
  const std::string format = GetParam();  // assimp export id
  const scenes::Scene scene = scenes::sheet_on_spikes();
  TempDir dir;
  const Files files = write_scene(scene, dir);
  // Give the sheet UVs and normals, then convert it with assimp.
  const Mesh& sheet = scene.movable[0];
  std::ostringstream obj;
  obj.precision(17);
  for (const auto& p : sheet.positions) obj << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (std::size_t i = 0; i < sheet.positions.size(); ++i)
    obj << "vt " << (i % 7) / 7.0 << " " << (i % 11) / 11.0 << "\n";
  obj << "vn 0 0 1\n";
  for (const auto& tri : sheet.triangles) {
    obj << "f";
    for (auto v : tri) obj << " " << v + 1 << "/" << v + 1 << "/1";
    obj << "\n";
  }
  write_text(dir.file("sheet.obj"), obj.str());
  const AssimpC& assimp = AssimpC::get();
  ASSERT_TRUE(assimp.complete()) << "assimp's C API not found through the assimp module";
  std::string ext;
  for (std::size_t i = 0; i < assimp.export_format_count(); ++i) {
    const aiExportFormatDesc* d = assimp.export_format_description(i);
    if (d->id == format) ext = d->fileExtension;
    assimp.release_export_format_description(d);
  }
  ASSERT_FALSE(ext.empty()) << format;
  const std::string input = dir.file("sheet." + ext);
  {
    const auto s = assimp.read(dir.file("sheet.obj"));
    ASSERT_NE(s, nullptr);
    ASSERT_EQ(assimp.export_scene(s.get(), format.c_str(), input.c_str(), 0), aiReturn_SUCCESS)
        << assimp.error_string();
  }
  const std::string output = dir.file("out/sheet." + ext);
  std::filesystem::create_directories(dir.file("out"));
  const auto r = run_cli("fix " + quote(input) + " --obstacle " + quote(files.obstacles[0]) + " -o " + quote(output));
  ASSERT_TRUE(testing::intersection_free(r.exit_code)) << r.out << r.err;

  const auto before = assimp.read(input);
  ASSERT_NE(before, nullptr);
  const auto after = assimp.read(output);
  ASSERT_NE(after, nullptr) << assimp.error_string();
  ASSERT_EQ(before->mNumMeshes, after->mNumMeshes);
  std::size_t moved = 0;
  for (unsigned m = 0; m < before->mNumMeshes; ++m) {
    const aiMesh& x = *before->mMeshes[m];
    const aiMesh& y = *after->mMeshes[m];
    ASSERT_EQ(x.mNumVertices, y.mNumVertices);
    ASSERT_EQ(x.mNumFaces, y.mNumFaces);
    for (unsigned f = 0; f < x.mNumFaces; ++f) {
      ASSERT_EQ(x.mFaces[f].mNumIndices, y.mFaces[f].mNumIndices);
      for (unsigned k = 0; k < x.mFaces[f].mNumIndices; ++k)
        ASSERT_EQ(x.mFaces[f].mIndices[k], y.mFaces[f].mIndices[k]);
    }
    ASSERT_EQ(x.HasTextureCoords(0), y.HasTextureCoords(0));
    ASSERT_EQ(x.HasNormals(), y.HasNormals());
    for (unsigned v = 0; v < x.mNumVertices; ++v) {
      if (x.HasTextureCoords(0)) {
        EXPECT_EQ(x.mTextureCoords[0][v], y.mTextureCoords[0][v]);
      }
      if (x.HasNormals()) {
        EXPECT_EQ(x.mNormals[v], y.mNormals[v]);
      }
      moved += x.mVertices[v] != y.mVertices[v] ? 1 : 0;
    }
  }
  EXPECT_GT(moved, 0u);
  EXPECT_EQ(detect_on_files({output}, files.obstacles).crossings, 0u);
}

INSTANTIATE_TEST_SUITE_P(Formats, FixFormat, ::testing::Values("ply", "plyb", "stl", "stlb", "gltf2", "glb2", "fbxa"),
                         [](const auto& info) { return info.param; });

// Pinning every vertex of the only movable mesh leaves nothing that may move: unresolved, exit 5,
// the output still written (unchanged), the remaining contours listed.
TEST(Fix, AllPinnedEndsUnresolved) {
  const scenes::Scene scene = scenes::tube_around_body();
  TempDir dir;
  const Files files = write_scene(scene, dir);
  std::string pins = "# every vertex\n";
  for (std::size_t v = 0; v < scene.movable[0].positions.size(); ++v) pins += std::to_string(v) + "\n";
  write_text(dir.file("pins.txt"), pins);
  const auto r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("out.obj")) + " --pin " +
                         quote(dir.file("pins.txt")) + " --report -");
  EXPECT_EQ(r.exit_code, 5) << r.err;
  const auto report = nlohmann::json::parse(r.out);
  EXPECT_EQ(report["status"], "unresolved");
  EXPECT_GT(report["contours"].size(), 0u);
  EXPECT_EQ(read_text(dir.file("out.obj")), read_text(files.movable[0]));
}

// Pinned vertices keep their exact coordinates while the rest resolves.
TEST(Fix, PinnedVerticesDoNotMove) {
  const scenes::Scene scene = scenes::sheet_on_spikes();
  TempDir dir;
  const Files files = write_scene(scene, dir);
  std::string pins;
  const std::size_t n = scene.movable[0].positions.size();
  for (std::size_t v = 0; v < n; v += 3) pins += "0 " + std::to_string(v) + "\n";
  write_text(dir.file("pins.txt"), pins);
  const auto r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("out.obj")) + " --pin " +
                         quote(dir.file("pins.txt")));
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 5) << r.err;
  const auto in = lines_of(read_text(files.movable[0]));
  const auto out = lines_of(read_text(dir.file("out.obj")));
  std::size_t vertex = 0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in[i].rfind("v ", 0) != 0) continue;
    if (vertex % 3 == 0) {
      EXPECT_EQ(in[i], out[i]) << "pinned vertex " << vertex;
    }
    ++vertex;
  }
}

TEST(Fix, RefusesBadOutputsBeforeWorking) {
  const scenes::Scene scene = scenes::tube_around_body();
  TempDir dir;
  const Files files = write_scene(scene, dir);
  const std::string input = files.movable[0];
  // The output is the input.
  auto r = run_cli("fix" + files.inputs_args() + " -o " + quote(input));
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("input"), std::string::npos);
  // An existing output without --overwrite; with it, it is replaced.
  write_text(dir.file("exists.obj"), "keep me\n");
  r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("exists.obj")));
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_EQ(read_text(dir.file("exists.obj")), "keep me\n");
  r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("exists.obj")) + " --overwrite");
  EXPECT_TRUE(testing::intersection_free(r.exit_code)) << r.err;
  // A folder that does not exist.
  r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("no/such/out.obj")));
  EXPECT_EQ(r.exit_code, 4);
  // The wrong number of outputs is a usage error.
  r = run_cli("fix" + files.inputs_args());
  EXPECT_EQ(r.exit_code, 2);
  // Nothing but the inputs and the one replaced output is left in the folder.
  std::size_t files_left = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    (void)entry;
    ++files_left;
  }
  EXPECT_EQ(files_left, files.movable.size() + files.obstacles.size() + 1);
}

}  // namespace
}  // namespace untangle
