// The fuzz targets' seed corpora (fuzz/corpus), replayed through the same per-input code the
// libFuzzer targets run (fuzz/fuzz_entries.cpp), so every build checks them; and build_contours on
// hand-made pathological crossing sets: it must return, list every crossing on exactly one
// contour and mark the contours whose walk fails as broken.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "fuzz_entries.h"
#include "test_support.h"
#include "topology/scene_topology.h"
#include "untangle/error.h"
#include "untangle/read_meshes.h"

#if defined(__SANITIZE_ADDRESS__)
// The load corpus runs assimp inside this process (the other tests run it in CLI processes), and
// Debian's assimp 5.2 leaks what an importer allocated when it throws on a corrupt file: those
// leaks are suppressed, as scripts/test.sh does for the CLI, so that the suite passes under
// ASan without LSAN_OPTIONS. Leaks in untangle's own code are still reported.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }
#endif

namespace untangle {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> corpus_files(const std::string& name) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(fs::path(UNTANGLE_FUZZ_CORPUS) / name))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<std::uint8_t> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(FuzzCorpus, LoadCorpusReplays) {
  const std::vector<fs::path> files = corpus_files("load");
  ASSERT_GE(files.size(), 10u);
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    const std::vector<std::uint8_t> bytes = read_bytes(file);
    EXPECT_EQ(fuzz::fuzz_load_one(bytes.data(), bytes.size()), 0);
  }
}

TEST(FuzzCorpus, ContoursCorpusReplays) {
  const std::vector<fs::path> files = corpus_files("contours");
  ASSERT_GE(files.size(), 5u);
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    const std::vector<std::uint8_t> bytes = read_bytes(file);
    EXPECT_EQ(fuzz::fuzz_contours_one(bytes.data(), bytes.size()), 0);
  }
}

// ----- what fuzzing found in the loader -----

// The message of read_meshes' error for a file with `content` and `extension`, or "" when it loads
// (then `triangles` is the number of triangles read).
std::string load_error(const std::string& content, const std::string& extension,
                       std::size_t* triangles = nullptr) {
  testing::TempDir dir;
  const std::string path = dir.file("input" + extension);
  std::ofstream(path, std::ios::binary) << content;
  try {
    std::size_t count = 0;
    for (const Mesh& mesh : read_meshes(path, Role::kMovable)) count += mesh.triangles.size();
    if (triangles != nullptr) *triangles = count;
    return "";
  } catch (const Error& e) {
    return e.what();
  }
}

// assimp's OFF importer reads counts glued to the keyword ("OFF3 1 0" is 3 vertices, 1 face): the
// size check must read them the same way, or a small file makes assimp allocate gigabytes
// (fuzz/corpus/load/crash_off_count_glued_to_keyword: 0x55555555 vertices, 17 GB).
TEST(FuzzFindings, OffCountsAreReadAsAssimpReadsThem) {
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";
  EXPECT_NE(
      load_error("OFF" + std::string(68, '3') + "\n4 4 6\n" + body, ".off").find("header claims"),
      std::string::npos);
  EXPECT_NE(
      load_error("OFF1431655765 4 6\n" + body, ".off").find("header claims 1431655765 vertices"),
      std::string::npos);
  EXPECT_NE(load_error("COFF4000000000 1 0\n" + body, ".off").find("header claims"),
            std::string::npos);
  EXPECT_NE(load_error("nOFF 3 4000000000 1 0\n" + body, ".off").find("header claims"),
            std::string::npos);
  EXPECT_NE(load_error("\xEF\xBB\xBFOFF\n4000000000 1 0\n" + body, ".off").find("header claims"),
            std::string::npos);
  EXPECT_NE(load_error("OFF3333333333\n4 4 6\n" + body, "").find("header claims"),
            std::string::npos);
  // Glued but small: read as assimp reads it.
  std::size_t triangles = 0;
  EXPECT_EQ(load_error("OFF4 4 6\n" + body, ".off", &triangles), "");
  EXPECT_EQ(triangles, 4u);
}

// When the importer of a known extension refuses a file, assimp tries every importer on its
// content: a PLY file named .glb reached assimp's PLY importer unchecked, which loops forever
// without end_header (fuzz/corpus/load/crash_ply_named_glb_without_end_header). The size checks
// go by content too. (.gltf files are refused earlier, by the JSON check.)
TEST(FuzzFindings, ChecksGoByContentNotOnlyByExtension) {
  const std::string ply_header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n";
  for (const char* extension : {".glb", ".dae", ".3ds", ".x", ".ms3d", ""}) {
    SCOPED_TRACE(extension);
    EXPECT_NE(load_error(ply_header, extension).find("end_header"), std::string::npos);
    EXPECT_NE(load_error("OFF\n4000000000 1 0\n0 0 0\n", extension).find("header claims"),
              std::string::npos);
  }
  std::size_t triangles = 0;
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_EQ(load_error(ply, ".glb", &triangles), "");
  EXPECT_EQ(triangles, 1u);
}

// ----- build_contours on raw crossing sets -----

Mesh make_mesh(std::vector<Vec3> positions, std::vector<Triangle> triangles) {
  Mesh mesh;
  mesh.path = "test";
  mesh.positions = std::move(positions);
  mesh.triangles = std::move(triangles);
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) mesh.polygon.push_back(t);
  mesh.source_faces = mesh.triangles.size();
  return mesh;
}

