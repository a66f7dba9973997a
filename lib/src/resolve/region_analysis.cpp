// Region analysis: cut edges per (mesh, partner), flood-filled regions, inside or area labels.
#include "resolve/region_analysis.h"

#include <algorithm>

#include "detect/orientation.h"
#include "geometry/vec3.h"
#include "resolve/inside_vertices.h"

namespace untangle {

std::uint32_t track_component(const SceneTopology& topo, const CrossingSet& set,
                              const TracedContour& traced, int k) {
  // The first crossing tells: its edge lies on track edge_track[0], its face on the other.
  const RawCrossing& x = set.items[traced.contour.crossings.front()];
  return traced.edge_track.front() == k ? topo.vertex_component[topo.edges[x.edge][0]]
                                        : topo.tri_component(x.face);
}

RegionAnalysis analyse_regions(const SceneTopology& topo, const CrossingSet& set,
                               const std::vector<TracedContour>& contours,
                               const RegionSettings& settings) {
  RegionAnalysis out;
  // Contours grouped by the (ordered) pair of components they join.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> groups;
  for (std::uint32_t k = 0; k < contours.size(); ++k) {
    const std::uint32_t c0 = track_component(topo, set, contours[k], 0);
    const std::uint32_t c1 = track_component(topo, set, contours[k], 1);
    groups[{std::min(c0, c1), std::max(c0, c1)}].push_back(k);
  }

  std::vector<double> vertex_area(topo.points.size(), 0.0);
  for (const auto& tri : topo.tris) {
    const double a = triangle_area(topo.points[tri[0]], topo.points[tri[1]], topo.points[tri[2]]);
    for (std::uint32_t v : tri) vertex_area[v] += a / 3.0;
  }

  std::vector<std::uint8_t> cut(topo.edges.size(), 0);
  std::vector<std::uint32_t> region;
  for (const auto& [key, members] : groups) {
    // A self-intersecting component is its own partner: one side, cut by both tracks.
    for (int side = 0; side < (key.first == key.second ? 1 : 2); ++side) {
      const std::uint32_t component = side == 0 ? key.first : key.second;
      const std::uint32_t partner = side == 0 ? key.second : key.first;
      const std::uint32_t mesh = topo.component_mesh[component];
      const std::uint32_t partner_mesh = topo.component_mesh[partner];
      // Edges of `component` crossed an odd number of times by all contours of the group together.
      std::vector<std::uint32_t> crossed;
      for (std::uint32_t k : members) {
        const TracedContour& traced = contours[k];
        for (std::size_t i = 0; i < traced.contour.crossings.size(); ++i) {
          const std::uint32_t edge = set.items[traced.contour.crossings[i]].edge;
          if (topo.vertex_component[topo.edges[edge][0]] == component) crossed.push_back(edge);
        }
      }
      const std::vector<std::uint32_t> odd = odd_edges(crossed);
      if (odd.empty()) continue;
      for (std::uint32_t e : odd) cut[e] = 1;
      const std::size_t region_count = flood_regions(topo, mesh, cut, region);
      for (std::uint32_t e : odd) cut[e] = 0;
      const std::uint32_t base = topo.mesh_vertex_begin[mesh];
      const std::uint32_t end = topo.mesh_vertex_begin[mesh + 1];

      std::vector<double> area(region_count, 0.0);
      for (std::uint32_t v = base; v < end; ++v) area[region[v - base]] += vertex_area[v];
      std::vector<std::int8_t> region_label(region_count, -1);
      RegionRule rule = RegionRule::kArea;

      const bool by_inside = component != partner && settings.outside_closed_obstacles &&
                             settings.obstacle[partner_mesh] && settings.orientation[partner] != 0;
      if (by_inside) {
        // Each cleanly cut edge has one endpoint inside the closed obstacle: the one on the inner
        // side of the face it crosses. Regions vote with their endpoints.
        rule = RegionRule::kInside;
        std::vector<int> votes(region_count, 0);
        for (std::uint32_t e : odd) {
          std::uint32_t face = kNone;
          auto it = std::lower_bound(set.items.begin(), set.items.end(), e,
                                     [](const RawCrossing& c, std::uint32_t x) { return c.edge < x; });
          for (; it != set.items.end() && it->edge == e; ++it) {
            if (topo.tri_component(it->face) == partner) {
              face = it->face;
              break;
            }
          }
          if (face == kNone) continue;
          const auto& f = topo.tris[face];
          const std::uint32_t a = topo.edges[e][0], b = topo.edges[e][1];
          const int side_a = orient_sos(topo.points, f[0], f[1], f[2], a) * settings.orientation[partner];
          const std::uint32_t inside = side_a < 0 ? a : b;
          const std::uint32_t outside = side_a < 0 ? b : a;
          votes[region[inside - base]] += 1;
          votes[region[outside - base]] -= 1;
        }
        for (std::size_t r = 0; r < region_count; ++r) {
          if (votes[r] > 0) region_label[r] = 1;
          else if (votes[r] < 0) region_label[r] = 0;
        }
      }
      // An open obstacle (holes at the eyes, limbs through each other) has an inside too: its
      // winding number above 1/2. Each endpoint of a cut edge votes for its region, inside or
      // not; where no endpoint is inside (a sheet-like obstacle) the area rule decides.
      const bool by_winding = !by_inside && component != partner &&
                              settings.outside_closed_obstacles && settings.obstacle[partner_mesh] &&
                              settings.winding != nullptr;
      if (by_winding) {
        std::vector<int> votes(region_count, 0);
        bool any_inside = false;
        for (std::uint32_t e : odd) {
          for (std::uint32_t v : topo.edges[e]) {
            const bool in = settings.winding->winding(partner_mesh, topo.points[v]) > 0.5;
            any_inside = any_inside || in;
            votes[region[v - base]] += in ? 1 : -1;
          }
        }
        if (any_inside) {
          rule = RegionRule::kInside;
          for (std::size_t r = 0; r < region_count; ++r) {
            if (votes[r] > 0) region_label[r] = 1;
            else if (votes[r] < 0) region_label[r] = 0;
          }
        }
      }
      if (!by_inside && rule == RegionRule::kArea) {
        // Two-colour the graph of regions joined by cut edges, starting from the largest region of
        // each connected part: crossing a cut flips legal and illegal. A region reached with both
        // colours (an odd cycle) stays as first coloured.
        std::vector<std::vector<std::uint32_t>> adjacent(region_count);
        for (std::uint32_t e : odd) {
          const std::uint32_t ra = region[topo.edges[e][0] - base];
          const std::uint32_t rb = region[topo.edges[e][1] - base];
          adjacent[ra].push_back(rb);
          adjacent[rb].push_back(ra);
        }
        std::vector<std::uint32_t> touched;
        for (std::uint32_t r = 0; r < region_count; ++r)
          if (!adjacent[r].empty()) touched.push_back(r);
        std::vector<std::uint8_t> done(region_count, 0);
        for (;;) {
          std::uint32_t seed = kNone;
          for (std::uint32_t r : touched) {
            if (done[r]) continue;
            if (seed == kNone || area[r] > area[seed]) seed = r;
          }
          if (seed == kNone) break;
          // Collect this connected part, then colour from its largest region.
          std::vector<std::uint32_t> queue{seed};
          done[seed] = 1;
          region_label[seed] = 0;
          for (std::size_t i = 0; i < queue.size(); ++i) {
            const std::uint32_t r = queue[i];
            for (std::uint32_t s : adjacent[r]) {
              if (done[s]) continue;
              done[s] = 1;
              region_label[s] = static_cast<std::int8_t>(1 - region_label[r]);
              queue.push_back(s);
            }
          }
          // A region adjacent to itself is not separated by the cuts: undecided.
          for (std::uint32_t r : queue) {
            if (std::find(adjacent[r].begin(), adjacent[r].end(), r) != adjacent[r].end())
              region_label[r] = -1;
          }
        }
      }

      std::vector<std::int8_t>& labels = out.labels[{component, partner}];
      labels.assign(end - base, -1);
      IllegalSet illegal;
      illegal.component = component;
      illegal.partner = partner;
      illegal.rule = rule;
      for (std::uint32_t v = base; v < end; ++v) {
        if (topo.vertex_component[v] != component) continue;
        labels[v - base] = region_label[region[v - base]];
        if (labels[v - base] == 1) {
          illegal.vertices.push_back(v);
          illegal.area += vertex_area[v];
        }
      }
      for (std::size_t r = 0; r < region_count; ++r) illegal.regions += region_label[r] == 1 ? 1 : 0;
      if (!illegal.vertices.empty()) out.illegal.push_back(std::move(illegal));
    }
  }
  std::sort(out.illegal.begin(), out.illegal.end(), [](const IllegalSet& a, const IllegalSet& b) {
    return a.component != b.component ? a.component < b.component : a.partner < b.partner;
  });
  return out;
}

}  // namespace untangle
