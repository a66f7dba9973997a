// A generated scene written as OBJ files (movable_<i>.obj, obstacle_<i>.obj) for CLI tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>
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

// The named generated scene `name` (a test failure, and an empty scene, when there is none).
inline scenes::Scene scene_named(const std::string& name) {
  for (auto& s : scenes::named_scenes())
    if (s.name == name) return s;
  ADD_FAILURE() << "no generated scene named " << name;
  return {};
}

// Per contour of a check or fix report: its two tracks as (mesh, type, separates), sorted, with
// closed and self. Compared as a multiset, it says whether two runs found the same kinds of
// contours whatever their order and numbering.
using ContourSignature = std::tuple<std::array<std::tuple<int, std::string, bool>, 2>, bool, bool>;
inline std::multiset<ContourSignature> contour_signatures(const nlohmann::json& report) {
  std::multiset<ContourSignature> out;
  for (const auto& c : report["contours"]) {
    std::array<std::tuple<int, std::string, bool>, 2> tracks;
    for (int k = 0; k < 2; ++k) {
      tracks[k] = {c["meshes"][k].get<int>(), c["types"][k].get<std::string>(),
                   c["separates"][k].get<bool>()};
    }
    std::sort(tracks.begin(), tracks.end());
    out.insert({tracks, c["closed"].get<bool>(), c["self"].get<bool>()});
  }
  return out;
}

}  // namespace untangle::testing
