// The layering (layering.h): each garment alone on the obstacles, then each laid over the ones
// inside it, nearest the obstacles first.
#include "resolve/layering.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include "geometry/point_grid.h"
#include "geometry/vec3.h"
#include "resolve/continuation.h"
#include "resolve/repair_loop.h"
#include "resolve/surface_queries.h"
#include "topology/scene_topology.h"
#include "untangle/mesh_info.h"

namespace untangle {
namespace {

// One layer: an edge-connected component of a movable mesh (a top and the trousers of one garment
// file are two), with its triangles renumbered over its own vertices.
struct Piece {
  std::uint32_t mesh = 0;
  std::vector<std::uint32_t> vertices;  // input indices, ascending
  std::vector<Triangle> triangles;      // over `vertices`
  std::vector<std::uint32_t> polygon;   // per triangle, its source face
};

// The pieces of the movable meshes, in mesh order, then component order; welded as `topo` (built
// from `meshes` at their input positions, as the repair welds them), components without a
// triangle left out.
std::vector<Piece> pieces_of(const SceneTopology& topo, const std::vector<Mesh>& meshes) {
  std::vector<Piece> pieces;
  for (std::uint32_t m = 0; m < meshes.size(); ++m) {
    if (meshes[m].role != Role::kMovable) continue;
    std::vector<std::uint32_t> piece_of_component(topo.component_mesh.size(), kNone);
    std::vector<std::uint32_t> local(meshes[m].positions.size(), kNone);
    const auto component = [&](std::uint32_t v) {
      return topo.vertex_component[topo.welded[m][v]];
    };
    for (std::uint32_t v = 0; v < meshes[m].positions.size(); ++v) {
      std::uint32_t& piece = piece_of_component[component(v)];
      if (piece == kNone) {
        piece = static_cast<std::uint32_t>(pieces.size());
        pieces.push_back({m, {}, {}, {}});
      }
      local[v] = static_cast<std::uint32_t>(pieces[piece].vertices.size());
      pieces[piece].vertices.push_back(v);
    }
    const Mesh& mesh = meshes[m];
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      if (tri[0] >= local.size() || tri[1] >= local.size() || tri[2] >= local.size()) continue;
      const std::uint32_t c = component(tri[0]);
      if (component(tri[1]) != c || component(tri[2]) != c) continue;
      Piece& piece = pieces[piece_of_component[c]];
      piece.triangles.push_back({local[tri[0]], local[tri[1]], local[tri[2]]});
      piece.polygon.push_back(t < mesh.polygon.size() ? mesh.polygon[t]
                                                      : static_cast<std::uint32_t>(t));
    }
  }
  std::vector<Piece> kept;
  for (Piece& p : pieces)
    if (!p.triangles.empty()) kept.push_back(std::move(p));
  return kept;
}

// The piece as a mesh of its own, at the positions of `mesh`.
Mesh piece_mesh(const Mesh& mesh, const Piece& piece, Role role) {
  Mesh out;
  out.path = mesh.path;
  out.name = mesh.name;
  out.role = role;
  out.positions.reserve(piece.vertices.size());
  for (std::uint32_t v : piece.vertices) out.positions.push_back(mesh.positions[v]);
  out.triangles = piece.triangles;
  out.polygon = piece.polygon;
  out.source_faces = mesh.source_faces;
  return out;
}

// Whether piece a should lie outside piece b, inside it, or neither (they do not overlap): +1,
// -1, 0. They overlap at a vertex of one whose closest point on the obstacles (`foot`) has one of
// the other's within `radius`; the other's vertex with the nearest foot (lowest index on a tie)
// is its partner there. Laid over b, a moves out at its vertices that lie nearer the obstacles
// (`depth`) than their partners, by the difference, and b moves out at none of its own; laid
// under b, the other way round. The order that moves less wins.
int outside_where_overlapping(const std::vector<Vec3>& foot_a, const std::vector<double>& depth_a,
                              const std::vector<Vec3>& foot_b, const std::vector<double>& depth_b,
                              double radius) {
  if (!(radius > 0.0)) return 0;
  double votes = 0.0;  // how far a moves laid under b, less how far laid over it
  const auto vote = [&](const std::vector<Vec3>& foot_p, const std::vector<double>& depth_p,
                        const std::vector<Vec3>& foot_q, const std::vector<double>& depth_q,
                        int sign) {
    PointGrid grid(radius);
    for (std::uint32_t j = 0; j < foot_q.size(); ++j) grid.add(foot_q[j], j);
    for (std::size_t i = 0; i < foot_p.size(); ++i) {
      double best = radius * radius;
      std::uint32_t nearest = kNone;
      grid.for_each_near(foot_p[i], [&](std::uint32_t j) {
        const Vec3 gap = sub(foot_q[j], foot_p[i]);
        const double d2 = dot(gap, gap);
        if (d2 < best || (d2 == best && nearest != kNone && j < nearest)) {
          best = d2;
          nearest = j;
        }
      });
      if (nearest == kNone) continue;
      votes -= sign * std::max(0.0, depth_q[nearest] - depth_p[i]);
    }
  };
  vote(foot_a, depth_a, foot_b, depth_b, 1);
  vote(foot_b, depth_b, foot_a, depth_a, -1);
  return votes > 0 ? 1 : votes < 0 ? -1 : 0;
}

// The layers innermost first: each after every piece it lies outside where they overlap
// (outside_where_overlapping, within the larger of their mean edge lengths), otherwise nearest
// the obstacles first by median distance, then by index. A cycle of such relations (three pieces
// each outside the next) is broken at its piece of least median distance.
std::vector<std::uint32_t> layer_order(const std::vector<std::vector<Vec3>>& foot,
                                       const std::vector<std::vector<double>>& depth,
                                       const std::vector<double>& distance,
                                       const std::vector<double>& edge) {
  const std::size_t n = foot.size();
  std::vector<std::vector<std::uint32_t>> inside_of(n);  // the pieces each lies outside
  for (std::uint32_t a = 0; a < n; ++a)
    for (std::uint32_t b = a + 1; b < n; ++b) {
      const int side = outside_where_overlapping(foot[a], depth[a], foot[b], depth[b],
                                                 std::max(edge[a], edge[b]));
      if (side > 0) inside_of[a].push_back(b);
      if (side < 0) inside_of[b].push_back(a);
    }
  const auto before = [&](std::uint32_t a, std::uint32_t b) {
    return distance[a] < distance[b] || (distance[a] == distance[b] && a < b);
  };
  std::vector<std::uint32_t> order;
  std::vector<std::uint8_t> placed(n, 0);
  while (order.size() < n) {
    std::uint32_t next = kNone, fallback = kNone;
    for (std::uint32_t k = 0; k < n; ++k) {
      if (placed[k]) continue;
      if (fallback == kNone || before(k, fallback)) fallback = k;
      bool ready = true;
      for (std::uint32_t i : inside_of[k]) ready = ready && placed[i];
      if (ready && (next == kNone || before(k, next))) next = k;
    }
    if (next == kNone) next = fallback;
    placed[next] = 1;
    order.push_back(next);
  }
  return order;
}

}  // namespace

