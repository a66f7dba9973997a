// Unit-free repair (issue 21): a scene scaled by a power of two is the same scene in other units,
// represented exactly, so `fix` must give the same positions scaled by the same factor, bit for
// bit, with the same counts. Every tolerance, step and tie-break is relative to the geometry and
// every construction homogeneous in the coordinates; one that is not (CGAL's constructed point
// where a ray meets a triangle, used by the region moves and the continuation, differed in its
// last bits) turns into other moves a few iterations later. Before that was found, 218 of 300
// random tangles wrote other positions at 1024 times their size, and 11 of them changed between
// clean and unresolved. A scale that is not a power of two (millimetres against metres) rounds
// every coordinate and is not covered here. A half turn about a coordinate axis is exact too, and
// covered (RotationFree below).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "scenes/random_tangles.h"
#include "scenes/scenes.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"
#include "untangle/read_meshes.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;

// A change of the coordinates that floating point makes exactly: a scale by a power of two, or a
// half turn about a coordinate axis (two coordinates negated).
struct Exact {
  std::string name;
  double length_factor;  // what it does to lengths
  std::function<Vec3(const Vec3&)> map;
};

Exact scale_by(double factor) {
  return {"scaled by " + std::to_string(factor), factor, [factor](const Vec3& p) {
            return Vec3{p[0] * factor, p[1] * factor, p[2] * factor};
          }};
}

Exact half_turn_about(int axis) {
  return {"turned half round axis " + std::to_string(axis), 1.0, [axis](const Vec3& p) {
            Vec3 q = p;
            for (int k = 0; k < 3; ++k)
              if (k != axis) q[k] = -q[k];
            return q;
          }};
}

// Runs fix on `meshes` and on them changed by each of `changes`, and compares: the same counts,
// and every position the same changed, bit for bit. Returns the unchanged scene's result.
FixResult expect_same_changed(const std::vector<Mesh>& meshes, const std::vector<Exact>& changes,
                              const std::string& name, const FixOptions& options = FixOptions{}) {
  std::vector<Mesh> plain = meshes;
  const FixResult a = fix_meshes(plain, options);
  for (const Exact& change : changes) {
    SCOPED_TRACE(name + " " + change.name);
    std::vector<Mesh> other = meshes;
    for (Mesh& mesh : other)
      for (Vec3& p : mesh.positions) p = change.map(p);
    const FixResult b = fix_meshes(other, options);
    EXPECT_EQ(a.clean, b.clean);
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_EQ(a.before.crossings, b.before.crossings);
    EXPECT_EQ(a.after.crossings, b.after.crossings);
    EXPECT_EQ(a.after.inside_vertices, b.after.inside_vertices);
    EXPECT_EQ(a.relax_sweeps, b.relax_sweeps);
    EXPECT_EQ(a.after.contour_length * change.length_factor, b.after.contour_length);
    std::size_t differ = 0, moved = 0;
    for (std::size_t m = 0; m < plain.size(); ++m)
      for (std::size_t i = 0; i < plain[m].positions.size(); ++i) {
        const Vec3& p = plain[m].positions[i];
        if (p != meshes[m].positions[i]) ++moved;
        if (change.map(p) != other[m].positions[i]) ++differ;
      }
    EXPECT_GT(moved, 0u) << "nothing moved: the case tests nothing";
    EXPECT_EQ(differ, 0u) << "positions that are not the same changed, of " << moved << " moved";
  }
  return a;
}

// The shipped garment on its body: the region moves' ray candidates decide part of its repair.
TEST(UnitFree, ShippedPairScaledByPowersOfTwo) {
  const fs::path dir = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman";
  std::vector<Mesh> meshes = read_meshes((dir / "male_casualsuit04.obj").string(), Role::kMovable);
  for (Mesh& body : read_meshes((dir / "male_generic.obj").string(), Role::kObstacle))
    meshes.push_back(std::move(body));
  expect_same_changed(meshes, {scale_by(1024.0), scale_by(1.0 / 1024.0)}, "shipped pair");
}

