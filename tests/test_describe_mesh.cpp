// describe_mesh_in (the figures of `info` and `check --verbose` from the scene topology check
// builds anyway) gives, mesh by mesh, exactly what describe_mesh gives from each mesh alone.
#include <gtest/gtest.h>

#include "scenes/scenes.h"
#include "resolve/canonical_order.h"
#include "topology/describe_mesh.h"
#include "untangle/intersections.h"

namespace untangle {
namespace {

void expect_same(const MeshInfo& a, const MeshInfo& b) {
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.welded_vertices, b.welded_vertices);
  EXPECT_EQ(a.components, b.components);
  EXPECT_EQ(a.boundary_loops, b.boundary_loops);
  EXPECT_EQ(a.boundary_edges, b.boundary_edges);
  EXPECT_EQ(a.non_manifold_edges, b.non_manifold_edges);
  EXPECT_EQ(a.degenerate_triangles, b.degenerate_triangles);
  EXPECT_EQ(a.zero_area_triangles, b.zero_area_triangles);
  EXPECT_EQ(a.closed, b.closed);
  EXPECT_EQ(a.area, b.area);  // bit for bit: sums that do not depend on the numbering
  EXPECT_EQ(a.mean_edge_length, b.mean_edge_length);
}

TEST(DescribeMesh, FromTheSceneTopologyEqualsEachMeshAlone) {
  std::size_t checked = 0;
  for (const scenes::Scene& scene : scenes::named_scenes()) {
    std::vector<Mesh> meshes = scene.movable;
    meshes.insert(meshes.end(), scene.obstacles.begin(), scene.obstacles.end());
    // An unused vertex and a dropped triangle in the first mesh: ranges must still line up.
    Mesh& first = meshes.front();
    first.positions.push_back(first.positions.front());
    first.positions.push_back({1e3, 1e3, 1e3});
    first.triangles.push_back({0, 0, 1});
    first.polygon.push_back(static_cast<std::uint32_t>(first.source_faces++));
    if (!first.triangle_group.empty()) first.triangle_group.push_back(first.triangle_group.back());
    std::vector<MeshInfo> infos;
    find_intersections(meshes, {}, nullptr, &infos);
    ASSERT_EQ(infos.size(), meshes.size());
    // describe_mesh_in on a scene's topology in the canonical numbering describe_mesh uses.
    std::vector<Mesh> canon;
    for (const Mesh& mesh : meshes) canon.push_back(canonical(mesh).mesh);
    const SceneTopology topo = build_topology(canon);
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      SCOPED_TRACE(scene.name + " mesh " + std::to_string(m));
      expect_same(infos[m], describe_mesh(meshes[m]));
      expect_same(describe_mesh_in(topo, m, canon[m]), describe_mesh(meshes[m]));
      ++checked;
    }
    EXPECT_GE(infos.front().degenerate_triangles, 1u);  // the added one
  }
  EXPECT_GT(checked, 10u);
}

}  // namespace
}  // namespace untangle
