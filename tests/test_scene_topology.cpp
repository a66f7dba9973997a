// The welded topology's adjacency: vertex -> edge lists and their neighbour ends agree with the
// edges, on tiny inline meshes, re-run with permuted vertex and face order.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "topology/scene_topology.h"

namespace untangle {
namespace {

// Every vertex's incident edges are listed once, ascending, with the other end of each edge as
// its neighbour; every edge appears in the lists of both its ends and nowhere else.
void expect_adjacency_consistent(const SceneTopology& topo) {
  ASSERT_EQ(topo.vertex_edge_begin.size(), topo.points.size() + 1);
  ASSERT_EQ(topo.vertex_edges.size(), 2 * topo.edges.size());
  ASSERT_EQ(topo.vertex_neighbors.size(), topo.vertex_edges.size());
  for (std::uint32_t v = 0; v < topo.points.size(); ++v) {
    const std::uint32_t first = topo.vertex_edge_begin[v], last = topo.vertex_edge_begin[v + 1];
    EXPECT_TRUE(std::is_sorted(topo.vertex_edges.begin() + first, topo.vertex_edges.begin() + last));
    for (std::uint32_t i = first; i < last; ++i) {
      const auto& edge = topo.edges[topo.vertex_edges[i]];
      ASSERT_TRUE(edge[0] == v || edge[1] == v);
      EXPECT_EQ(topo.vertex_neighbors[i], edge[0] == v ? edge[1] : edge[0]);
      EXPECT_NE(topo.vertex_neighbors[i], v);
      EXPECT_EQ(topo.find_edge(v, topo.vertex_neighbors[i]), topo.vertex_edges[i]);
    }
  }
}

// Two triangles sharing an edge, a fan of three around vertex 0, and a loose triangle welded to
// the fan at one corner (a duplicate position): a bowtie vertex, a boundary, an interior edge.
Mesh fan_and_bowtie() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 0, 0},
                 {0, 0, 0}, {-1, -1, 1}, {0, -1, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {5, 6, 7}};
  return m;
}

TEST(SceneTopology, NeighboursAreTheOtherEndsOfTheEdges) {
  const SceneTopology topo = build_topology({fan_and_bowtie()});
  EXPECT_EQ(topo.points.size(), 7u);  // positions 0 and 5 weld
  expect_adjacency_consistent(topo);
  // Welded vertex 0 touches 1, 2, 3, 4 (the fan) and the loose triangle's two other corners.
  const std::uint32_t first = topo.vertex_edge_begin[0], last = topo.vertex_edge_begin[1];
  std::vector<std::uint32_t> around(topo.vertex_neighbors.begin() + first, topo.vertex_neighbors.begin() + last);
  std::sort(around.begin(), around.end());
  EXPECT_EQ(around, (std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6}));
}

TEST(SceneTopology, NeighboursAreConsistentUnderPermutedInput) {
  std::mt19937 rng(5);
  const Mesh base = fan_and_bowtie();
  for (int round = 0; round < 50; ++round) {
    Mesh m = base;
    std::vector<std::uint32_t> order(m.positions.size());
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<Vec3> positions(m.positions.size());
    for (std::size_t i = 0; i < order.size(); ++i) positions[order[i]] = m.positions[i];
    m.positions = positions;
    for (auto& tri : m.triangles)
      for (auto& v : tri) v = order[v];
    std::shuffle(m.triangles.begin(), m.triangles.end(), rng);
    const SceneTopology topo = build_topology({m, base});  // two meshes: global ids per mesh
    expect_adjacency_consistent(topo);
  }
}

}  // namespace
}  // namespace untangle
