// Converting global ids back to per-mesh input indices and counting.
#include "check/summarize.h"

#include <algorithm>

namespace untangle {

Intersections summarize(const SceneTopology& topo, const CrossingSet& set,
                        const std::vector<TracedContour>& traced) {
  Intersections result = summarize_crossings(topo, set);
  add_contours(traced, result);
  return result;
}

Intersections summarize_crossings(const SceneTopology& topo, const CrossingSet& set) {
  Intersections result;
  result.crossings.reserve(set.items.size());
  for (const RawCrossing& c : set.items) {
    Crossing out;
    out.edge_mesh = topo.edge_mesh(c.edge);
    out.edge_v0 = topo.representative[topo.edges[c.edge][0]];
    out.edge_v1 = topo.representative[topo.edges[c.edge][1]];
    out.face_mesh = topo.tri_mesh[c.face];
    out.face = topo.tri_source[c.face];
    out.point = c.point;
    result.crossings.push_back(out);
  }
  const std::vector<std::array<std::uint32_t, 2>> pairs = intersecting_pairs(topo, set);
  result.triangle_pairs.reserve(pairs.size());
  for (const auto& pair : pairs) {
    std::array<std::uint32_t, 4> p{topo.tri_mesh[pair[0]], topo.tri_source[pair[0]],
                                   topo.tri_mesh[pair[1]], topo.tri_source[pair[1]]};
    if (std::make_pair(p[2], p[3]) < std::make_pair(p[0], p[1])) {
      std::swap(p[0], p[2]);
      std::swap(p[1], p[3]);
    }
    result.triangle_pairs.push_back(p);
  }
  // Triangles are numbered mesh by mesh in input order, so (mesh, triangle) grows with the id and
  // the pairs come out sorted already; sorted again only if that ever changes.
  if (!std::is_sorted(result.triangle_pairs.begin(), result.triangle_pairs.end()))
    std::sort(result.triangle_pairs.begin(), result.triangle_pairs.end());

  result.counts.crossings = result.crossings.size();
  result.counts.triangle_pairs = result.triangle_pairs.size();
  result.counts.contacts = contacts_of(topo, set);
  return result;
}

std::vector<MeshContact> contacts_of(const SceneTopology& topo, const CrossingSet& set) {
  std::vector<MeshContact> contacts = topo.contacts;
  for (const auto& pair : set.coplanar_pairs) {
    const std::uint32_t a = std::min(topo.tri_mesh[pair[0]], topo.tri_mesh[pair[1]]);
    const std::uint32_t b = std::max(topo.tri_mesh[pair[0]], topo.tri_mesh[pair[1]]);
    auto it = std::find_if(contacts.begin(), contacts.end(),
                           [&](const MeshContact& c) { return c.mesh_a == a && c.mesh_b == b; });
    if (it == contacts.end()) {
      MeshContact c;
      c.mesh_a = a;
      c.mesh_b = b;
      contacts.push_back(c);
      it = contacts.end() - 1;
    }
    ++it->coplanar_pairs;
  }
  std::sort(contacts.begin(), contacts.end(), [](const MeshContact& x, const MeshContact& y) {
    return x.mesh_a != y.mesh_a ? x.mesh_a < y.mesh_a : x.mesh_b < y.mesh_b;
  });
  return contacts;
}

void add_contours(const std::vector<TracedContour>& traced, Intersections& result,
                  bool separation) {
  IntersectionCounts& counts = result.counts;
  counts.contours = traced.size();
  for (const TracedContour& t : traced) {
    const Contour& c = t.contour;
    result.contours.push_back(c);
    counts.contour_length += c.length;
    counts.loop_vertices += c.loop_vertices;
    counts.branch_points += c.branch_points;
    if (t.broken) ++counts.broken;
    for (const Track& track : c.tracks) {
      ++counts.tracks[static_cast<int>(track.type)];
      if (separation && (track.type == TrackType::kCL || track.type == TrackType::kBB) &&
          !track.separates)
        ++counts.non_separating;
    }
    const TrackType a = c.tracks[0].type, b = c.tracks[1].type;
    auto is = [&](TrackType x, TrackType y) { return (a == x && b == y) || (a == y && b == x); };
    if (c.self) ++counts.pairs_self;
    else if (is(TrackType::kCL, TrackType::kCL)) ++counts.pairs_cl_cl;
    else if (is(TrackType::kBB, TrackType::kII)) ++counts.pairs_bb_ii;
    else if (is(TrackType::kBI, TrackType::kBI)) ++counts.pairs_bi_bi;
    else ++counts.pairs_other;
  }
}

}  // namespace untangle
