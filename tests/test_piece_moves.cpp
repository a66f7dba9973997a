// Pieces moved whole (FixOptions::piece_moves, DESIGN §5 "Pieces moved whole"): a ring through
// the wall of a tube, tori whose tubes pass through one another, a sheet pierced by a torus. No
// local move frees them; the piece moved whole by the shortest clear translation, then repaired,
// does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "resolve/piece_moves.h"
#include "scenes/random_tangles.h"
#include "scenes/scenes.h"
#include "scenes/self_scenes.h"
#include "test_support.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"

namespace untangle {
namespace {

using testing::run_cli;
using testing::TempDir;

// Random tangle 269 (tests/scenes/random_tangles.h): an open tube (movable, 8 x 3 vertices) whose
// wall an obstacle torus passes through near its rim. Scaled by `scale`; the tube's triangles
// midpoint-subdivided `levels` times, the ring's `ring_levels` times.
std::vector<Mesh> ring_through_tube(double scale = 1.0, int levels = 0, int ring_levels = 0) {
  std::vector<Mesh> meshes = scenes::scene_meshes(scenes::random_tangle(269).scene);
  for (auto [m, l] : {std::pair<int, int>{0, levels}, std::pair<int, int>{1, ring_levels}}) {
    if (l == 0) continue;
    Mesh fine = scenes::subdivide_midpoint(meshes[m], l);
    fine.role = meshes[m].role;
    meshes[m] = fine;
  }
  for (Mesh& m : meshes)
    for (Vec3& p : m.positions)
      for (double& x : p) x *= scale;
  return meshes;
}

FixOptions without_piece_moves() {
  FixOptions options;
  options.piece_moves = false;
  return options;
}

// Every vertex of `after` is its `before` position plus one and the same translation (up to
// rounding of the sums), returned.
Vec3 common_shift(const Mesh& before, const Mesh& after) {
  const Vec3 shift{after.positions[0][0] - before.positions[0][0],
                   after.positions[0][1] - before.positions[0][1],
                   after.positions[0][2] - before.positions[0][2]};
  for (std::size_t i = 0; i < before.positions.size(); ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(after.positions[i][k] - before.positions[i][k], shift[k], 1e-12)
          << "vertex " << i;
  return shift;
}

// The repair of `input` without the moves must leave it unresolved (else the scene no longer
// shows what the moves are for); with them it must end clean on an independent detection, the
// moves kept. `meshes` receives the result.
FixResult parted(const std::vector<Mesh>& input, std::vector<Mesh>& meshes) {
  std::vector<Mesh> alone = input;
  EXPECT_FALSE(fix_meshes(alone, without_piece_moves()).clean)
      << "the repair resolves it alone: the scene no longer shows what moving pieces is for";
  meshes = input;
  const FixResult r = fix_meshes(meshes, FixOptions{});
  EXPECT_TRUE(r.clean);
  const Intersections after = find_intersections(meshes);
  EXPECT_EQ(after.counts.crossings, 0u);
  EXPECT_EQ(after.counts.inside_vertices, 0u);
  EXPECT_TRUE(r.piece_moves.kept);
  return r;
}

TEST(PieceMoves, TubeThroughARingIsSlidOffIt) {
  const std::vector<Mesh> input = ring_through_tube();
  ASSERT_GT(find_intersections(input).counts.crossings, 0u);
  std::vector<Mesh> meshes;
  const FixResult r = parted(input, meshes);
  ASSERT_TRUE(r.piece_moves.ran);
  EXPECT_TRUE(r.piece_moves.kept);
  EXPECT_TRUE(r.piece_moves.clean);
  EXPECT_EQ(r.piece_moves.tangled, 1u);
  ASSERT_EQ(r.piece_moves.pieces.size(), 1u);
  EXPECT_EQ(r.piece_moves.pieces[0].mesh, 0u);
  EXPECT_EQ(r.piece_moves.pieces[0].vertex, 0u);
  // The tube moved rigidly, by the translation reported, at most half its diagonal (the longest
  // tried); the ring did not move.
  const Vec3 shift = common_shift(input[0], meshes[0]);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(shift[k], r.piece_moves.pieces[0].shift[k], 1e-12);
  const double length = std::sqrt(shift[0] * shift[0] + shift[1] * shift[1] + shift[2] * shift[2]);
  EXPECT_NEAR(length, r.piece_moves.largest_move, 1e-12);
  EXPECT_LE(r.quality[0].max_displacement_over_diagonal, 0.5 + 1e-12);
  EXPECT_EQ(meshes[1].positions, input[1].positions);
  EXPECT_NEAR(r.quality[0].max_stretch, 1.0, 1e-9);
  EXPECT_EQ(r.quality[0].flipped_faces, 0u);
  EXPECT_NEAR(r.quality[0].max_displacement, length, 1e-9);
}

// Unit-free and order-free: the scene scaled by 1024 gives the positions times 1024, bit for
// bit; listed the other way round, the same positions.
TEST(PieceMoves, ScaledOrListedOtherwiseTheSamePositions) {
  std::vector<Mesh> plain = ring_through_tube();
  std::vector<Mesh> large = ring_through_tube(1024.0);
  ASSERT_TRUE(fix_meshes(plain, FixOptions{}).piece_moves.kept);
  ASSERT_TRUE(fix_meshes(large, FixOptions{}).piece_moves.kept);
  for (std::size_t m = 0; m < plain.size(); ++m)
    for (std::size_t i = 0; i < plain[m].positions.size(); ++i)
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(plain[m].positions[i][k] * 1024.0, large[m].positions[i][k]) << m << " " << i;

  std::vector<Mesh> swapped = ring_through_tube();
  std::swap(swapped[0], swapped[1]);
  const FixResult r = fix_meshes(swapped, FixOptions{});
  ASSERT_TRUE(r.piece_moves.kept);
  EXPECT_EQ(r.piece_moves.pieces[0].mesh, 1u);
  EXPECT_EQ(swapped[1].positions, plain[0].positions);
}

// Only small pieces interlocked with small things, free to move: a tube of more than
// kMaxPieceTriangles triangles (a garment's size), a tube on a ring of more than that (a garment
// piece on a body) and a tube with a pinned vertex stay where the repair left them.
TEST(PieceMoves, LargeOrPinnedPiecesStay) {
  FixOptions one_run;  // no retry, continuation or layering: one repair, then the pieces
  one_run.retries = 0;
  one_run.continuation = false;
  one_run.layering = false;
  for (auto [levels, ring_levels] : {std::pair<int, int>{4, 0}, std::pair<int, int>{0, 3}}) {
    std::vector<Mesh> meshes = ring_through_tube(1.0, levels, ring_levels);
    ASSERT_GT(std::max(meshes[0].triangles.size(), meshes[1].triangles.size()), kMaxPieceTriangles);
    const FixResult r = fix_meshes(meshes, one_run);
    EXPECT_FALSE(r.clean);
    EXPECT_FALSE(r.piece_moves.ran);
  }
  {
    std::vector<Mesh> meshes = ring_through_tube();
    PinMask pins(2);
    pins[0].assign(meshes[0].positions.size(), 0);
    pins[0][3] = 1;
    const FixResult r = fix_meshes(meshes, FixOptions{}, pins);
    EXPECT_FALSE(r.clean);
    EXPECT_FALSE(r.piece_moves.ran);
  }
}

// Random tangles that only moving pieces whole resolves (tests/scenes/random_tangles.h): a sheet
// pierced by a torus (154), three tori whose tubes pass through one another (670), a sheet
// through an obstacle torus's hole and tube (169; 826, the same kind, has been resolved by the
// torus scaled down about its centre since that continuation chooses its factor by depth).
TEST(PieceMoves, InterlockedRandomTanglesAreParted) {
  for (std::uint64_t seed : {154u, 670u, 169u}) {
    const scenes::RandomTangle tangle = scenes::random_tangle(seed);
    SCOPED_TRACE(tangle.description);
    std::vector<Mesh> meshes;
    const FixResult r = parted(scenes::scene_meshes(tangle.scene), meshes);
    EXPECT_GE(r.piece_moves.pieces.size(), 1u);
    EXPECT_LE(r.piece_moves.pieces.size(), r.piece_moves.tangled);
  }
}

// The command line: the summary line, the report's piece_moves, exit 6 (the move is beyond the
// default move bound), and --no-piece-moves: exit 5.
TEST(PieceMoves, CommandLineReportsThePiecesMoved) {
  TempDir dir;
  const std::vector<Mesh> meshes = ring_through_tube();
  scenes::write_obj(meshes[0], dir.file("tube.obj"));
  scenes::write_obj(meshes[1], dir.file("ring.obj"));
  std::filesystem::create_directories(dir.file("out"));
  const std::string common = "fix '" + dir.file("tube.obj") + "' --obstacle '" +
                             dir.file("ring.obj") + "' --output-dir '" + dir.file("out") +
                             "' --overwrite";
  const auto moved = run_cli(common + " --report '" + dir.file("report.json") + "'");
  EXPECT_EQ(moved.exit_code, 6) << moved.out << moved.err;
  EXPECT_NE(moved.out.find("pieces moved whole: 1 of 1 tangled"), std::string::npos) << moved.out;
  const nlohmann::json report = nlohmann::json::parse(testing::read_text(dir.file("report.json")));
  EXPECT_EQ(report["status"], "distorted");
  EXPECT_EQ(report["options"]["piece_moves"], true);
  ASSERT_TRUE(report["piece_moves"].is_object());
  EXPECT_EQ(report["piece_moves"]["moved"], 1);
  EXPECT_EQ(report["piece_moves"]["kept"], true);
  EXPECT_EQ(report["piece_moves"]["pieces"][0]["mesh"], 0);
  EXPECT_EQ(report["piece_moves"]["pieces"][0]["shift"].size(), 3u);

  const auto off = run_cli(common + " --no-piece-moves --report '" + dir.file("off.json") + "'");
  EXPECT_EQ(off.exit_code, 5) << off.out << off.err;
  const nlohmann::json report_off = nlohmann::json::parse(testing::read_text(dir.file("off.json")));
  EXPECT_TRUE(report_off["piece_moves"].is_null());
  EXPECT_EQ(report_off["options"]["piece_moves"], false);
}

}  // namespace
}  // namespace untangle
