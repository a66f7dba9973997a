// Building the welded, globally indexed topology of a set of meshes.
#include "topology/scene_topology.h"

#include <algorithm>
#include <cstring>
#include <numeric>

namespace untangle {

std::uint32_t SceneTopology::find_edge(std::uint32_t a, std::uint32_t b) const {
  if (a > b) std::swap(a, b);
  const std::array<std::uint32_t, 2> key{a, b};
  auto it = std::lower_bound(edges.begin(), edges.end(), key);
  if (it == edges.end() || *it != key) return kNone;
  return static_cast<std::uint32_t>(it - edges.begin());
}

SceneTopology build_topology(const std::vector<Mesh>& meshes) {
  SceneTopology topo;
  const std::size_t mesh_count = meshes.size();
  topo.welded.resize(mesh_count);
  topo.degenerate.assign(mesh_count, 0);

  // Weld per mesh: each group of equal positions becomes one welded vertex, numbered in order of
  // its smallest input index (an open-addressing table keyed by the coordinates' bits; -0.0 and
  // 0.0 weld, as they compare equal).
  for (std::size_t m = 0; m < mesh_count; ++m) {
    const std::vector<Vec3>& pos = meshes[m].positions;
    std::size_t capacity = 16;
    while (capacity < 2 * pos.size()) capacity *= 2;
    std::vector<std::uint32_t> table(capacity, kNone);
    std::vector<std::uint32_t> leader(pos.size());
    for (std::uint32_t v = 0; v < pos.size(); ++v) {
      std::uint64_t h = 1469598103934665603ull;
      for (double c : pos[v]) {
        const double normal = c + 0.0;  // -0.0 -> 0.0
        std::uint64_t bits;
        std::memcpy(&bits, &normal, sizeof bits);
        h = (h ^ bits) * 1099511628211ull;
        h ^= h >> 29;
      }
      std::size_t slot = static_cast<std::size_t>(h) & (capacity - 1);
      for (;;) {
        if (table[slot] == kNone) {
          table[slot] = v;
          leader[v] = v;
          break;
        }
        if (pos[table[slot]] == pos[v]) {
          leader[v] = table[slot];
          break;
        }
        slot = (slot + 1) & (capacity - 1);
      }
    }
    topo.mesh_vertex_begin.push_back(static_cast<std::uint32_t>(topo.points.size()));
    std::vector<std::uint32_t>& map = topo.welded[m];
    map.assign(pos.size(), kNone);
    for (std::uint32_t v = 0; v < pos.size(); ++v) {
      if (leader[v] == v) {
        map[v] = static_cast<std::uint32_t>(topo.points.size());
        topo.points.push_back(pos[v]);
        topo.vertex_mesh.push_back(static_cast<std::uint32_t>(m));
        topo.representative.push_back(v);
      } else {
        map[v] = map[leader[v]];
      }
    }
  }
  topo.mesh_vertex_begin.push_back(static_cast<std::uint32_t>(topo.points.size()));

  // Keep triangles with three distinct welded corners.
  for (std::size_t m = 0; m < mesh_count; ++m) {
    topo.mesh_tri_begin.push_back(static_cast<std::uint32_t>(topo.tris.size()));
    const std::vector<Triangle>& tris = meshes[m].triangles;
    for (std::uint32_t t = 0; t < tris.size(); ++t) {
      const std::array<std::uint32_t, 3> w{topo.welded[m][tris[t][0]], topo.welded[m][tris[t][1]],
                                           topo.welded[m][tris[t][2]]};
      if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) {
        ++topo.degenerate[m];
        continue;
      }
      topo.tris.push_back(w);
      topo.tri_mesh.push_back(static_cast<std::uint32_t>(m));
      topo.tri_source.push_back(t);
    }
  }
  topo.mesh_tri_begin.push_back(static_cast<std::uint32_t>(topo.tris.size()));