const char* to_string(LayerOrderRule rule) {
  return rule == LayerOrderRule::kOverlap ? "overlap" : "median_distance";
}

bool worth_layering(const std::vector<Mesh>& input, const std::vector<Mesh>& kept, int threads) {
  bool obstacle = false;
  std::size_t movable = 0;
  for (const Mesh& m : input) {
    obstacle = obstacle || (m.role == Role::kObstacle && !m.triangles.empty());
    movable += m.role == Role::kMovable ? 1 : 0;
  }
  if (!obstacle || pieces_of(build_topology(input), input).size() < 2) return false;
  if (movable > 1) return true;
  // One movable mesh: its repair alone is the attempt kept, so only pieces crossing there leave
  // something to lay.
  const Intersections found = detect_as_check(kept, threads);
  const SceneTopology topo = build_topology(kept);
  for (const Crossing& c : found.crossings) {
    if (kept[c.edge_mesh].role != Role::kMovable || kept[c.face_mesh].role != Role::kMovable)
      continue;
    const std::uint32_t a = topo.vertex_component[topo.welded[c.edge_mesh][c.edge_v0]];
    const std::uint32_t b =
        topo.vertex_component[topo.welded[c.face_mesh][kept[c.face_mesh].triangles[c.face][0]]];
    if (a != b) return true;
  }
  return false;
}

