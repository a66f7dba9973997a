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

namespace {

// A hash of a position's coordinate bits (-0.0 and 0.0 alike, as they compare equal).
std::uint64_t position_hash(const Vec3& p) {
  std::uint64_t h = 1469598103934665603ull;
  for (double c : p) {
    const double normal = c + 0.0;  // -0.0 -> 0.0
    std::uint64_t bits;
    std::memcpy(&bits, &normal, sizeof bits);
    h = (h ^ bits) * 1099511628211ull;
    h ^= h >> 29;
  }
  return h;
}

// The kept triangles flagged `turned` (a repeat of theirs ran the other way, so the file does not
// say which winding is meant) take the winding of their neighbours: a search across edges from
// every other triangle, in index order, turns each one reached so that the edge it is reached
// through runs the other way in it; a component of such triangles alone starts from its lowest.
void orient_turned(SceneTopology& topo, std::vector<std::uint8_t>& turned) {
  const std::uint32_t n = static_cast<std::uint32_t>(topo.tris.size());
  std::vector<std::uint32_t> queue;
  for (std::uint32_t t = 0; t < n; ++t)
    if (!turned[t]) queue.push_back(t);
  auto runs = [&](std::uint32_t t, std::uint32_t a, std::uint32_t b) {  // a -> b is an edge of t
    const auto& c = topo.tris[t];
    for (int k = 0; k < 3; ++k)
      if (c[k] == a && c[(k + 1) % 3] == b) return true;
    return false;
  };
  std::uint32_t next_seed = 0;
  for (std::size_t head = 0;;) {
    if (head == queue.size()) {
      while (next_seed < n && !turned[next_seed]) ++next_seed;
      if (next_seed == n) break;
      turned[next_seed] = 0;
      queue.push_back(next_seed);
    }
    const std::uint32_t t = queue[head++];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = topo.tris[t][k], b = topo.tris[t][(k + 1) % 3];
      const std::uint32_t e = topo.tri_edges[t][k];
      for (std::uint32_t i = topo.edge_face_begin[e]; i < topo.edge_face_begin[e + 1]; ++i) {
        const std::uint32_t u = topo.edge_faces[i];
        if (!turned[u]) continue;
        turned[u] = 0;
        if (runs(u, a, b)) {  // same direction as in t: turn u over (tri_edges follow the corners)
          std::swap(topo.tris[u][1], topo.tris[u][2]);
          std::swap(topo.tri_edges[u][0], topo.tri_edges[u][2]);
        }
        queue.push_back(u);
      }
    }
  }
}

