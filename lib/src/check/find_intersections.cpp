// find_intersections: topology, detection, contours, counts (the `check` pipeline).
#include "untangle/intersections.h"

#include <chrono>

#include "check/summarize.h"
#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "detect/run_parallel.h"
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

Intersections find_intersections(const std::vector<Mesh>& meshes, const DetectOptions& options,
                                 DetectTimings* timings, std::vector<MeshInfo>* infos) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const SceneTopology topo = build_topology(meshes);
  if (infos != nullptr) {
    infos->clear();
    for (std::size_t m = 0; m < meshes.size(); ++m) infos->push_back(describe_mesh_in(topo, m, meshes[m]));
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
  find_inside_vertices(topo, role, ObstacleWinding(topo, role), {}, options.threads, inside);
  result.counts.inside_by_mesh = inside_per_mesh(topo, inside);
  for (std::size_t n : result.counts.inside_by_mesh) result.counts.inside_vertices += n;
  const auto t2 = Clock::now();
  if (timings != nullptr) {
    timings->detect_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    timings->topology_ms = std::chrono::duration<double, std::milli>(t_topology - t0).count();
    timings->contours_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
  }
  return result;
}

}  // namespace untangle
