// find_intersections: topology, detection, contours, counts (the `check` pipeline).
#include "untangle/intersections.h"

#include "check/find_intersections.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <tuple>

#include "check/summarize.h"
#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "detect/run_parallel.h"
#include "resolve/canonical_order.h"
#include "resolve/inside_vertices.h"
#include "topology/describe_mesh.h"
#include "topology/scene_topology.h"

namespace untangle {

const char* to_string(TrackType type) {
  switch (type) {
    case TrackType::kCL: return "CL";
    case TrackType::kBB: return "BB";
    case TrackType::kBI: return "BI";
    case TrackType::kII: return "II";
  }
  return "?";
}

namespace {

// The result of a detection on the canonical scene, in the input's meshes, vertex and triangle
// indices: crossings sorted again by them (contours keep pointing at the same crossings, and come
// in the order of their lowest crossing again), pairs likewise, per-mesh counts reordered.
void to_input_indices(const CanonicalScene& scene, Intersections& result) {
  const std::size_t n = result.crossings.size();
  const auto& mesh_of = scene.mesh_order;
  const auto& canon = scene.renumbering;
  for (Crossing& c : result.crossings) {
    const auto& vertices = canon[c.edge_mesh].vertex_order;
    c.edge_v0 = vertices[c.edge_v0];
    c.edge_v1 = vertices[c.edge_v1];
    if (c.edge_v1 < c.edge_v0) std::swap(c.edge_v0, c.edge_v1);
    c.face = canon[c.face_mesh].triangle_order[c.face];
    c.edge_mesh = mesh_of[c.edge_mesh];
    c.face_mesh = mesh_of[c.face_mesh];
  }
  auto key = [](const Crossing& c) {
    return std::make_tuple(c.edge_mesh, c.edge_v0, c.edge_v1, c.face_mesh, c.face);
  };
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return key(result.crossings[a]) < key(result.crossings[b]);
  });
  std::vector<std::uint32_t> position(n);
  std::vector<Crossing> sorted;
  sorted.reserve(n);
  for (std::uint32_t k = 0; k < n; ++k) {
    position[order[k]] = k;
    sorted.push_back(result.crossings[order[k]]);
  }
  result.crossings = std::move(sorted);
  for (Contour& contour : result.contours) {
    for (std::uint32_t& c : contour.crossings) c = position[c];
    for (Track& track : contour.tracks) track.mesh = mesh_of[track.mesh];
  }
  const auto lowest = [](const Contour& c) {
    return c.crossings.empty() ? static_cast<std::uint32_t>(-1)
                               : *std::min_element(c.crossings.begin(), c.crossings.end());
  };
  std::stable_sort(result.contours.begin(), result.contours.end(),
                   [&](const Contour& a, const Contour& b) { return lowest(a) < lowest(b); });
  for (auto& p : result.triangle_pairs) {
    p[1] = canon[p[0]].triangle_order[p[1]];
    p[3] = canon[p[2]].triangle_order[p[3]];
    p[0] = mesh_of[p[0]];
    p[2] = mesh_of[p[2]];
    if (std::make_pair(p[2], p[3]) < std::make_pair(p[0], p[1])) {
      std::swap(p[0], p[2]);
      std::swap(p[1], p[3]);
    }
  }
  std::sort(result.triangle_pairs.begin(), result.triangle_pairs.end());
  counts_in_input_order(scene, result.counts);
}

}  // namespace

// Detection runs on the canonical scene, as the repair does (canonical_order.h): the symbolic
// perturbation resolves exact degeneracies by vertex ids, so `check`, `fix`'s `before` and its
// verdict on the written files decide them alike, whatever the file's order and the order the
// meshes are listed in.
Intersections find_intersections(const std::vector<Mesh>& input, const DetectOptions& options,
                                 DetectTimings* timings, std::vector<MeshInfo>* infos) {
  return find_intersections_reusing(input, options, nullptr, timings, infos);
}

Intersections find_intersections_reusing(const std::vector<Mesh>& input,
                                         const DetectOptions& options,
                                         const ObstacleWinding* earlier, DetectTimings* timings,
                                         std::vector<MeshInfo>* infos) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  CanonicalScene scene = canonical_scene(input);
  const std::vector<Mesh>& meshes = scene.meshes;
  const SceneTopology topo = build_topology(meshes);
  if (infos != nullptr) {
    std::vector<MeshInfo> described;
    for (std::size_t m = 0; m < meshes.size(); ++m) described.push_back(describe_mesh_in(topo, m, meshes[m]));
    *infos = in_input_order(scene, described);
  }
  const auto t_topology = Clock::now();
  DetectSettings settings;
  settings.threads = options.threads;
  settings.self_pairs = options.self_intersections;
  if (options.skip_obstacle_pairs) {
    for (const Mesh& m : meshes) settings.skip_among.push_back(m.role == Role::kObstacle);
  }
  const CrossingSet set = detect_crossings(topo, settings);
  const auto t1 = Clock::now();
  // The contours, and meanwhile the crossings and pairs of the result (each into its own slot).
  std::vector<TracedContour> traced;
  Intersections result;
  run_parallel(options.threads, 2, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t part = begin; part < end; ++part) {
      if (part == 0) {
        traced = build_contours(topo, set, options.threads, options.separation);
      } else {
        result = summarize_crossings(topo, set);
      }
    }
  });
  add_contours(traced, result, options.separation);
  // Movable vertices inside the obstacles, on the positions as given (the verdict of `fix` is
  // taken on the files written and read back).
  std::vector<Role> role;
  for (const Mesh& m : meshes) role.push_back(m.role);
  std::vector<std::uint32_t> inside;
  find_inside_by_parts(topo, role, ObstacleWinding(topo, role, options.threads, earlier), set,
                       options.threads, inside);
  result.counts.inside_by_mesh = inside_per_mesh(topo, inside);
  for (std::size_t n : result.counts.inside_by_mesh) result.counts.inside_vertices += n;
  to_input_indices(scene, result);
  const auto t2 = Clock::now();
  if (timings != nullptr) {
    timings->detect_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    timings->topology_ms = std::chrono::duration<double, std::milli>(t_topology - t0).count();
    timings->contours_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
  }
  return result;
}

}  // namespace untangle
