// Ring walks, local sheets, track corners and track pieces (mesh_walks.h).
#include "resolve/mesh_walks.h"

#include <algorithm>
#include <unordered_set>

#include "detect/orientation.h"

namespace untangle {

bool is_boundary_vertex(const SceneTopology& topo, std::uint32_t v) {
  for (std::uint32_t k = topo.vertex_edge_begin[v]; k < topo.vertex_edge_begin[v + 1]; ++k)
    if (topo.is_boundary(topo.vertex_edges[k])) return true;
  return false;
}

std::vector<std::uint32_t> local_sheet(const SceneTopology& topo, std::uint32_t mesh,
                                       const std::vector<std::uint32_t>& seeds,
                                       const std::vector<std::uint8_t>& excluded, int rings,
                                       std::vector<std::uint8_t>& in_sheet) {
  const std::uint32_t base = topo.mesh_vertex_begin[mesh];
  in_sheet.assign(topo.mesh_vertex_begin[mesh + 1] - base, 0);
  std::vector<std::uint32_t> members;
  auto add = [&](std::uint32_t v) {
    if (in_sheet[v - base] || excluded[v - base]) return;
    in_sheet[v - base] = 1;
    members.push_back(v);
  };
  for (std::uint32_t v : seeds) add(v);
  std::size_t ring_start = 0;
  for (int ring = 0; ring < rings; ++ring) {
    const std::size_t ring_end = members.size();
    for (std::size_t i = ring_start; i < ring_end; ++i) {
      const std::uint32_t v = members[i];
      for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j) {
        add(topo.vertex_neighbors[j]);
      }
    }
    ring_start = ring_end;
  }
  std::vector<std::uint32_t> tris;
  for (std::uint32_t v : members)
    for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j) {
      const std::uint32_t e = topo.vertex_edges[j];
      for (std::uint32_t k = topo.edge_face_begin[e]; k < topo.edge_face_begin[e + 1]; ++k) {
        const auto& tri = topo.tris[topo.edge_faces[k]];
        if (in_sheet[tri[0] - base] && in_sheet[tri[1] - base] && in_sheet[tri[2] - base])
          tris.push_back(topo.edge_faces[k]);
      }
    }
  std::sort(tris.begin(), tris.end());
  tris.erase(std::unique(tris.begin(), tris.end()), tris.end());
  return tris;
}

std::vector<int> ring_distance(const SceneTopology& topo, std::uint32_t mesh,
                               const std::vector<std::uint32_t>& seeds, int limit) {
  const std::uint32_t base = topo.mesh_vertex_begin[mesh];
  std::vector<int> d(topo.mesh_vertex_begin[mesh + 1] - base, limit + 1);
  std::vector<std::uint32_t> front;
  for (std::uint32_t v : seeds)
    if (d[v - base] != 0) {
      d[v - base] = 0;
      front.push_back(v);
    }
  for (int ring = 1; ring <= limit && !front.empty(); ++ring) {
    std::vector<std::uint32_t> next;
    for (std::uint32_t v : front)
      for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j) {
        const std::uint32_t w = topo.vertex_neighbors[j];
        if (d[w - base] > ring) {
          d[w - base] = ring;
          next.push_back(w);
        }
      }
    front = std::move(next);
  }
  return d;
}

std::vector<std::uint32_t> track_corners(const SceneTopology& topo, const CrossingSet& set,
                                         const TracedContour& t, int k) {
  const Contour& c = t.contour;
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < c.crossings.size(); ++i) {
    const RawCrossing& x = set.items[c.crossings[i]];
    if (t.edge_track[i] == k)
      for (std::uint32_t v : topo.edges[x.edge]) out.push_back(v);
    else
      for (std::uint32_t v : topo.tris[x.face]) out.push_back(v);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  out.erase(std::remove_if(out.begin(), out.end(),
                           [&](std::uint32_t v) {
                             return std::find(t.loop_vertex_ids.begin(), t.loop_vertex_ids.end(),
                                              v) != t.loop_vertex_ids.end();
                           }),
            out.end());
  return out;
}

std::vector<std::vector<std::uint32_t>> track_pieces(const SceneTopology& topo,
                                                     const CrossingSet& set, const TracedContour& t,
                                                     int k, std::size_t limit) {
  const Contour& c = t.contour;
  std::vector<std::uint32_t> cut;
  std::vector<std::uint32_t> seeds[2];
  for (std::size_t i = 0; i < c.crossings.size(); ++i) {
    if (t.edge_track[i] != k) continue;
    const RawCrossing& x = set.items[c.crossings[i]];
    const auto& f = topo.tris[x.face];
    cut.push_back(x.edge);
    for (std::uint32_t v : topo.edges[x.edge]) {
      if (v == f[0] || v == f[1] || v == f[2]) continue;
      seeds[orient_sos(topo.points, f[0], f[1], f[2], v) > 0 ? 0 : 1].push_back(v);
    }
  }
  std::sort(cut.begin(), cut.end());
  auto is_loop = [&](std::uint32_t v) {
    return std::find(t.loop_vertex_ids.begin(), t.loop_vertex_ids.end(), v) !=
           t.loop_vertex_ids.end();
  };
  std::vector<std::vector<std::uint32_t>> out;
  for (int s = 0; s < 2; ++s) {
    std::unordered_set<std::uint32_t> other(seeds[1 - s].begin(), seeds[1 - s].end());
    std::unordered_set<std::uint32_t> seen;
    std::vector<std::uint32_t> piece;
    bool ok = true;
    for (std::uint32_t v : seeds[s]) {
      if (other.count(v) || is_loop(v)) {
        ok = false;  // an endpoint on both sides: the cut separates nothing here
        break;
      }
      if (seen.insert(v).second) piece.push_back(v);
    }
    for (std::size_t i = 0; ok && i < piece.size(); ++i) {
      const std::uint32_t v = piece[i];
      for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j) {
        const std::uint32_t w = topo.vertex_neighbors[j];
        if (std::binary_search(cut.begin(), cut.end(), topo.vertex_edges[j]) || is_loop(w))
          continue;
        if (!seen.insert(w).second) continue;
        if (other.count(w) || piece.size() >= limit) {
          ok = false;  // the piece leaks round the track's end, or is a side of the surface
          break;
        }
        piece.push_back(w);
      }
    }
    if (!ok || piece.empty()) continue;
    std::sort(piece.begin(), piece.end());
    out.push_back(std::move(piece));
  }
  return out;
}

std::vector<std::uint8_t> own_side_of(const SceneTopology& topo, std::uint32_t mesh,
                                      const std::vector<std::uint32_t>& own,
                                      const std::vector<std::uint32_t>& others, int rings) {
  const std::vector<int> near_own = ring_distance(topo, mesh, own, rings + 1);
  const std::vector<int> near_other = ring_distance(topo, mesh, others, rings + 1);
  std::vector<std::uint8_t> own_side(near_own.size(), 0);
  for (std::size_t i = 0; i < own_side.size(); ++i)
    own_side[i] =
        near_own[i] == 0 || (near_own[i] < near_other[i] && near_own[i] <= rings + 1) ? 1 : 0;
  return own_side;
}

}  // namespace untangle
