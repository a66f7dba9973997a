// Generated scenes for self-intersections, loop vertices and layered garments (issue 4).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scenes/scenes.h"
#include "untangle/mesh.h"

namespace untangle::scenes {

// ---- mesh operations ----

// Midpoint subdivision: every triangle into four (corners kept, orientation kept), the midpoint of
// an edge shared by two triangles made once (welded). The shape does not change, so neither does
// the intersection curve in space; `polygon` and `triangle_group` follow the parent triangle.
Mesh subdivide_midpoint(const Mesh& mesh);
// `levels` rounds of subdivide_midpoint.
Mesh subdivide_midpoint(const Mesh& mesh, int levels);
// The same surface with vertex order, triangle order and each triangle's first corner shuffled by
// a fixed, platform-independent generator (orientation kept).
Mesh permuted(const Mesh& mesh, std::uint64_t seed);
// Both meshes in one (b's vertices and triangles after a's); name and role of `a`.
Mesh merged(const Mesh& a, const Mesh& b, const std::string& name);
// Rotation by `angle` (radians) about the axis x (0), y (1) or z (2) through the origin, then
// translation by `offset`.
Mesh rotated(Mesh mesh, int axis, double angle, Vec3 offset);

// ---- the self-intersection configurations of Wicke et al. 2006 ----

// One movable sheet each (built from a flat "base" in z = 0 and "flaps" folded back over it along
// a fold line). The base lies on a grid of spacing 1/2; the flaps' coordinates are literals with
// four decimals, so that no vertex lies on a triangle it does not belong to and no two edges
// without a common vertex meet, also after midpoint subdivision (flap heights with small dyadic
// ratios would put subdivided crossings exactly on the base's grid lines). Triangulated "union
// jack" style so the loop-vertex cases can choose a vertex with four neighbours (one on the fold)
// or eight (three on the fold).
enum class WickeCase {
  kClosed,            // a bump of the flap through the base: one closed contour, CL / CL
  kBoundaryBoundary,  // a narrow flap dives through the base: BB (flap) / II (base)
  kBoundaryInterior,  // a flap dives through the base across its side edge: BI / BI
  kLoopVertex,        // the fold passes 180 degrees at one fold vertex: loop vertex to boundary
  kCrossing,          // two flaps dive through the base and each other: contours crossing
  kFigureEight,       // a flap vertex next to one fold vertex pushed through: loop vertex to itself
  kLoopToLoop,        // a flap vertex next to three fold vertices pushed through: loop to loop
};
const char* to_string(WickeCase c);
std::vector<WickeCase> all_wicke_cases();
Mesh wicke_scene(WickeCase c);

// ---- larger self-intersections ----

// A square sheet (nt x ny vertices) along the nodal cubic x = t^2 - 1, z = t (t^2 - 1) s(y): the
// half t > 0 folds back through the half t < 0 along one line across the whole sheet.
Mesh folded_through_itself(int nt, int ny);
// A sheet rolled into a spiral of three turns (columns around, rows along z) whose radius wobbles
// so that neighbouring turns pass through each other in several closed patches.
Mesh spiral_roll(int columns, int rows);
// An open tube (radius 1, length 3) whose +x wall is pushed in, through the -x wall and out.
Mesh pinched_tube(int slices, int rings);

// ---- layers and obstacles ----

// Three layers along the z axis: an open "dress" tube (radius 1) over an open "t-shirt" tube
// (radius 0.9) over a closed capsule "body" (radius 0.8, obstacle). Smooth radial dents: the dress
// dips through the t-shirt alone in one place and through t-shirt and body in another; the t-shirt
// dips through the body in a third. Legal order everywhere else: dress outside t-shirt outside
// body.
Scene three_layers(int slices, int rings);
// Two layers made for one body at one offset: an open "dress" tube (radius 0.902 on average, a
// gentle wobble of 0.01) over an open "t-shirt" tube (radius 0.9), over a closed capsule "body"
// (radius 0.8, obstacle). About two fifths of the dress lies inside the t-shirt, in patches all
// over: the two cross everywhere at a small angle, the way MakeHuman's dress and t-shirt for one
// body do.
Scene interleaved_layers(int slices, int rings);
// A dress with a turned-down collar over a t-shirt over a body: the dress's band (radius 0.902,
// wobbling 0.01 round the t-shirt as in interleaved_layers) rises to z = 0.95 and folds sharply
// down again as a collar pressed onto it (radius 0.906, wobbling 0.004) to z = 0.55. Over the
// fold, collar and band triangles that share a vertex cross (contours through loop vertices), and
// the collar dips through the band in patches. The t-shirt (radius 0.9, an open tube up to
// z = 0.9) lies under band and collar; the body is a closed capsule (radius 0.8, obstacle).
// `band_rings` rings along the band, a fifth of that along the collar.
Scene turned_down_collar(int slices, int band_rings);
// Two overlapping capsules (one along y, one along x, their caps and walls crossing) as one closed
// but self-intersecting mesh.
Mesh self_intersecting_obstacle(int slices);

}  // namespace untangle::scenes
