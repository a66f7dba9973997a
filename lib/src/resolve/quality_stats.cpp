// quality_stats and measure_quality: per movable mesh, edge-length change, flipped faces and
// largest displacement; within_bounds: the guard of a result.
#include "resolve/quality_stats.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "geometry/vec3.h"

namespace untangle {
namespace {

// An edge's length ratio, longer over shorter (1 unchanged; infinite collapsed), from `before`'s
// length `was` (nonzero) to its length now.
double edge_ratio(double was, double now) {
  return now <= 0.0 ? INFINITY : std::max(now / was, was / now);
}

// Whether triangle `tri`'s normal turned by more than 90 degrees from `before` to `now`.
bool turned_over(const std::vector<Vec3>& before, const std::vector<Vec3>& now,
                 const std::array<std::uint32_t, 3>& tri) {
  const Vec3 n0 = cross(sub(before[tri[1]], before[tri[0]]), sub(before[tri[2]], before[tri[0]]));
  const Vec3 n1 = cross(sub(now[tri[1]], now[tri[0]]), sub(now[tri[2]], now[tri[0]]));
  return dot(n0, n1) < 0.0;
}

}  // namespace

std::vector<QualityStats> quality_stats(const SceneTopology& topo, const std::vector<Vec3>& input,
                                        const std::vector<Role>& role) {
  const std::size_t meshes = role.size();
  std::vector<QualityStats> out(meshes);
  std::vector<std::vector<double>> change(meshes);
  std::vector<double> mean_edge(meshes, 0.0);
  std::vector<std::size_t> edges(meshes, 0);
  for (const auto& e : topo.edges) {
    const std::uint32_t m = topo.vertex_mesh[e[0]];
    const double before = norm(sub(input[e[0]], input[e[1]]));
    mean_edge[m] += before;
    ++edges[m];
    if (role[m] != Role::kMovable || before <= 0.0) continue;
    const double after = norm(sub(topo.points[e[0]], topo.points[e[1]]));
    change[m].push_back(std::abs(after / before - 1.0));
    out[m].max_stretch = std::max(out[m].max_stretch, edge_ratio(before, after));
  }
  for (std::size_t m = 0; m < meshes; ++m) {
    if (edges[m] > 0) mean_edge[m] /= static_cast<double>(edges[m]);
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
    if (role[m] == Role::kMovable && turned_over(input, topo.points, topo.tris[t]))
      ++out[m].flipped_faces;
  }
  std::vector<Vec3> lo(meshes, Vec3{INFINITY, INFINITY, INFINITY}), hi(meshes, Vec3{-INFINITY, -INFINITY, -INFINITY});
  for (std::uint32_t v = 0; v < topo.points.size(); ++v) {
    const std::uint32_t m = topo.vertex_mesh[v];
    if (role[m] != Role::kMovable) continue;
    for (int a = 0; a < 3; ++a) {
      lo[m][a] = std::min(lo[m][a], input[v][a]);
      hi[m][a] = std::max(hi[m][a], input[v][a]);
    }
    const double d = norm(sub(topo.points[v], input[v]));
    if (d > out[m].max_displacement) {
      out[m].max_displacement = d;
      out[m].max_displacement_over_mean_edge = mean_edge[m] > 0.0 ? d / mean_edge[m] : 0.0;
    }
  }
  for (std::size_t m = 0; m < meshes; ++m) {
    const double diagonal = lo[m][0] <= hi[m][0] ? norm(sub(hi[m], lo[m])) : 0.0;
    out[m].max_displacement_over_diagonal =
        diagonal > 0.0 ? out[m].max_displacement / diagonal : 0.0;
  }
  return out;
}

namespace {

// The movable meshes of `input` welded into one topology whose points are `output`'s (each welded
// vertex takes the output position of its smallest input vertex), their input positions in
// `before`. Obstacles stand in it as empty meshes, so that a body is not welded and its edges
// listed for nothing (in `fix`, 27,300 triangles against the garment's 3,200).
SceneTopology movable_topology(const std::vector<Mesh>& input, const std::vector<Mesh>& output,
                               std::vector<Vec3>& before) {
  std::vector<Mesh> movable(input.size());
  for (std::size_t m = 0; m < input.size(); ++m) {
    movable[m].role = input[m].role;
    if (input[m].role != Role::kMovable) continue;
    movable[m].positions = input[m].positions;
    movable[m].triangles = input[m].triangles;
  }
  SceneTopology topo = build_topology(movable);
  before = topo.points;
  for (std::size_t m = 0; m < input.size(); ++m) {
    if (m >= output.size() || output[m].positions.size() != input[m].positions.size() ||
        input[m].role != Role::kMovable)
      continue;
    for (std::uint32_t i = 0; i < input[m].positions.size(); ++i) {
      const std::uint32_t v = topo.welded[m][i];
      if (topo.representative[v] == i) topo.points[v] = output[m].positions[i];
    }
  }
  return topo;
}

}  // namespace

std::vector<QualityStats> measure_quality(const std::vector<Mesh>& input,
                                          const std::vector<Mesh>& output) {
  std::vector<Vec3> before;
  const SceneTopology topo = movable_topology(input, output, before);
  std::vector<Role> role;
  for (const Mesh& m : input) role.push_back(m.role);
  return quality_stats(topo, before, role);
}

std::size_t faces_beyond_bounds(const std::vector<Mesh>& input, const std::vector<Mesh>& output,
                                const QualityBounds& bounds) {
  std::vector<Vec3> before;
  const SceneTopology topo = movable_topology(input, output, before);
  const std::vector<Vec3>& now = topo.points;
  std::size_t faces = 0;
  for (const auto& tri : topo.tris) {
    bool beyond = turned_over(before, now, tri);
    for (int k = 0; k < 3 && !beyond; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      const double was = norm(sub(before[a], before[b]));
      beyond = was > 0.0 && edge_ratio(was, norm(sub(now[a], now[b]))) > bounds.max_stretch;
    }
    if (beyond) ++faces;
  }
  return faces;
}

bool shape_within_bounds(const QualityStats& q, const QualityBounds& bounds) {
  return q.max_stretch <= bounds.max_stretch && q.flipped_faces <= bounds.max_flips;
}

bool within_bounds(const QualityStats& q, const QualityBounds& bounds) {
  return shape_within_bounds(q, bounds) && q.max_displacement_over_diagonal <= bounds.max_move;
}

const char* to_string(FixStatus status) {
  switch (status) {
    case FixStatus::kClean: return "clean";
    case FixStatus::kUnresolved: return "unresolved";
    case FixStatus::kDistorted: return "distorted";
  }
  return "unresolved";
}

FixStatus judge_result(const IntersectionCounts& written, const std::vector<QualityStats>& quality,
                       const QualityBounds& bounds) {
  if (written.crossings > 0 || written.inside_vertices > 0) return FixStatus::kUnresolved;
  for (const QualityStats& q : quality)
    if (!within_bounds(q, bounds)) return FixStatus::kDistorted;
  return FixStatus::kClean;
}

}  // namespace untangle