// A 2 x 2 sheet in z = 0 over [0, 2]^2 and a vertical strip in y = 0.7 that cuts through it.
std::vector<Mesh> sheet_and_strip() {
  std::vector<Vec3> grid;
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 2; ++i) grid.push_back({double(i), double(j), 0.0});
  std::vector<Triangle> tris;
  for (std::uint32_t j = 0; j < 2; ++j) {
    for (std::uint32_t i = 0; i < 2; ++i) {
      const std::uint32_t a = j * 3 + i, b = a + 1, c = a + 3, d = c + 1;
      tris.push_back({a, b, d});
      tris.push_back({a, d, c});
    }
  }
  return {make_mesh(grid, tris),
          make_mesh({{-1.0, 0.7, -1.0}, {3.0, 0.7, -1.0}, {3.0, 0.7, 1.0}, {-1.0, 0.7, 1.0}},
                    {{0, 1, 2}, {0, 2, 3}})};
}

std::size_t broken_count(const std::vector<TracedContour>& contours) {
  return static_cast<std::size_t>(std::count_if(contours.begin(), contours.end(),
                                                [](const TracedContour& c) { return c.broken; }));
}

struct Scene {
  std::vector<Mesh> meshes = sheet_and_strip();
  SceneTopology topo = build_topology(meshes);
  CrossingSet real = detect_crossings(topo, DetectSettings{});
};

TEST(BuildContoursRaw, RealDetectionGivesOneUnbrokenContour) {
  const Scene scene;
  ASSERT_GE(scene.real.items.size(), 4u);
  const std::vector<TracedContour> contours = build_contours(scene.topo, scene.real);
  ASSERT_EQ(contours.size(), 1u);
  EXPECT_FALSE(contours[0].broken);
  fuzz::check_contours(scene.topo, scene.real, contours, /*from_detection=*/true);
}

// Every crossing dropped in turn: the walk meets a link without partner.
TEST(BuildContoursRaw, MissingPartnerIsBroken) {
  const Scene scene;
  for (std::size_t drop = 0; drop < scene.real.items.size(); ++drop) {
    SCOPED_TRACE(drop);
    std::vector<RawCrossing> items = scene.real.items;
    items.erase(items.begin() + static_cast<std::ptrdiff_t>(drop));
    const CrossingSet set = fuzz::make_crossing_set(items);
    const std::vector<TracedContour> contours = build_contours(scene.topo, set);
    EXPECT_GE(broken_count(contours), 1u);
    fuzz::check_contours(scene.topo, set, contours, /*from_detection=*/false);
  }
}

// Invented crossings: an edge "through" a face it belongs to, one through a face it touches, one
// of the strip's edges through every sheet face (an edge crossing faces that share edges, i.e. one
// surface several times), plus the real ones.
TEST(BuildContoursRaw, InventedCrossingsAreSurvived) {
  const Scene scene;
  const SceneTopology& topo = scene.topo;
  std::vector<RawCrossing> items = scene.real.items;
  auto add = [&](std::uint32_t edge, std::uint32_t face) {
    items.push_back({edge, face, topo.points[topo.edges[edge][0]]});
  };
  add(topo.tri_edges[0][0], 0);
  add(topo.tri_edges[0][1], 1);
  const std::uint32_t strip_edge = topo.tri_edges[topo.mesh_tri_begin[1]][0];
  for (std::uint32_t f = 0; f < topo.mesh_tri_begin[1]; ++f) add(strip_edge, f);
  const CrossingSet set = fuzz::make_crossing_set(items);
  const std::vector<TracedContour> contours = build_contours(topo, set);
  EXPECT_GE(broken_count(contours), 1u);
  fuzz::check_contours(topo, set, contours, /*from_detection=*/false);
}

// Crossings on the edges of a zero-area triangle (collinear corners: kept by the topology, unlike
// triangles with repeated corners) and on a non-manifold edge shared by three triangles.
TEST(BuildContoursRaw, DegenerateAndNonManifoldEdges) {
  std::vector<Mesh> meshes = sheet_and_strip();
  meshes.push_back(make_mesh({{0.5, 0.5, -1.0},
                              {0.5, 0.5, 0.0},
                              {0.5, 0.5, 1.0},
                              {1.5, 0.5, 1.0},
                              {1.5, 1.5, 1.0},
                              {0.5, 1.5, -1.0}},
                             {{0, 1, 2}, {0, 2, 3}, {0, 2, 4}, {0, 2, 5}}));
  const SceneTopology topo = build_topology(meshes);
  const CrossingSet real = detect_crossings(topo, DetectSettings{});
  fuzz::check_contours(topo, real, build_contours(topo, real), /*from_detection=*/true);
  std::vector<RawCrossing> items = real.items;
  for (std::uint32_t t = topo.mesh_tri_begin[2]; t < topo.mesh_tri_begin[3]; ++t) {
    for (std::uint32_t e : topo.tri_edges[t]) {
      for (std::uint32_t f = 0; f < topo.mesh_tri_begin[1]; f += 3) {
        items.push_back({e, f, topo.points[topo.edges[e][0]]});
      }
    }
  }
  const CrossingSet set = fuzz::make_crossing_set(items);
  const std::vector<TracedContour> contours = build_contours(topo, set);
  EXPECT_GE(broken_count(contours), 1u);
  fuzz::check_contours(topo, set, contours, /*from_detection=*/false);
}

}  // namespace
}  // namespace untangle
