// StepDetector (step_detector.h): incremental detection between the steps of a simulation.
#include "sim/step_detector.h"

namespace untangle {

StepDetector::StepDetector(const std::vector<Mesh>& meshes, int threads)
    : topo_(build_topology(meshes)) {
  settings_.threads = threads;
  for (const Mesh& mesh : meshes) {
    role_.push_back(mesh.role);
    settings_.skip_among.push_back(mesh.role == Role::kObstacle);
  }
  changed_.assign(topo_.points.size(), 0);
  build_obstacles();
}

void StepDetector::build_obstacles() {
  obstacle_bvh_ = std::make_unique<TriangleBvh>(topo_, settings_.skip_among);
  settings_.skipped_bvh = obstacle_bvh_.get();
  winding_ = std::make_unique<ObstacleWinding>(topo_, role_, settings_.threads);
  hierarchy_ = std::make_unique<SceneHierarchy>(topo_, settings_);
  set_ = detect_crossings(topo_, settings_);
  find_inside_by_parts(topo_, role_, *winding_, set_, settings_.threads, inside_);
}

void StepDetector::detect(const std::vector<Mesh>& meshes, bool obstacles_moved) {
  bool any = false;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const std::vector<std::uint32_t>& welded = topo_.welded[m];
    for (std::size_t i = 0; i < welded.size(); ++i) {
      Vec3& p = topo_.points[welded[i]];
      if (p == meshes[m].positions[i]) continue;
      p = meshes[m].positions[i];
      changed_[welded[i]] = 1;
      any = true;
    }
  }
  if (obstacles_moved) {
    build_obstacles();
  } else if (any) {
    hierarchy_->update(topo_, changed_);
    set_ = update_crossings(topo_, settings_, *hierarchy_, set_, changed_);
    find_inside_by_parts(topo_, role_, *winding_, set_, settings_.threads, inside_);
  }
  std::fill(changed_.begin(), changed_.end(), 0);
}

std::size_t StepDetector::inside_vertices() const {
  std::size_t n = 0;
  for (std::uint32_t v : inside_) n += v != kNone ? 1 : 0;
  return n;
}

}  // namespace untangle