// Random tangles that wrote other positions at 1024 times their size: two that ended clean at
// one size and unresolved at the other (19, 173), and two that end unresolved at both (42, 44:
// the unresolved run's relaxation too).
TEST(UnitFree, RandomTanglesScaledByPowersOfTwo) {
  for (std::uint64_t seed : {19u, 42u, 44u, 173u}) {
    const std::vector<Mesh> meshes = scenes::scene_meshes(scenes::random_tangle(seed).scene);
    expect_same_changed(meshes, {scale_by(1024.0), scale_by(1.0 / 1024.0)},
                        "random tangle " + std::to_string(seed));
  }
}

// The continuation, where it runs: seeds 42 and 44 are clean beyond the bounds after their
// retries, and the continuation runs. Its plan measures the thickness behind each obstacle vertex
// with CGAL's ray; handed a unit direction, the ray's second point mixed the scene's length with
// a fixed one, and at 1024 times the size the plan differed in its last bits (48 coordinates of
// seed 42's) and so did the result (161 of 191 moved positions).
TEST(UnitFree, ContinuationScaledByPowersOfTwo) {
  FixOptions options;
  options.continuation = true;
  for (std::uint64_t seed : {42u, 44u}) {
    const std::vector<Mesh> meshes = scenes::scene_meshes(scenes::random_tangle(seed).scene);
    const FixResult r = expect_same_changed(
        meshes, {scale_by(1024.0), scale_by(1.0 / 1024.0)},
        "random tangle " + std::to_string(seed) + " with the continuation", options);
    EXPECT_TRUE(r.continuation.ran)
        << "seed " << seed << ": no continuation, the test no longer tests";
  }
}

// Rotation-free where floating point allows it: a half turn about a coordinate axis negates two
// coordinates exactly, so the canonical vertex order (by distances from order-free means) and
// every construction (negation-symmetric) follow it, and so do the closest points (ties between
// equally close triangles go to the lowest id, not to CGAL's traversal, which follows the
// coordinates). Before the vertex order was free of it, a half turn about y moved the shipped
// pair's result by up to 0.3% of its diagonal. A quarter turn permutes coordinates, and every
// three-term dot product then adds in another order: not covered.
TEST(RotationFree, ShippedPairTurnedHalfRoundEachAxis) {
  const fs::path dir = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman";
  std::vector<Mesh> meshes = read_meshes((dir / "male_casualsuit04.obj").string(), Role::kMovable);
  for (Mesh& body : read_meshes((dir / "male_generic.obj").string(), Role::kObstacle))
    meshes.push_back(std::move(body));
  expect_same_changed(meshes, {half_turn_about(0), half_turn_about(1), half_turn_about(2)},
                      "shipped pair");
}

// Random tangles in general position. Snapped ones (on a dyadic grid, exact degeneracies) are
// left out: the symbolic perturbation that decides their degenerate configurations moves points
// along the coordinate axes, which do not turn with the scene (DESIGN §2). Of seeds 0 to 39 all
// 29 in general position were the same turned, against 4 before; without the closest points'
// tie-break, 24.
TEST(RotationFree, RandomTanglesTurnedHalfRound) {
  std::size_t tested = 0;
  for (std::uint64_t seed = 0; seed < 16; ++seed) {
    const scenes::RandomTangle tangle = scenes::random_tangle(seed);
    if (tangle.snapped) continue;
    const std::vector<Mesh> meshes = scenes::scene_meshes(tangle.scene);
    if (find_intersections(meshes).counts.crossings == 0) continue;  // nothing would move
    expect_same_changed(meshes, {half_turn_about(1)}, "random tangle " + std::to_string(seed));
    ++tested;
  }
  EXPECT_GE(tested, 8u);
}

}  // namespace
}  // namespace untangle