  // Edges: (v0, v1, triangle) records in (v0, v1, triangle) order, by a counting sort on v0 and a
  // small sort inside each bucket; faces of one edge come out ascending.
  struct Record {
    std::uint32_t a, b, t;
    bool operator<(const Record& o) const {
      return a != o.a ? a < o.a : b != o.b ? b < o.b : t < o.t;
    }
  };
  std::vector<std::uint32_t> bucket(topo.points.size() + 1, 0);
  for (const auto& tri : topo.tris)
    for (int k = 0; k < 3; ++k) ++bucket[std::min(tri[k], tri[(k + 1) % 3]) + 1];
  for (std::size_t v = 0; v < topo.points.size(); ++v) bucket[v + 1] += bucket[v];
  std::vector<Record> records(topo.tris.size() * 3);
  {
    std::vector<std::uint32_t> fill(bucket.begin(), bucket.end() - 1);
    for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        std::uint32_t a = topo.tris[t][k], b = topo.tris[t][(k + 1) % 3];
        if (a > b) std::swap(a, b);
        records[fill[a]++] = {a, b, t};
      }
    }
  }
  for (std::size_t v = 0; v < topo.points.size(); ++v)
    std::sort(records.begin() + bucket[v], records.begin() + bucket[v + 1]);
  topo.tri_edges.assign(topo.tris.size(), {kNone, kNone, kNone});
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (i == 0 || records[i].a != records[i - 1].a || records[i].b != records[i - 1].b) {
      topo.edges.push_back({records[i].a, records[i].b});
      topo.edge_face_begin.push_back(static_cast<std::uint32_t>(topo.edge_faces.size()));
    }
    const std::uint32_t e = static_cast<std::uint32_t>(topo.edges.size() - 1);
    if (topo.edge_faces.size() == topo.edge_face_begin.back() ||
        topo.edge_faces.back() != records[i].t) {
      topo.edge_faces.push_back(records[i].t);
    }
    const auto& tri = topo.tris[records[i].t];
    for (int k = 0; k < 3; ++k) {
      std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      if (a > b) std::swap(a, b);
      if (a == records[i].a && b == records[i].b) topo.tri_edges[records[i].t][k] = e;
    }
  }
  topo.edge_face_begin.push_back(static_cast<std::uint32_t>(topo.edge_faces.size()));

  // Vertex -> edges.
  topo.vertex_edge_begin.assign(topo.points.size() + 1, 0);
  for (const auto& e : topo.edges) {
    ++topo.vertex_edge_begin[e[0] + 1];
    ++topo.vertex_edge_begin[e[1] + 1];
  }
  for (std::size_t v = 0; v < topo.points.size(); ++v) {
    topo.vertex_edge_begin[v + 1] += topo.vertex_edge_begin[v];
  }
  topo.vertex_edges.resize(topo.vertex_edge_begin.back());
  topo.vertex_neighbors.resize(topo.vertex_edge_begin.back());
  std::vector<std::uint32_t> fill(topo.vertex_edge_begin.begin(), topo.vertex_edge_begin.end() - 1);
  for (std::uint32_t e = 0; e < topo.edges.size(); ++e) {
    const std::uint32_t a = topo.edges[e][0], b = topo.edges[e][1];
    topo.vertex_edges[fill[a]] = e;
    topo.vertex_neighbors[fill[a]++] = b;
    topo.vertex_edges[fill[b]] = e;
    topo.vertex_neighbors[fill[b]++] = a;
  }
  // Components: union-find over triangle corners, then numbered by lowest vertex.
  std::vector<std::uint32_t> parent(topo.points.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& tri : topo.tris) {
    for (int k = 1; k < 3; ++k) {
      const std::uint32_t a = find(tri[0]), b = find(tri[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  topo.vertex_component.assign(topo.points.size(), kNone);
  std::vector<std::uint32_t> number(topo.points.size(), kNone);
  for (std::uint32_t v = 0; v < topo.points.size(); ++v) {
    const std::uint32_t root = find(v);
    if (number[root] == kNone) {
      number[root] = static_cast<std::uint32_t>(topo.component_mesh.size());
      topo.component_mesh.push_back(topo.vertex_mesh[v]);
    }
    topo.vertex_component[v] = number[root];
  }
  return topo;
}

std::vector<std::uint32_t> SceneTopology::triangles_at(const std::vector<std::uint32_t>& vertices) const {
  std::vector<std::uint32_t> out;
  for (std::uint32_t v : vertices)
    for (std::uint32_t i = vertex_edge_begin[v]; i < vertex_edge_begin[v + 1]; ++i) {
      const std::uint32_t e = vertex_edges[i];
      for (std::uint32_t k = edge_face_begin[e]; k < edge_face_begin[e + 1]; ++k) out.push_back(edge_faces[k]);
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void update_points(const std::vector<Mesh>& meshes, SceneTopology& topology) {
  for (std::size_t v = 0; v < topology.points.size(); ++v) {
    topology.points[v] = meshes[topology.vertex_mesh[v]].positions[topology.representative[v]];
  }
}

}  // namespace untangle
