// A generated scene written as OBJ files (movable_<i>.obj, obstacle_<i>.obj) for CLI tests.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scenes/scenes.h"
#include "test_support.h"

namespace untangle::testing {

struct SceneFiles : scenes::SceneFiles {
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
  return {scenes::write_scene_files(scene, folder)};
}

inline SceneFiles write_scene(const scenes::Scene& scene, const TempDir& dir) {
  return write_scene(scene, dir.path().string());
}

}  // namespace untangle::testing
