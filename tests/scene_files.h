// A generated scene written as OBJ files (movable_<i>.obj, obstacle_<i>.obj) for CLI tests.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scenes/scenes.h"
#include "test_support.h"

namespace untangle::testing {

struct SceneFiles {
  std::vector<std::string> movable, obstacles;
  // The CLI arguments naming them: movable files, then --obstacle FILE for each obstacle.
  std::string inputs_args() const {
    std::string args;
    for (const auto& m : movable) args += " " + quote(m);
    for (const auto& o : obstacles) args += " --obstacle " + quote(o);
    return args;
  }
};

// Writes every mesh of `scene` under `folder` (created if missing).
inline SceneFiles write_scene(const scenes::Scene& scene, const std::string& folder) {
  std::filesystem::create_directories(folder);
  SceneFiles files;
  for (std::size_t i = 0; i < scene.movable.size(); ++i) {
    files.movable.push_back(folder + "/movable_" + std::to_string(i) + ".obj");
    scenes::write_obj(scene.movable[i], files.movable.back());
  }
  for (std::size_t i = 0; i < scene.obstacles.size(); ++i) {
    files.obstacles.push_back(folder + "/obstacle_" + std::to_string(i) + ".obj");
    scenes::write_obj(scene.obstacles[i], files.obstacles.back());
  }
  return files;
}

inline SceneFiles write_scene(const scenes::Scene& scene, const TempDir& dir) {
  return write_scene(scene, dir.path().string());
}

}  // namespace untangle::testing
