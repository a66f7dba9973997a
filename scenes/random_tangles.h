// Random tangles (issue 5): seeded scenes of small meshes thrown through each other.
// Reproducible scenes of 2 to 4 small meshes (open sheets, open tubes, closed spheres, boxes and
// tori), for property tests of `fix` and of the detector.
#pragma once

#include <cstdint>
#include <string>

#include "scenes/scenes.h"
#include "untangle/mesh.h"

namespace untangle::scenes {

// ---- primitives not covered by scenes.h ----

// The closed surface of an axis-aligned box centred on `centre` with half extents `half`, each
// face a grid of cells x cells quads (two triangles each). Welded (the faces share their rims),
// outward oriented.
Mesh box_surface(Vec3 centre, Vec3 half, int cells, const std::string& name);
// A closed torus around the z axis through `centre`: `around` rings of `tube` vertices each
// (both >= 3), ring radius `major`, tube radius `minor` (< major). Welded, outward oriented.
Mesh torus(Vec3 centre, double major, double minor, int around, int tube, const std::string& name);

// ---- the random scenes ----

struct RandomTangle {
  Scene scene;  // name "random_tangle_<seed>"; obstacles (if any) have role kObstacle
  // Coordinates snapped to a coarse dyadic grid, sheets and boxes axis-aligned, rotations by
  // quarter turns: exact degeneracies (vertex on face, edge on edge, coplanar overlaps) are likely.
  // Otherwise everything is in general position with probability one.
  bool snapped = false;
  std::string description;  // one line: the meshes, their kinds and resolutions, for messages
};

// The scene of `seed`. The same seed gives the same scene bit for bit on every platform (its own
// integer -> double mapping over std::mt19937_64; no std::*_distribution). Every mesh is welded
// by construction, free of degenerate triangles (also after snapping) and at most a few hundred
// triangles; there is at most one obstacle.
RandomTangle random_tangle(std::uint64_t seed);

}  // namespace untangle::scenes