// Positions shared by welded vertices of different meshes (hashed by their coordinates' bits, as
// the welding; -0.0 and 0.0 are one position), the contact map, and the seam vertices and repeated
// faces per pair of meshes.
void find_contacts(SceneTopology& topo, const std::vector<Mesh>& meshes) {
  const std::size_t nv = topo.points.size();
  // Only an obstacle's vertex makes a shared position contact: a movable vertex on it is sewn to
  // what never moves. Where movable meshes alone share a position (two garments through each
  // other at a vertex of both, common in grid-snapped scenes), fix can still part them, so they
  // stay two points.
  auto obstacle = [&](std::uint32_t v) { return meshes[topo.vertex_mesh[v]].role == Role::kObstacle; };
  std::size_t capacity = 16;
  while (capacity < 2 * nv) capacity *= 2;
  std::vector<std::uint32_t> table(capacity, kNone);
  auto slot_of = [&](std::uint32_t v) {
    const std::uint64_t h = position_hash(topo.points[v]);
    std::size_t slot = static_cast<std::size_t>(h) & (capacity - 1);
    while (table[slot] != kNone && topo.points[table[slot]] != topo.points[v]) slot = (slot + 1) & (capacity - 1);
    return slot;
  };
  // Each position holds its first vertex until an obstacle's comes: then the lowest obstacle
  // vertex there, the point every other vertex there is mapped to. Movable vertices that met only
  // movable ones there wait in `pending`.
  std::vector<std::uint32_t> leader, pending;
  auto map_to = [&](std::uint32_t v, std::uint32_t to) {
    if (leader.empty()) {  // the first shared position: from now on every vertex gets its leader
      leader.resize(nv);
      std::iota(leader.begin(), leader.end(), 0u);
    }
    leader[v] = to;  // of another mesh (a mesh's own equal positions are welded)
  };
  for (std::uint32_t v = 0; v < nv; ++v) {
    const std::size_t slot = slot_of(v);
    const std::uint32_t there = table[slot];
    if (there == kNone) {
      table[slot] = v;
    } else if (obstacle(there)) {
      map_to(v, there);
    } else if (obstacle(v)) {
      pending.push_back(there);
      table[slot] = v;
    } else {
      pending.push_back(v);
    }
  }
  for (std::uint32_t v : pending) {
    const std::uint32_t there = table[slot_of(v)];
    if (there != v && obstacle(there)) map_to(v, there);
  }
  if (leader.empty()) return;
  topo.contact_point = leader;
  topo.seam.assign(nv, 0);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> members;  // (leader, mesh)
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (leader[v] == v) continue;
    topo.seam[v] = topo.seam[leader[v]] = 1;
    members.push_back({leader[v], topo.vertex_mesh[v]});
  }
  for (std::uint32_t v = 0; v < nv; ++v)
    if (topo.seam[v] && leader[v] == v) members.push_back({v, topo.vertex_mesh[v]});
  std::sort(members.begin(), members.end());
  std::vector<std::array<std::uint32_t, 3>> pairs;  // (a, b, kind): 0 seam position, 1 repeated face
  // Every two meshes of one run of equal keys in `sorted` (key, mesh) pairs make a pair of `kind`.
  auto pair_up = [&pairs](const auto& sorted, std::uint32_t kind) {
    for (std::size_t i = 0; i < sorted.size();) {
      std::size_t j = i;
      while (j < sorted.size() && sorted[j].first == sorted[i].first) ++j;
      for (std::size_t x = i; x < j; ++x)
        for (std::size_t y = x + 1; y < j; ++y)
          pairs.push_back({sorted[x].second, sorted[y].second, kind});
      i = j;
    }
  };
  pair_up(members, 0);
  topo.contact_tris = topo.tris;
  std::vector<std::pair<std::array<std::uint32_t, 3>, std::uint32_t>> keyed;  // (corner set, mesh)
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
    auto& c = topo.contact_tris[t];
    for (auto& v : c) v = leader[v];
    if (!topo.seam[c[0]] || !topo.seam[c[1]] || !topo.seam[c[2]]) continue;
    std::array<std::uint32_t, 3> key = c;
    std::sort(key.begin(), key.end());
    keyed.push_back({key, topo.tri_mesh[t]});
  }
  std::sort(keyed.begin(), keyed.end());
  keyed.erase(std::unique(keyed.begin(), keyed.end()), keyed.end());
  pair_up(keyed, 1);
  std::sort(pairs.begin(), pairs.end());
  for (const auto& p : pairs) {
    if (topo.contacts.empty() || topo.contacts.back().mesh_a != p[0] || topo.contacts.back().mesh_b != p[1]) {
      MeshContact c;
      c.mesh_a = p[0];
      c.mesh_b = p[1];
      topo.contacts.push_back(c);
    }
    ++(p[2] == 0 ? topo.contacts.back().seam_vertices : topo.contacts.back().repeated_faces);
  }
}

}  // namespace

