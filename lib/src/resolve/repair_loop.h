// The repair loop: detect -> contours -> regions -> moves -> apply, until clean, capped or stalled.
#pragma once

#include <memory>
#include <vector>

#include "resolve/moves.h"
#include "untangle/fix.h"
#include "untangle/mesh.h"

namespace untangle {

class ObstacleWinding;

// fix_meshes on meshes already in canonical order (canonical_order.h): moves the movable
// meshes' positions in place and returns what the loop computed (`after` counts the state left in
// `meshes`, as the loop detected it; nothing is detected again). `rest` (optional; the same
// meshes, vertex for vertex) is the shape the relaxation moves toward, where the run's input is
// not the asset's shape (the continuation's steps); quality is measured against the run's input.
// `described` (optional) receives describe_mesh_in of each mesh as given, from the loop's topology;
// `winding` (optional) the obstacles' winding numbers the loop built, for a later detection of the
// same obstacles to share (find_intersections_reusing).
FixResult run_repair(std::vector<Mesh>& meshes, const FixOptions& options, const PinMask& pins,
                     const Rounding& round, const FixProgress& progress,
                     const std::vector<Mesh>* rest = nullptr,
                     std::vector<MeshInfo>* described = nullptr,
                     std::shared_ptr<const ObstacleWinding>* winding = nullptr);

// Adds the times of `from` to those of `to` (the attempts of one run share its clock).
void add_times(const FixResult& from, FixResult& to);

// Detection as `check` runs it on a scene (obstacle pairs left out, no separation test): the
// verdict on a result. `winding`: the obstacles' winding numbers of the repair, shared where the
// obstacles are the same (null: built here).
Intersections detect_as_check(const std::vector<Mesh>& meshes, int threads,
                              const ObstacleWinding* winding = nullptr);

// How good a result is, lower better: 0 clean within `bounds`, 1 clean, 2 unresolved.
int rank(const FixResult& r, const QualityBounds& bounds);

// The largest edge-length ratio of a result's meshes (1 without any).
double largest_stretch(const FixResult& r);

// Whether `a` (the continuation or the layering; its meshes `a_meshes`) is better than `b` (the
// attempt kept so far, `b_meshes`), both repairs of `input`: a lower rank; or, both clean beyond
// the bounds, `a` better in its largest stretch or in its faces beyond the bounds
// (faces_beyond_bounds) and no worse in the other, or, better in one and worse in the other,
// with fewer faces turned over. A tie keeps `b`. An unresolved continuation or layering is never
// kept: its steps were each no worse than their own start, not than the input, so it could leave
// more crossings of a kind or a vertex moved further than an unresolved run may write
// (FixOptions::max_written_move).
bool better(const FixResult& a, const std::vector<Mesh>& a_meshes, const FixResult& b,
            const std::vector<Mesh>& b_meshes, const std::vector<Mesh>& input,
            const QualityBounds& bounds);

// fix_meshes (fix.h) whose relaxation moves toward `rest` (per mesh, per input vertex; an
// obstacle's entry its positions now) in place of the input's shape: the simulation's correction,
// whose input is a step's end and whose cloth has a rest shape of its own. Null: fix_meshes.
FixResult fix_meshes_toward(std::vector<Mesh>& meshes,
                            const std::vector<std::vector<Vec3>>* rest, const FixOptions& options,
                            const PinMask& pins, const std::function<Vec3(const Vec3&)>& round,
                            const FixProgress& progress);

}  // namespace untangle
