// quality_stats: per movable mesh, edge-length change, flipped faces and largest displacement.
#include "resolve/quality_stats.h"

#include <algorithm>
#include <cmath>

#include "geometry/vec3.h"

namespace untangle {

std::vector<QualityStats> quality_stats(const SceneTopology& topo, const std::vector<Vec3>& input,
                                        const SceneMeasures& measures) {
  const std::size_t meshes = measures.role.size();
  std::vector<QualityStats> out(meshes);
  std::vector<std::vector<double>> change(meshes);
  for (const auto& e : topo.edges) {
    const std::uint32_t m = topo.vertex_mesh[e[0]];
    if (measures.role[m] != Role::kMovable) continue;
    const double before = norm(sub(input[e[0]], input[e[1]]));
    if (before <= 0.0) continue;
    change[m].push_back(std::abs(norm(sub(topo.points[e[0]], topo.points[e[1]])) / before - 1.0));
  }
  for (std::size_t m = 0; m < meshes; ++m) {
    std::vector<double>& c = change[m];
    if (c.empty()) continue;
    double sum = 0.0;
    for (double x : c) sum += x;  // in edge order: the same sum at any thread count
    out[m].edge_change_mean = sum / static_cast<double>(c.size());
    std::sort(c.begin(), c.end());
    const std::size_t rank = (95 * c.size() + 99) / 100;  // nearest rank, 1-based
    out[m].edge_change_p95 = c[std::max<std::size_t>(rank, 1) - 1];
    out[m].edge_change_max = c.back();
  }
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
    const std::uint32_t m = topo.tri_mesh[t];
    if (measures.role[m] != Role::kMovable) continue;
    const auto& tri = topo.tris[t];
    const Vec3 n0 = cross(sub(input[tri[1]], input[tri[0]]), sub(input[tri[2]], input[tri[0]]));
    const Vec3 n1 = cross(sub(topo.points[tri[1]], topo.points[tri[0]]),
                          sub(topo.points[tri[2]], topo.points[tri[0]]));
    if (dot(n0, n1) < 0.0) ++out[m].flipped_faces;
  }
  for (std::uint32_t v = 0; v < topo.points.size(); ++v) {
    const std::uint32_t m = topo.vertex_mesh[v];
    if (measures.role[m] != Role::kMovable) continue;
    const double d = norm(sub(topo.points[v], input[v]));
    if (d > out[m].max_displacement) {
      out[m].max_displacement = d;
      out[m].max_displacement_over_mean_edge =
          measures.mean_edge[m] > 0.0 ? d / measures.mean_edge[m] : 0.0;
    }
  }
  return out;
}

}  // namespace untangle
