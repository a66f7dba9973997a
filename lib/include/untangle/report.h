// JSON reports and contour polylines: what `info` and `check` write for people and pipelines.
#pragma once

#include <string>
#include <vector>

#include "untangle/fix.h"
#include "untangle/intersections.h"
#include "untangle/mesh.h"
#include "untangle/mesh_info.h"

namespace untangle {

// 3: untangle_version in every report (2 in the branch that added it), inside_vertices and
// inside_by_mesh in every counts object, quality in the fix report, and a status that is clean
// only with no vertex inside an obstacle.
// 4: the fix status `distorted`, quality measured on the files written (with max_stretch,
// max_displacement_over_diagonal, within_bounds), the bounds and relax among the options, relax.
// 5: `contacts` in every counts object (exact contact per pair of meshes: seam_vertices,
// repeated_faces, coplanar_pairs), and repeated faces left out of detection.
// 6: `reverted` in the fix report.
// 7: relax_sweeps among the fix options.
// 8: `layering` in the fix report and among its options. 9: the layering's `orders`. 10: the
// continuation's `gave_up`. 11: `scaled_continuation`. 12: `piece_moves` in the fix report and
// among its options. 13: `second_scaled_continuation`, and `chosen_by` in both.
inline constexpr int kReportSchemaVersion = 13;

struct CheckTimingsMs {
  double load = 0.0, detect = 0.0, contours = 0.0, total = 0.0;
};

// The `info` report: schema_version, command, meshes (path, name, role, and every MeshInfo field).
std::string info_report_json(const std::vector<Mesh>& meshes, const std::vector<MeshInfo>& infos);

// The `check` report. Keys and their order are stable; only timing_ms varies between runs.
// schema_version, command, status (clean | intersecting), meshes (path, name, role, vertices,
// faces, boundary_loops), before (crossings, triangle_pairs, contours, contour_length, tracks,
// pairs, loop_vertices, non_separating, branch_points, inside_vertices, inside_by_mesh), contours (meshes, types, closed, self,
// crossings, length, loop_vertices, separates, smaller_area, cut_edges), timing_ms.
std::string check_report_json(const std::vector<Mesh>& meshes, const std::vector<MeshInfo>& infos,
                              const Intersections& found, const CheckTimingsMs& timings);

struct FixTimingsMs {
  double load = 0.0, detect = 0.0, contours = 0.0, resolve = 0.0, write = 0.0, verify = 0.0,
         total = 0.0;
};

// The `fix` report: the check keys (status is clean | unresolved | distorted, judge_result of the
// files written; `before` as detected on the input, `after` and `contours` as detected on the
// files written), plus options (method, max_iterations, clearance, outside_closed_obstacles,
// relax, max_stretch, max_flips, max_move), iterations, stalled, outputs, history (iteration,
// crossings, contour_length, elapsed_ms), displacement (max, mean, max_over_mean_edge,
// moved_vertices), quality (per movable mesh, of the files written against the input: mesh,
// edge_change_mean, edge_change_p95, edge_change_max, max_stretch, flipped_faces,
// max_displacement, max_displacement_over_mean_edge, max_displacement_over_diagonal,
// within_bounds), regions (by_inside, by_area), relax (sweeps, vertices), obstacles
// (crossing_pairs: FixResult::obstacle_crossing_pairs) and timing_ms (load, detect, contours,
// resolve, relax, write, verify, total).
std::string fix_report_json(const std::vector<Mesh>& meshes, const std::vector<MeshInfo>& infos,
                            const std::vector<std::string>& outputs, const FixOptions& options,
                            const QualityBounds& bounds, const FixResult& result,
                            const Intersections& verified, const FixTimingsMs& timings);

// OBJ text of the contour polylines: one object per contour named
// `contour_<k>_<type0>_<type1>` (with `_self` for self-intersections), `l` elements through its
// points, closed contours returning to their first point.
std::string contours_obj(const Intersections& found);

// Writes `text` to `path` through a temporary file in the same folder and a rename, so that no
// partial file is ever left. Throws Error(kOutputNotWritten) naming the path.
void write_text_file_atomically(const std::string& path, const std::string& text);

}  // namespace untangle