FixResult run_layering(std::vector<Mesh>& meshes, const FixOptions& options, const PinMask& pins,
                       const Rounding& round, const FixProgress& progress,
                       const std::vector<std::vector<std::uint32_t>>& input_vertex,
                       LayeringRecord& record) {
  const std::vector<Mesh> input = meshes;
  std::vector<std::uint32_t> movable, obstacles;
  for (std::uint32_t m = 0; m < meshes.size(); ++m)
    (meshes[m].role == Role::kMovable ? movable : obstacles).push_back(m);
  const auto pins_of = [&](std::uint32_t m) {
    return m < pins.size() ? pins[m] : std::vector<std::uint8_t>{};
  };

  FixResult result;
  bool cancelled = false;
  const FixProgress watch = [&](const IterationRecord& r) {
    IterationRecord staged = r;
    staged.stage = 5;
    if (progress && !progress(staged)) cancelled = true;
    return !cancelled;
  };
  int last_iterations = 0;
  const auto take = [&](const FixResult& r) {
    for (IterationRecord h : r.history) {
      h.stage = 5;
      result.history.push_back(h);
    }
    add_times(r, result);
    result.relax_sweeps += r.relax_sweeps;
    result.relaxed_vertices += r.relaxed_vertices;
    result.illegal_regions_by_inside += r.illegal_regions_by_inside;
    result.illegal_regions_by_area += r.illegal_regions_by_area;
    last_iterations = r.iterations;
  };

  // 1. Each movable mesh alone with the obstacles.
  FixOptions alone = options;
  alone.layering = false;
  // The layering's own continuation grows the inner layers back (3.); one inside each garment's
  // repair alone would run before it, on every pair, for seconds each. Pieces moved whole are
  // the whole run's last resort, not a layer's.
  alone.continuation = false;
  alone.piece_moves = false;
  for (std::uint32_t m : movable) {
    if (cancelled) break;
    std::vector<Mesh> scene{meshes[m]};
    PinMask scene_pins{pins_of(m)};
    for (std::uint32_t o : obstacles) {
      scene.push_back(meshes[o]);
      scene_pins.emplace_back();
    }
    const FixResult r = fix_meshes(scene, alone, scene_pins, round, watch);
    take(r);
    meshes[m].positions = std::move(scene[0].positions);
  }

  // 2. The orders of the pieces, innermost first: by the median distance of a piece's vertices
  // to the obstacles, and by which lies outside which where they overlap (layer_order).
  const SceneTopology topo = build_topology(input);
  std::vector<std::uint32_t> obstacle_tris;
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t)
    if (meshes[topo.tri_mesh[t]].role == Role::kObstacle) obstacle_tris.push_back(t);
  const std::unique_ptr<MeshTree> tree = build_tree(topo, obstacle_tris);
  const auto closest = [&](const Vec3& p) {
    if (tree->empty()) return p;  // every obstacle triangle degenerate: nothing to lay on
    return closest_on(*tree, p).point;
  };
  const std::vector<Piece> pieces = pieces_of(topo, input);
  // Each piece as the report names it: its ordinal among its mesh's pieces by their lowest vertex
  // in the input's numbering (the pieces are found in the canonical one).
  std::vector<std::uint32_t> named(pieces.size(), 0);
  {
    std::vector<std::uint32_t> lowest(pieces.size(), kNone);
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      const std::vector<std::uint32_t>* to_input =
          pieces[k].mesh < input_vertex.size() ? &input_vertex[pieces[k].mesh] : nullptr;
      for (std::uint32_t v : pieces[k].vertices)
        lowest[k] =
            std::min(lowest[k], to_input != nullptr && v < to_input->size() ? (*to_input)[v] : v);
    }
    for (std::size_t k = 0; k < pieces.size(); ++k)
      for (std::size_t i = 0; i < pieces.size(); ++i)
        if (pieces[i].mesh == pieces[k].mesh && lowest[i] < lowest[k]) ++named[k];
  }
  // Each vertex's closest point on the obstacles and its distance there, per piece.
  std::vector<std::vector<Vec3>> foot(pieces.size());
  std::vector<std::vector<double>> depth(pieces.size());
  std::vector<double> distance(pieces.size(), 0.0), edge(pieces.size(), 0.0);
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    for (std::uint32_t v : pieces[k].vertices) {
      const Vec3& p = meshes[pieces[k].mesh].positions[v];
      foot[k].push_back(closest(p));
      depth[k].push_back(norm(sub(foot[k].back(), p)));
    }
    std::vector<double> d = depth[k];
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    distance[k] = d[d.size() / 2];
    edge[k] = describe_mesh(piece_mesh(input[pieces[k].mesh], pieces[k], Role::kMovable))
                  .mean_edge_length;
  }
  std::vector<std::uint32_t> by_distance(pieces.size());
  std::iota(by_distance.begin(), by_distance.end(), 0u);
  std::stable_sort(by_distance.begin(), by_distance.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return distance[a] < distance[b]; });

  // 3. Each over the ones inside it, in `order`; the whole scene judged as one at the end.
  // The positions of step 1, where a second order starts.
  std::vector<std::vector<Vec3>> laid_alone;
  for (const Mesh& m : meshes) laid_alone.push_back(m.positions);
  const auto lay = [&](const std::vector<std::uint32_t>& order, LayeringOrderRecord& tried) {
    for (std::size_t k = 0; k < order.size(); ++k) {
      const Piece& piece = pieces[order[k]];
      LayerRecord layer;
      layer.mesh = piece.mesh;
      layer.component = named[order[k]];
      layer.distance = distance[order[k]];
      // The piece, the ones inside it as obstacles, the obstacles.
      std::vector<Mesh> scene{piece_mesh(meshes[piece.mesh], piece, Role::kMovable)};
      PinMask scene_pins(1);
      const std::vector<std::uint8_t> mesh_pins = pins_of(piece.mesh);
      if (!mesh_pins.empty())
        for (std::uint32_t v : piece.vertices)
          scene_pins[0].push_back(v < mesh_pins.size() ? mesh_pins[v] : 0);
      for (std::size_t i = 0; i < k; ++i) {
        const Piece& inner = pieces[order[i]];
        scene.push_back(piece_mesh(meshes[inner.mesh], inner, Role::kObstacle));
        scene_pins.emplace_back();
      }
      for (std::uint32_t o : obstacles) {
        scene.push_back(meshes[o]);
        scene_pins.emplace_back();
      }
      const Intersections found = detect_as_check(scene, options.threads);
      layer.clean = found.counts.crossings == 0 && found.counts.inside_vertices == 0;
      if (k == 0 || layer.clean || cancelled) {
        tried.layers.push_back(std::move(layer));
        continue;
      }
      // The plan: the inner pieces flattened onto the obstacles' surface.
      ContinuationPlan plan;
      plan.inward.resize(scene.size());
      for (std::size_t i = 1; i <= k; ++i) {
        plan.inward[i].resize(scene[i].positions.size());
        for (std::size_t v = 0; v < scene[i].positions.size(); ++v) {
          const Vec3& p = scene[i].positions[v];
          const Vec3 in = sub(closest(p), p);
          plan.inward[i][v] = in;
          const double length = norm(in);
          plan.largest_shrink = std::max(plan.largest_shrink, length);
          if (length > 0.0) ++plan.shrunk_vertices;
        }
      }
      plan.movable_edge = edge[order[k]];
      if (!(plan.movable_edge > 0.0) || !(plan.largest_shrink > 0.0)) {
        tried.layers.push_back(std::move(layer));
        continue;
      }
      plan.steps = continuation_steps(plan.largest_shrink, plan.movable_edge);
      // Each step relaxes toward the shape the piece had alone on the obstacles, not toward its
      // input: the input lies through the obstacles. Measured with whole garments as the layers,
      // relaxed toward its input female_sportsuit01 over female_casualsuit01 on their body kept 15
      // crossings, relaxed toward its shape alone it ended clean.
      const FixResult r =
          run_continuation(scene, plan, alone, scene_pins, round, watch, layer.runs, 5);
      take(r);
      layer.clean = r.clean;
      for (std::size_t i = 0; i < piece.vertices.size(); ++i)
        meshes[piece.mesh].positions[piece.vertices[i]] = scene[0].positions[i];
      tried.layers.push_back(std::move(layer));
    }
    FixResult judged;
    const Intersections after = detect_as_check(meshes, options.threads);
    judged.after = after.counts;
    judged.clean = !cancelled && after.counts.crossings == 0 && after.counts.inside_vertices == 0;
    judged.iterations = last_iterations;
    judged.quality = measure_quality(input, meshes);
    tried.clean = judged.clean;
    tried.crossings = after.counts.crossings;
    tried.inside_vertices = after.counts.inside_vertices;
    tried.max_stretch = largest_stretch(judged);
    return judged;
  };

  // The median distances first. Where that ends unresolved or beyond the bounds, the order where
  // the pieces overlap too, from the same garments alone, and the better of the two is kept (a
  // tie keeps the first). Neither order wins on every scene: on the six pairs of MakeHuman
  // garments on their bodies (docs/PERFORMANCE.md) the median distances gave the better result
  // on three, the overlaps on the other three.
  record.orders.emplace_back();  // by median distance
  FixResult judged = lay(by_distance, record.orders.back());
  std::size_t chosen = 0;
  const std::vector<std::uint32_t> by_overlap = rank(judged, options.bounds) > 0 && !cancelled
                                                    ? layer_order(foot, depth, distance, edge)
                                                    : by_distance;
  if (by_overlap != by_distance) {
    std::vector<Mesh> first = meshes;
    for (std::size_t m = 0; m < meshes.size(); ++m) meshes[m].positions = laid_alone[m];
    record.orders.emplace_back();
    record.orders.back().rule = LayerOrderRule::kOverlap;
    FixResult other = lay(by_overlap, record.orders.back());
    if (!cancelled && better(other, meshes, judged, first, input, options.bounds)) {
      judged = std::move(other);
      chosen = 1;
    } else {
      meshes = std::move(first);
    }
  }
  record.orders[chosen].kept = true;

  result.after = judged.after;
  result.clean = judged.clean;
  result.stalled = !result.clean;
  result.iterations = judged.iterations;
  result.quality = std::move(judged.quality);
  result.displacement = displacement_against(input, meshes);
  const LayeringOrderRecord& kept = record.orders[chosen];
  record.layers = kept.layers;
  record.clean = kept.clean;
  record.crossings = kept.crossings;
  record.inside_vertices = kept.inside_vertices;
  record.max_stretch = kept.max_stretch;
  return result;
}

}  // namespace untangle
