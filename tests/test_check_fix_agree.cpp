// Issue 22 §2: `check` and `fix` count the same crossings before the repair, on every input, in
// any vertex or face order. Detection's symbolic perturbation resolves exact degeneracies (shared
// positions, coplanar faces, an edge through an edge) by vertex ids; fix detects on a canonical
// numbering of each mesh, so check must too, or the two disagree (the CesiumMilkTruck: 671
// against 662).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "test_support.h"
#include "untangle/intersections.h"
#include "untangle/read_meshes.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::run_cli;
using testing::TempDir;
using testing::write_text;

const std::string kTruck = "/usr/share/assimp/models/glTF/CesiumMilkTruck/CesiumMilkTruck.gltf";

// Fisher-Yates with mt19937 (fully specified, unlike std::shuffle).
template <typename T>
void shuffle(std::vector<T>& items, std::mt19937& random) {
  for (std::size_t i = items.size(); i > 1; --i) std::swap(items[i - 1], items[random() % i]);
}

// The mesh with its vertices and triangles in a shuffled order and each triangle's corners
// rotated (orientation kept): the same geometry, another numbering.
Mesh shuffled(const Mesh& mesh, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::vector<std::uint32_t> order(mesh.positions.size());  // order[new] = old
  for (std::uint32_t k = 0; k < order.size(); ++k) order[k] = k;
  shuffle(order, random);
  std::vector<std::uint32_t> new_index(order.size());
  for (std::uint32_t k = 0; k < order.size(); ++k) new_index[order[k]] = k;
  Mesh out;
  out.path = mesh.path;
  out.name = mesh.name;
  out.role = mesh.role;
  out.source_faces = mesh.source_faces;
  for (std::uint32_t old : order) out.positions.push_back(mesh.positions[old]);
  for (const Triangle& t : mesh.triangles) {
    const std::uint32_t r = random() % 3;
    out.triangles.push_back({new_index[t[r]], new_index[t[(r + 1) % 3]], new_index[t[(r + 2) % 3]]});
  }
  shuffle(out.triangles, random);
  return out;
}

// An (n x n)-cell grid sheet, corners at f(i, j).
template <typename F>
void add_grid(Mesh& mesh, int n, F f) {
  const auto first = static_cast<std::uint32_t>(mesh.positions.size());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) mesh.positions.push_back(f(i, j));
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = first + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      mesh.triangles.push_back({a, b, d});
      mesh.triangles.push_back({a, d, c});
    }
  }
}

// One mesh of exact degeneracies, each a self-intersection: a flat 4 x 4 sheet on integer
// coordinates; a coplanar copy shifted by half a cell (edges through edges in its plane); an upright
// sheet in the plane x = 2 through the first sheet's vertices and edges; an exact copy of the first
// sheet (positions shared, welded into it). A second mesh, an upright sheet in y = 2 through both
// flat sheets and the first upright one, crosses it at shared grid points.
std::vector<Mesh> degenerate_scene() {
  Mesh one;
  one.path = "degenerate.obj";
  add_grid(one, 4, [](int i, int j) { return Vec3{double(i), double(j), 0.0}; });
  add_grid(one, 4, [](int i, int j) { return Vec3{i + 0.5, j + 0.5, 0.0}; });
  add_grid(one, 4, [](int i, int j) { return Vec3{2.0, double(i), j - 2.0}; });
  add_grid(one, 4, [](int i, int j) { return Vec3{double(i), double(j), 0.0}; });
  Mesh two;
  two.path = "upright.obj";
  add_grid(two, 4, [](int i, int j) { return Vec3{double(i), 2.0, j - 2.0}; });
  for (Mesh* m : {&one, &two}) m->source_faces = m->triangles.size();
  return {one, two};
}

std::string obj_text(const Mesh& mesh) {
  std::string text;
  char line[128];
  for (const Vec3& p : mesh.positions) {
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    text += line;
  }
  for (const Triangle& t : mesh.triangles) {
    std::snprintf(line, sizeof line, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    text += line;
  }
  return text;
}

// check's and fix's `before` (fix stopped before its first move), as the CLI reports them.
struct Before {
  nlohmann::json check, fix;
};

Before before_of(const std::vector<std::string>& inputs, const TempDir& dir) {
  std::string args;
  for (const std::string& in : inputs) args += " " + quote(in);
  const auto c = run_cli("check" + args + " --report -");
  EXPECT_EQ(c.exit_code, 5) << c.err;
  fs::create_directories(dir.path() / "out");
  const auto f = run_cli("fix" + args + " --output-dir " + quote(dir.file("out")) +
                         " --overwrite --max-iterations 0 -q --report -");
  EXPECT_EQ(f.exit_code, 5) << f.err;
  Before b;
  b.check = nlohmann::json::parse(c.out, nullptr, false)["before"];
  b.fix = nlohmann::json::parse(f.out, nullptr, false)["before"];
  return b;
}

TEST(CheckFixAgree, CesiumMilkTruck) {
  if (!fs::exists(kTruck)) GTEST_SKIP() << "assimp-testmodels is not installed";
  TempDir dir;
  const Before b = before_of({kTruck}, dir);
  ASSERT_TRUE(b.check.is_object() && b.fix.is_object());
  EXPECT_GT(b.check["crossings"].get<std::size_t>(), 0u);
  EXPECT_EQ(b.check, b.fix);
  // The library's detection gives the same counts on the truck's meshes in any order.
  const std::vector<Mesh> meshes = read_meshes(kTruck, Role::kMovable);
  const IntersectionCounts reference = find_intersections(meshes).counts;
  EXPECT_EQ(reference.crossings, b.check["crossings"].get<std::size_t>());
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    std::vector<Mesh> other;
    for (std::size_t m = 0; m < meshes.size(); ++m) other.push_back(shuffled(meshes[m], seed * 10 + m));
    const IntersectionCounts counts = find_intersections(other).counts;
    EXPECT_EQ(counts.crossings, reference.crossings) << "seed " << seed;
    EXPECT_EQ(counts.triangle_pairs, reference.triangle_pairs) << "seed " << seed;
    EXPECT_EQ(counts.contours, reference.contours) << "seed " << seed;
    EXPECT_EQ(counts.loop_vertices, reference.loop_vertices) << "seed " << seed;
  }
}

TEST(CheckFixAgree, DegenerateSceneInAnyOrder) {
  const std::vector<Mesh> scene = degenerate_scene();
  nlohmann::json first;
  for (std::uint32_t seed : {0u, 1u, 2u, 3u, 4u}) {
    TempDir dir;
    std::vector<std::string> inputs;
    for (std::size_t m = 0; m < scene.size(); ++m) {
      const Mesh mesh = seed == 0 ? scene[m] : shuffled(scene[m], seed * 10 + m);
      inputs.push_back(dir.file(fs::path(scene[m].path).filename().string()));
      write_text(inputs.back(), obj_text(mesh));
    }
    const Before b = before_of(inputs, dir);
    ASSERT_TRUE(b.check.is_object() && b.fix.is_object()) << "seed " << seed;
    EXPECT_GT(b.check["crossings"].get<std::size_t>(), 0u);
    EXPECT_EQ(b.check, b.fix) << "seed " << seed;
    // And the same counts whatever the order. Not the contour length: exact duplicate vertices
    // (the copy of the first sheet, welded into it) keep their input order in the canonical
    // numbering, so the walk through the non-manifold edges they make can link other crossings.
    nlohmann::json counts = b.check;
    counts.erase("contour_length");
    if (seed == 0) first = counts;
    EXPECT_EQ(counts, first) << "seed " << seed;
  }
}

}  // namespace
}  // namespace untangle