SceneTopology build_topology(const std::vector<Mesh>& meshes) {
  SceneTopology topo;
  const std::size_t mesh_count = meshes.size();
  topo.welded.resize(mesh_count);
  topo.degenerate.assign(mesh_count, 0);
  // Sized once for their largest possible length: grown by doubling, the body's arrays were
  // copied and their pages first touched several times over (a fix builds the topology three
  // times).
  std::size_t positions = 0, triangles = 0;
  for (const Mesh& mesh : meshes) {
    positions += mesh.positions.size();
    triangles += mesh.triangles.size();
  }
  topo.points.reserve(positions);
  topo.vertex_mesh.reserve(positions);
  topo.representative.reserve(positions);
  topo.tris.reserve(triangles);
  topo.tri_mesh.reserve(triangles);
  topo.tri_source.reserve(triangles);

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
      const std::uint64_t h = position_hash(pos[v]);
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

  // Keep triangles with three distinct welded corners, each set of corners once: a file that
  // repeats its faces (double-sided rendering: every face again with the opposite winding) is one
  // surface, and its copies would make every edge non-manifold. `turned`: a kept triangle one of
  // whose repeats runs the other way (its winding is decided below, from its neighbours).
  topo.repeated.assign(mesh_count, 0);
  std::vector<std::uint8_t> turned;
  bool any_turned = false;
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
    // Repeats: each kept triangle of this mesh looked up by its corner set in an open-addressing
    // table (linear in the mesh, as the welding); the first of each set stays.
    const std::uint32_t first = topo.mesh_tri_begin.back(), last = static_cast<std::uint32_t>(topo.tris.size());
    std::size_t capacity = 16;
    while (capacity < 2 * static_cast<std::size_t>(last - first)) capacity *= 2;
    std::vector<std::uint32_t> table(capacity, kNone);
    std::vector<std::uint8_t> drop(last - first, 0);
    turned.resize(last, 0);
    bool any = false;
    auto sorted = [&](std::uint32_t t) {
      std::array<std::uint32_t, 3> c = topo.tris[t];
      if (c[0] > c[1]) std::swap(c[0], c[1]);
      if (c[1] > c[2]) std::swap(c[1], c[2]);
      if (c[0] > c[1]) std::swap(c[0], c[1]);
      return c;
    };
    auto winding = [&](std::uint32_t t) {  // +1 or -1: the corner order against the sorted one
      const auto& c = topo.tris[t];
      const int inversions = (c[0] > c[1]) + (c[0] > c[2]) + (c[1] > c[2]);
      return inversions % 2 == 0 ? 1 : -1;
    };
    for (std::uint32_t t = first; t < last; ++t) {
      const std::array<std::uint32_t, 3> key = sorted(t);
      std::uint64_t h = (std::uint64_t{key[0]} * 0x9e3779b97f4a7c15ull) ^ (std::uint64_t{key[1]} * 0xc2b2ae3d27d4eb4full) ^
                        (std::uint64_t{key[2]} * 0x165667b19e3779f9ull);
      h ^= h >> 31;
      std::size_t slot = static_cast<std::size_t>(h) & (capacity - 1);
      while (table[slot] != kNone && sorted(table[slot]) != key) slot = (slot + 1) & (capacity - 1);
      if (table[slot] == kNone) {
        table[slot] = t;
        continue;
      }
      const std::uint32_t kept = table[slot];
      drop[t - first] = 1;
      any = true;
      if (winding(t) != winding(kept)) {
        turned[kept] = 1;
        any_turned = true;
      }
    }
    if (!any) continue;
    std::uint32_t out = first;
    for (std::uint32_t t = first; t < last; ++t) {
      if (drop[t - first]) {
        ++topo.repeated[m];
        continue;
      }
      topo.tris[out] = topo.tris[t];
      topo.tri_source[out] = topo.tri_source[t];
      turned[out] = turned[t];
      ++out;
    }
    topo.tris.resize(out);
    topo.tri_mesh.resize(out);
    topo.tri_source.resize(out);
    turned.resize(out);
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
  topo.edges.reserve(records.size());
  topo.edge_face_begin.reserve(records.size() + 1);
  topo.edge_faces.reserve(records.size());
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
  if (any_turned) orient_turned(topo, turned);

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
  find_contacts(topo, meshes);
  for (std::uint32_t m = 0; m < mesh_count; ++m) {
    if (topo.repeated[m] == 0) continue;
    MeshContact c;
    c.mesh_a = c.mesh_b = m;
    c.repeated_faces = topo.repeated[m];
    topo.contacts.push_back(c);
  }
  std::sort(topo.contacts.begin(), topo.contacts.end(), [](const MeshContact& a, const MeshContact& b) {
    return a.mesh_a != b.mesh_a ? a.mesh_a < b.mesh_a : a.mesh_b < b.mesh_b;
  });
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
  // A vertex that left its shared position is itself again for detection (fix pins them, so only
  // other callers move one).
  SceneTopology& topo = topology;
  for (std::uint32_t v = 0; v < topo.contact_point.size(); ++v) {
    const std::uint32_t p = topo.contact_point[v];
    if (p == v || topo.points[p] == topo.points[v]) continue;
    topo.contact_point[v] = v;
    for (std::uint32_t t : topo.triangles_at({v}))
      for (int k = 0; k < 3; ++k)
        if (topo.tris[t][k] == v) topo.contact_tris[t][k] = v;
  }
}

}  // namespace untangle
