// Consistent orientation of the faces of each component, and whether a closed one faces outward.
#include "topology/orientations.h"

#include "geometry/vec3.h"

namespace untangle {

std::vector<std::int8_t> face_orientations(const SceneTopology& topo) {
  const std::size_t nt = topo.tris.size();
  std::vector<std::int8_t> sign(nt, 0);
  std::vector<std::uint8_t> broken(topo.component_mesh.size(), 0);
  for (std::uint32_t e = 0; e < topo.edges.size(); ++e)
    if (topo.edge_face_count(e) > 2) broken[topo.vertex_component[topo.edges[e][0]]] = 1;
  // Whether triangle t runs along edge e from its first vertex to its second.
  auto forward = [&](std::uint32_t t, std::uint32_t e) {
    const auto& tri = topo.tris[t];
    for (int k = 0; k < 3; ++k)
      if (tri[k] == topo.edges[e][0] && tri[(k + 1) % 3] == topo.edges[e][1]) return true;
    return false;
  };
  std::vector<std::uint32_t> queue;
  for (std::uint32_t seed = 0; seed < nt; ++seed) {
    if (sign[seed] != 0 || broken[topo.tri_component(seed)]) continue;
    sign[seed] = 1;
    queue.assign(1, seed);
    for (std::size_t i = 0; i < queue.size(); ++i) {
      const std::uint32_t t = queue[i];
      for (std::uint32_t e : topo.tri_edges[t]) {
        if (topo.edge_face_count(e) != 2) continue;
        const std::uint32_t f0 = topo.edge_faces[topo.edge_face_begin[e]];
        const std::uint32_t u = f0 == t ? topo.edge_faces[topo.edge_face_begin[e] + 1] : f0;
        // Consistent neighbours run along their shared edge in opposite directions.
        const std::int8_t want =
            forward(t, e) != forward(u, e) ? sign[t] : static_cast<std::int8_t>(-sign[t]);
        if (sign[u] == 0) {
          sign[u] = want;
          queue.push_back(u);
        } else if (sign[u] != want) {
          broken[topo.tri_component(t)] = 1;  // not orientable
        }
      }
    }
  }
  for (std::uint32_t t = 0; t < nt; ++t)
    if (broken[topo.tri_component(t)]) sign[t] = 0;
  return sign;
}

std::vector<int> closed_orientations(const SceneTopology& topo) {
  const std::size_t n = topo.component_mesh.size();
  // Every edge must have two faces that traverse it in opposite directions.
  std::vector<std::uint8_t> closed(n, 1);
  for (std::uint32_t e = 0; e < topo.edges.size(); ++e) {
    const std::uint32_t c = topo.vertex_component[topo.edges[e][0]];
    if (!closed[c]) continue;
    if (topo.edge_face_count(e) != 2) {
      closed[c] = 0;
      continue;
    }
    int direction = 0;
    for (std::uint32_t i = topo.edge_face_begin[e]; i < topo.edge_face_begin[e + 1]; ++i) {
      const auto& tri = topo.tris[topo.edge_faces[i]];
      for (int k = 0; k < 3; ++k) {
        if (tri[k] == topo.edges[e][0] && tri[(k + 1) % 3] == topo.edges[e][1]) ++direction;
        if (tri[k] == topo.edges[e][1] && tri[(k + 1) % 3] == topo.edges[e][0]) --direction;
      }
    }
    if (direction != 0) closed[c] = 0;
  }
  // Each component's volume about its first triangle's first corner (volume6).
  std::vector<double> volume(n, 0.0);
  std::vector<std::uint8_t> any(n, 0);
  std::vector<Vec3> about(n);
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
    const std::uint32_t k = topo.tri_component(t);
    const auto& tri = topo.tris[t];
    if (!any[k]) about[k] = topo.points[tri[0]];
    volume[k] += volume6(about[k], topo.points[tri[0]], topo.points[tri[1]], topo.points[tri[2]]);
    any[k] = 1;
  }
  std::vector<int> out(n, 0);
  for (std::size_t c = 0; c < n; ++c)
    if (closed[c] && any[c] && volume[c] != 0.0) out[c] = volume[c] > 0.0 ? 1 : -1;
  return out;
}

}  // namespace untangle
