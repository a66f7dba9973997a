// The example scenes of `untangle simulate --example` (sim_examples.h).
#include "scenes/sim_examples.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "geometry/vec3.h"
#include "scenes/random_tangles.h"
#include "scenes/scenes.h"
#include "untangle/error.h"
#include "untangle/read_meshes.h"

namespace untangle::scenes {
namespace {

struct Box {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
};

Box bounds(const Mesh& mesh) {
  Box box;
  for (const Vec3& p : mesh.positions)
    for (int c = 0; c < 3; ++c) {
      box.lo[c] = std::min(box.lo[c], p[c]);
      box.hi[c] = std::max(box.hi[c], p[c]);
    }
  return box;
}

std::vector<Mesh> read_installed(const std::string& path, Role role, const std::string& what) {
  if (path.empty() || !std::filesystem::exists(path))
    throw Error(ExitCode::kUnreadableInput, path, what + " is not installed");
  return read_meshes(path, role);
}

}  // namespace

std::string makehuman_dir() { return UNTANGLE_MAKEHUMAN_DIR; }

const char* simulation_example_names() { return "ball, box, spikes, cow or fitting"; }

SimulationScene simulation_example(const std::string& name, int resolution) {
  SimulationScene scene;
  const int n = resolution > 0 ? resolution : 81;
  if (name == "ball" || name == "box") {
    const int m = resolution > 0 ? resolution : 21;
    scene.meshes.push_back(
        grid_sheet(m, m, {-0.8, 0.7, -0.8}, {1.6, 0.013, 0.0}, {0.0, -0.011, 1.6}, "sheet"));
    if (name == "ball")
      scene.meshes.push_back(uv_sphere({0.01, 0.0, -0.02}, 0.5, 32, 16, "ball"));
    else
      scene.meshes.push_back(box_surface({0.0, 0.0, 0.0}, {1.5, 0.5, 1.5}, 8, "box"));
    scene.meshes.back().role = Role::kObstacle;
  } else if (name == "spikes") {
    // Slightly tilted, so that no edge of the sheet lies exactly over a row of tips.
    scene.meshes.push_back(
        grid_sheet(n, n, {-1.0, 0.45, -1.0}, {2.0, 0.0, 0.017}, {0.013, 0.0, 2.0}, "sheet"));
    Mesh spikes = cone_spikes({0.0, 0.0, 0.0}, 1.6, 4, 0.4, "spikes");
    for (Vec3& p : spikes.positions) p = Vec3{p[0], p[2], -p[1]};  // tips up (+y)
    spikes.role = Role::kObstacle;
    scene.meshes.push_back(std::move(spikes));
  } else if (name == "cow") {
    // The cow spans x -0.5 (tail) to 0.5 (head); the sheets, 1.1 a side, fall from 0.06 above
    // its highest point, 0.08 apart, each turned a little against the one below.
    std::vector<Mesh> cow = read_installed(cow_path(), Role::kObstacle, "the cow of libcgal-demo");
    Box box;
    for (const Mesh& mesh : cow) {
      const Box b = bounds(mesh);
      for (int c = 0; c < 3; ++c) {
        box.lo[c] = std::min(box.lo[c], b.lo[c]);
        box.hi[c] = std::max(box.hi[c], b.hi[c]);
      }
    }
    const double cx = 0.5 * (box.lo[0] + box.hi[0]), cz = 0.5 * (box.lo[2] + box.hi[2]);
    for (int k = 0; k < 4; ++k) {
      const double angle = 0.07 + 0.21 * k, side = 1.1;
      const Vec3 u{side * std::cos(angle), 0.011, side * std::sin(angle)};
      const Vec3 v{-side * std::sin(angle), -0.007, side * std::cos(angle)};
      const Vec3 origin{cx - 0.5 * (u[0] + v[0]), box.hi[1] + 0.06 + 0.08 * k - 0.5 * (u[1] + v[1]),
                        cz - 0.5 * (u[2] + v[2])};
      scene.meshes.push_back(grid_sheet(n, n, origin, u, v, "sheet" + std::to_string(k + 1)));
    }
    for (std::size_t k = 0; k < cow.size(); ++k) {
      cow[k].name = k == 0 ? "cow" : "cow_" + std::to_string(k + 1);
      scene.meshes.push_back(std::move(cow[k]));
    }
  } else if (name == "fitting") {
    // Decimetres. The body grows back from 0.97 about its centre, pushing into the garment, which
    // the correction keeps outside frame after frame. Without gravity: nothing holds the trousers
    // up but friction, and with 98.1 dm/s^2 they slid down to the feet and tangled there within
    // 10 frames (measured); a fitting is the garment relaxing onto the body.
    const std::string dir = makehuman_dir();
    std::vector<Mesh> garment = read_installed(dir + "/male_casualsuit04.obj", Role::kMovable,
                                               "the MakeHuman garment of testdata/makehuman");
    std::vector<Mesh> body = read_installed(dir + "/male_generic.obj", Role::kObstacle,
                                            "the MakeHuman body of testdata/makehuman");
    // Each mesh is written to a file of its own name (garment, garment_2, ...).
    auto add_meshes = [&](std::vector<Mesh>& meshes, const std::string& stem) {
      for (std::size_t k = 0; k < meshes.size(); ++k) {
        meshes[k].name = k == 0 ? stem : stem + "_" + std::to_string(k + 1);
        scene.meshes.push_back(std::move(meshes[k]));
      }
    };
    add_meshes(garment, "garment");
    const std::size_t first_body = scene.meshes.size();
    add_meshes(body, "body");
    scene.options.gravity = {0.0, 0.0, 0.0};
    for (std::size_t m = first_body; m < scene.meshes.size(); ++m) {
      const Box b = bounds(scene.meshes[m]);
      ObstacleSchedule schedule;
      schedule.mesh = m;
      schedule.centre = scale(add(b.lo, b.hi), 0.5);
      schedule.from = 0.97;
      schedule.frames = 20;
      scene.schedules.push_back(schedule);
    }
  } else {
    throw Error(ExitCode::kUsage, "",
                "unknown example '" + name + "' (" + simulation_example_names() + ")");
  }
  return scene;
}

}  // namespace untangle::scenes
