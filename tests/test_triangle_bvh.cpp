// The hierarchy's descents, whole and split into parts for parallel loops, report every pair of
// triangles whose boxes overlap exactly once (against all pairs tested by brute force).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "detect/triangle_bvh.h"
#include "scenes/scenes.h"
#include "topology/scene_topology.h"

namespace untangle {
namespace {

using Pairs = std::vector<std::array<std::uint32_t, 2>>;

std::vector<std::uint32_t> triangles_of(const SceneTopology& topo, std::size_t mesh) {
  std::vector<std::uint32_t> tris;
  for (std::uint32_t t = topo.mesh_tri_begin[mesh]; t < topo.mesh_tri_begin[mesh + 1]; ++t)
    tris.push_back(t);
  return tris;
}

// Every pair (t of `a`, u of `b`, t != u; unordered and each once when a == b) with overlapping
// closed boxes.
Pairs brute_force(const SceneTopology& topo, const std::vector<std::uint32_t>& a,
                  const std::vector<std::uint32_t>& b, bool self) {
  Pairs pairs;
  for (std::uint32_t t : a)
    for (std::uint32_t u : b) {
      if (self && u <= t) continue;
      if (triangle_box(topo, t).overlaps(triangle_box(topo, u))) pairs.push_back({t, u});
    }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

// The pairs of all parts of a split descent, normalised to (min, max) when self, in sorted order;
// duplicates kept, so that a pair reported twice fails the comparison.
Pairs from_parts(const TriangleBvh& a, const TriangleBvh& b, bool self, std::size_t want,
                 std::size_t* parts) {
  Pairs pairs;
  const std::vector<TriangleBvh::Part> split = a.split(b, self, want);
  *parts = split.size();
  for (const TriangleBvh::Part& part : split)
    a.each_pair_in(b, part, self, [&](std::uint32_t t, std::uint32_t u) {
      pairs.push_back(self ? std::array<std::uint32_t, 2>{std::min(t, u), std::max(t, u)}
                           : std::array<std::uint32_t, 2>{t, u});
    });
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

void check_scene(const scenes::Scene& scene) {
  const SceneTopology topo = build_topology(scenes::scene_meshes(scene));
  const std::size_t meshes = topo.mesh_tri_begin.size() - 1;
  for (std::size_t m = 0; m < meshes; ++m) {
    const std::vector<std::uint32_t> own = triangles_of(topo, m);
    const TriangleBvh tree(topo, own);
    const Pairs want_self = brute_force(topo, own, own, true);
    Pairs whole;
    tree.each_pair_self([&](std::uint32_t t, std::uint32_t u) {
      whole.push_back({std::min(t, u), std::max(t, u)});
    });
    std::sort(whole.begin(), whole.end());
    EXPECT_EQ(whole, want_self) << scene.name << " mesh " << m << " self, whole descent";
    for (std::size_t want : {1, 2, 7, 64, 100000}) {
      std::size_t parts = 0;
      EXPECT_EQ(from_parts(tree, tree, true, want, &parts), want_self)
          << scene.name << " mesh " << m << " self, " << want << " parts wanted";
      if (want <= own.size() / 8) {
        EXPECT_GE(parts, want) << scene.name << " mesh " << m;
      }
    }
    for (std::size_t n = m + 1; n < meshes; ++n) {
      const std::vector<std::uint32_t> other = triangles_of(topo, n);
      const TriangleBvh other_tree(topo, other);
      const Pairs want_between = brute_force(topo, own, other, false);
      for (std::size_t want : {1, 2, 7, 64, 100000}) {
        std::size_t parts = 0;
        EXPECT_EQ(from_parts(tree, other_tree, false, want, &parts), want_between)
            << scene.name << " meshes " << m << ", " << n << ", " << want << " parts wanted";
      }
    }
  }
}

TEST(TriangleBvh, SplitDescentsReportEveryOverlappingPairOnce) {
  for (const scenes::Scene& scene : scenes::named_scenes()) check_scene(scene);
}

TEST(TriangleBvh, SplitDescentsOnTheSheetThroughTheCow) {
  if (scenes::cow_path().empty()) GTEST_SKIP() << "the cow (libcgal-demo) is not installed";
  check_scene(scenes::sheet_through_cow(21));
}

}  // namespace
}  // namespace untangle
