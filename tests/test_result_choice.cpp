// The choice between two repairs of the same input (fix_meshes.cpp, `better`): the continuation or
// the layering replaces the attempt kept so far where it ranks better (clean within the bounds,
// then clean, then unresolved), or, both clean beyond the bounds, where it is better in its
// largest edge ratio or its faces beyond the bounds (faces_beyond_bounds) and no worse in the
// other, or, better in one and worse in the other, has fewer faces turned over. Each measure
// alone chose a result with visible damage on MakeHuman garments (DESIGN §5, *Retries and the
// continuation*).
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "resolve/quality_stats.h"
#include "resolve/repair_loop.h"
#include "scenes/scenes.h"

namespace untangle {
namespace {

// A flat 5 x 5 sheet with unit edges along x and y.
std::vector<Mesh> sheet() {
  return {scenes::grid_sheet(5, 5, {0.0, 0.0, 0.0}, {4.0, 0.0, 0.0}, {0.0, 4.0, 0.0}, "sheet")};
}

std::uint32_t vertex_at(const Mesh& m, double x, double y) {
  for (std::uint32_t i = 0; i < m.positions.size(); ++i)
    if (m.positions[i][0] == x && m.positions[i][1] == y) return i;
  ADD_FAILURE() << "no vertex at " << x << ", " << y;
  return 0;
}

std::size_t faces_at(const Mesh& m, std::uint32_t v) {
  std::size_t n = 0;
  for (const Triangle& t : m.triangles) n += (t[0] == v || t[1] == v || t[2] == v) ? 1 : 0;
  return n;
}

// The sheet with the interior vertices at (x, y) lifted by `height`.
std::vector<Mesh> lifted(const std::vector<std::pair<double, double>>& at, double height) {
  std::vector<Mesh> meshes = sheet();
  for (const auto& [x, y] : at) meshes[0].positions[vertex_at(meshes[0], x, y)][2] = height;
  return meshes;
}

// A clean result with the quality of `meshes` against the sheet.
FixResult clean_result(const std::vector<Mesh>& meshes) {
  FixResult r;
  r.clean = true;
  r.quality = measure_quality(sheet(), meshes);
  return r;
}

TEST(ResultChoice, FacesBeyondTheBoundsCountTurnedAndStretchedFaces) {
  const std::vector<Mesh> input = sheet();
  const QualityBounds bounds;  // 1.5, no flip
  EXPECT_EQ(faces_beyond_bounds(input, input, bounds), 0u);
  // Lifted by 2 edges, the edges to the vertex grow to sqrt(5) = 2.24: every face at it.
  const std::uint32_t centre = vertex_at(input[0], 2.0, 2.0);
  EXPECT_EQ(faces_beyond_bounds(input, lifted({{2.0, 2.0}}, 2.0), bounds),
            faces_at(input[0], centre));
  // Lifted by half an edge (1.12): none; with the bound at 1.1, every face at it.
  EXPECT_EQ(faces_beyond_bounds(input, lifted({{2.0, 2.0}}, 0.5), bounds), 0u);
  QualityBounds tight;
  tight.max_stretch = 1.1;
  EXPECT_EQ(faces_beyond_bounds(input, lifted({{2.0, 2.0}}, 0.5), tight),
            faces_at(input[0], centre));
  // Mirrored in x: every face turned over, no edge changed.
  std::vector<Mesh> mirrored = input;
  for (Vec3& p : mirrored[0].positions) p[0] = -p[0];
  EXPECT_EQ(faces_beyond_bounds(input, mirrored, bounds), input[0].triangles.size());
  EXPECT_EQ(measure_quality(input, mirrored)[0].max_stretch, 1.0);
}

TEST(ResultChoice, BothBeyondTheBoundsTheCountsThenTheTurnedFacesDecide) {
  const std::vector<Mesh> input = sheet();
  const QualityBounds bounds;
  const auto better_than = [&](const std::vector<Mesh>& a, const std::vector<Mesh>& b) {
    return better(clean_result(a), a, clean_result(b), b, input, bounds);
  };
  const std::vector<Mesh> one_high = lifted({{2.0, 2.0}}, 2.0);  // 2.24 on the faces at one vertex
  const std::vector<Mesh> one_higher = lifted({{2.0, 2.0}}, 3.0);  // 3.16 on the same faces
  const std::vector<Mesh> two_high = lifted({{1.0, 1.0}, {3.0, 3.0}}, 2.0);  // 2.24, twice as many
  std::vector<Mesh> mirrored = input;  // every face turned over, no edge changed
  for (Vec3& p : mirrored[0].positions) p[0] = -p[0];
  ASSERT_GT(faces_beyond_bounds(input, two_high, bounds),
            faces_beyond_bounds(input, one_high, bounds));

  // As many faces, a smaller largest ratio; as large a ratio, fewer faces: better.
  EXPECT_TRUE(better_than(one_high, one_higher));
  EXPECT_TRUE(better_than(one_high, two_high));
  // Worse in either: not better, whichever way round.
  EXPECT_FALSE(better_than(one_higher, one_high));
  EXPECT_FALSE(better_than(two_high, one_high));
  // Better in one and worse in the other: fewer faces turned over decides. The sheet with every
  // face turned has the smaller ratio (1, no edge changed) over more faces; the lifted sheet wins
  // either way round.
  EXPECT_TRUE(better_than(one_high, mirrored));
  EXPECT_FALSE(better_than(mirrored, one_high));
  // None turned over in either: the attempt kept so far stays.
  EXPECT_FALSE(better_than(two_high, one_higher));
  EXPECT_FALSE(better_than(one_higher, two_high));
  // A tie keeps the attempt kept so far.
  EXPECT_FALSE(better_than(one_high, one_high));
}

TEST(ResultChoice, RankComesFirstAndAnUnresolvedAlternativeIsNeverKept) {
  const std::vector<Mesh> input = sheet();
  const QualityBounds bounds;
  // 1.02, moved 0.035 of the diagonal: within every bound.
  const std::vector<Mesh> within = lifted({{2.0, 2.0}}, 0.2);
  const std::vector<Mesh> beyond = lifted({{2.0, 2.0}}, 2.0);
  EXPECT_TRUE(better(clean_result(within), within, clean_result(beyond), beyond, input, bounds));
  EXPECT_FALSE(better(clean_result(beyond), beyond, clean_result(within), within, input, bounds));
  FixResult unresolved = clean_result(within);
  unresolved.clean = false;
  FixResult kept = clean_result(beyond);
  kept.clean = false;
  EXPECT_FALSE(better(unresolved, within, kept, beyond, input, bounds));
  EXPECT_TRUE(better(clean_result(beyond), beyond, kept, beyond, input, bounds));
}

}  // namespace
}  // namespace untangle
