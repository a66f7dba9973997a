// measure_scene: the repair's read-only measures of a scene, once per run.
#include "resolve/scene_measures.h"

#include "geometry/vec3.h"
#include "resolve/buried_faces.h"
#include "resolve/region_analysis.h"

namespace untangle {
namespace {

// Buried faces and crossing pairs of the closed obstacle components. Those crossings are
// reported and left alone; region moves never aim at the buried faces.
void find_buried_obstacle_faces(const SceneTopology& topo, int threads, SceneMeasures& m) {
  m.buried.assign(topo.tris.size(), 0);
  std::vector<ClosedSurface> surfaces;
  std::vector<std::uint32_t> of_component(topo.component_mesh.size(), kNone);
  for (std::uint32_t c = 0; c < topo.component_mesh.size(); ++c) {
    if (m.movable_component(topo, c) || m.closed[c] == 0) continue;
    of_component[c] = static_cast<std::uint32_t>(surfaces.size());
    surfaces.push_back({{}, m.closed[c]});
  }
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
    const std::uint32_t s = of_component[topo.tri_component(t)];
    if (s != kNone) surfaces[s].triangles.push_back(t);
  }
  const std::vector<std::vector<std::uint8_t>> flags =
      buried_faces(topo, surfaces, threads, &m.obstacle_crossing_pairs);
  for (std::size_t s = 0; s < surfaces.size(); ++s)
    for (std::size_t k = 0; k < surfaces[s].triangles.size(); ++k)
      m.buried[surfaces[s].triangles[k]] = flags[s][k];
}

}  // namespace

SceneMeasures measure_scene(const SceneTopology& topo, const std::vector<Mesh>& meshes,
                            const PinMask& pins, int threads) {
  SceneMeasures m;
  const std::size_t nv = topo.points.size();
  for (const Mesh& mesh : meshes) m.role.push_back(mesh.role);
  m.free.assign(nv, 0);
  for (std::uint32_t v = 0; v < nv; ++v)
    m.free[v] = meshes[topo.vertex_mesh[v]].role == Role::kMovable ? 1 : 0;
  for (std::size_t k = 0; k < pins.size() && k < meshes.size(); ++k) {
    for (std::size_t i = 0; i < pins[k].size() && i < topo.welded[k].size(); ++i)
      if (pins[k][i]) m.free[topo.welded[k][i]] = 0;
  }
  // Seam vertices (a position shared with another mesh: a collar sewn onto the body) are contact,
  // not penetration (DESIGN §2): they stay where they are, and so stay one point with the other.
  for (std::uint32_t v = 0; v < topo.seam.size(); ++v)
    if (topo.seam[v]) m.free[v] = 0;
  m.mean_edge.assign(meshes.size(), 0.0);
  std::vector<std::size_t> edge_count(meshes.size(), 0);
  m.vertex_edge.assign(nv, 0.0);
  std::vector<std::uint32_t> incident(nv, 0);
  for (const auto& e : topo.edges) {
    const double len = norm(sub(topo.points[e[0]], topo.points[e[1]]));
    const std::uint32_t mesh = topo.vertex_mesh[e[0]];
    m.mean_edge[mesh] += len;
    ++edge_count[mesh];
    for (std::uint32_t v : e) {
      m.vertex_edge[v] += len;
      ++incident[v];
    }
  }
  for (std::size_t k = 0; k < meshes.size(); ++k)
    if (edge_count[k] > 0) m.mean_edge[k] /= static_cast<double>(edge_count[k]);
  for (std::uint32_t v = 0; v < nv; ++v)
    m.vertex_edge[v] =
        incident[v] > 0 ? m.vertex_edge[v] / incident[v] : m.mean_edge[topo.vertex_mesh[v]];
  m.closed = closed_orientations(topo);
  m.oriented.assign(topo.component_mesh.size(), 0);
  m.orientation = face_orientations(topo);
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t)
    if (m.orientation[t] != 0) m.oriented[topo.tri_component(t)] = 1;
  m.component_size.assign(topo.component_mesh.size(), 0);
  for (std::uint32_t v = 0; v < nv; ++v) ++m.component_size[topo.vertex_component[v]];
  find_buried_obstacle_faces(topo, threads, m);
  return m;
}

}  // namespace untangle
