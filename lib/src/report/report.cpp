// JSON reports (nlohmann::ordered_json keeps key order stable) and contour OBJ text.
#include "untangle/report.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "untangle/error.h"
#include "untangle/version.h"

namespace untangle {
namespace {

using Json = nlohmann::ordered_json;

Json mesh_entry(const Mesh& mesh, const MeshInfo& info) {
  Json j;
  j["path"] = mesh.path;
  j["name"] = mesh.name;
  j["role"] = to_string(mesh.role);
  j["vertices"] = info.vertices;
  j["faces"] = info.faces;
  j["boundary_loops"] = info.boundary_loops;
  // Legal input, handled (dropped or decided symbolically), but worth knowing about.
  j["degenerate_triangles"] = info.degenerate_triangles;
  j["zero_area_triangles"] = info.zero_area_triangles;
  return j;
}

// The continuation's steps, or a layer's.
Json continuation_steps_json(const std::vector<ContinuationStep>& steps) {
  Json runs = Json::array();
  for (const ContinuationStep& r : steps) {
    Json step;
    step["shrink"] = r.shrink;
    step["crossings_before"] = r.crossings_before;
    step["inside_before"] = r.inside_before;
    step["crossings_after"] = r.crossings_after;
    step["inside_after"] = r.inside_after;
    step["iterations"] = r.iterations;
    step["clean"] = r.clean;
    runs.push_back(step);
  }
  return runs;
}

// A continuation's record (null when it did not run); `factor` only for the scaled one.
Json continuation_json(const ContinuationRecord& c) {
  if (!c.ran) return nullptr;
  Json e;
  if (c.factor > 0.0) e["factor"] = c.factor;
  if (c.chosen_by != ScaleChoice::kNone)
    e["chosen_by"] = c.chosen_by == ScaleChoice::kDepth ? "depth" : "count";
  e["steps"] = c.steps;
  e["deepest"] = c.deepest;
  e["largest_shrink"] = c.largest_shrink;
  e["shrunk_vertices"] = c.shrunk_vertices;
  e["clean"] = c.clean;
  e["crossings"] = c.crossings;
  e["inside_vertices"] = c.inside_vertices;
  e["max_stretch"] = c.max_stretch;
  e["kept"] = c.kept;
  e["gave_up"] = c.gave_up;
  e["runs"] = continuation_steps_json(c.runs);
  return e;
}

Json layers_json(const std::vector<LayerRecord>& layers) {
  Json all = Json::array();
  for (const LayerRecord& layer : layers) {
    Json one;
    one["mesh"] = layer.mesh;
    one["component"] = layer.component;
    one["distance"] = layer.distance;
    one["clean"] = layer.clean;
    one["runs"] = continuation_steps_json(layer.runs);
    all.push_back(one);
  }
  return all;
}

Json counts_json(const IntersectionCounts& c) {
  Json j;
  j["crossings"] = c.crossings;
  j["triangle_pairs"] = c.triangle_pairs;
  j["contours"] = c.contours;
  j["contour_length"] = c.contour_length;
  Json tracks;
  tracks["CL"] = c.tracks[0];
  tracks["BB"] = c.tracks[1];
  tracks["BI"] = c.tracks[2];
  tracks["II"] = c.tracks[3];
  j["tracks"] = tracks;
  Json pairs;
  pairs["CL/CL"] = c.pairs_cl_cl;
  pairs["BB/II"] = c.pairs_bb_ii;
  pairs["BI/BI"] = c.pairs_bi_bi;
  pairs["self"] = c.pairs_self;
  pairs["other"] = c.pairs_other;
  j["pairs"] = pairs;
  j["loop_vertices"] = c.loop_vertices;
  j["non_separating"] = c.non_separating;
  j["branch_points"] = c.branch_points;
  j["inside_vertices"] = c.inside_vertices;
  j["inside_by_mesh"] = c.inside_by_mesh;
  Json contacts = Json::array();
  for (const MeshContact& m : c.contacts) {
    Json e;
    e["meshes"] = {m.mesh_a, m.mesh_b};
    e["seam_vertices"] = m.seam_vertices;
    e["repeated_faces"] = m.repeated_faces;
    e["coplanar_pairs"] = m.coplanar_pairs;
    contacts.push_back(e);
  }
  j["contacts"] = contacts;
  return j;
}

Json contour_json(const Contour& c) {
  Json j;
  j["meshes"] = {c.tracks[0].mesh, c.tracks[1].mesh};
  j["types"] = {to_string(c.tracks[0].type), to_string(c.tracks[1].type)};
  j["closed"] = c.closed;
  j["self"] = c.self;
  j["crossings"] = c.crossings.size();
  j["length"] = c.length;
  j["loop_vertices"] = c.loop_vertices;
  j["separates"] = {c.tracks[0].separates, c.tracks[1].separates};
  j["smaller_area"] = {c.tracks[0].smaller_area, c.tracks[1].smaller_area};
  j["cut_edges"] = {c.tracks[0].cut_edges, c.tracks[1].cut_edges};
  return j;
}

}  // namespace

std::string info_report_json(const std::vector<Mesh>& meshes, const std::vector<MeshInfo>& infos) {
  Json j;
  j["schema_version"] = kReportSchemaVersion;
  j["untangle_version"] = untangle_version();
  j["command"] = "info";
  Json list = Json::array();
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const MeshInfo& info = infos[i];
    Json m = mesh_entry(meshes[i], info);
    m["triangles"] = info.triangles;
    m["welded_vertices"] = info.welded_vertices;
    m["components"] = info.components;
    m["boundary_edges"] = info.boundary_edges;
    m["non_manifold_edges"] = info.non_manifold_edges;
    m["degenerate_triangles"] = info.degenerate_triangles;
    m["zero_area_triangles"] = info.zero_area_triangles;
    m["closed"] = info.closed;
    m["area"] = info.area;
    m["mean_edge_length"] = info.mean_edge_length;
    list.push_back(m);
  }
  j["meshes"] = list;
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string check_report_json(const std::vector<Mesh>& meshes, const std::vector<MeshInfo>& infos,
                              const Intersections& found, const CheckTimingsMs& timings) {
  Json j;
  j["schema_version"] = kReportSchemaVersion;
  j["untangle_version"] = untangle_version();
  j["command"] = "check";
  j["status"] =
      found.counts.crossings == 0 && found.counts.inside_vertices == 0 ? "clean" : "intersecting";
  Json list = Json::array();
  for (std::size_t i = 0; i < meshes.size(); ++i) list.push_back(mesh_entry(meshes[i], infos[i]));
  j["meshes"] = list;
  j["before"] = counts_json(found.counts);
  Json contours = Json::array();
  for (const Contour& c : found.contours) contours.push_back(contour_json(c));
  j["contours"] = contours;
  Json t;
  t["load"] = timings.load;
  t["detect"] = timings.detect;
  t["contours"] = timings.contours;
  t["total"] = timings.total;
  j["timing_ms"] = t;
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string fix_report_json(const std::vector<Mesh>& meshes, const std::vector<MeshInfo>& infos,
                            const std::vector<std::string>& outputs, const FixOptions& options,
                            const QualityBounds& bounds, const FixResult& result,
                            const Intersections& verified, const FixTimingsMs& timings) {
  Json j;
  j["schema_version"] = kReportSchemaVersion;
  j["untangle_version"] = untangle_version();
  j["command"] = "fix";
  j["status"] = to_string(judge_result(verified.counts, result.quality, bounds));
  Json list = Json::array();
  for (std::size_t i = 0; i < meshes.size(); ++i) list.push_back(mesh_entry(meshes[i], infos[i]));
  j["meshes"] = list;
  j["outputs"] = outputs;
  Json opts;
  opts["method"] = to_string(options.method);
  opts["max_iterations"] = options.max_iterations;
  opts["clearance"] = options.clearance;
  opts["outside_closed_obstacles"] = options.outside_closed_obstacles;
  opts["relax"] = options.relax;
  opts["relax_sweeps"] = options.relax_sweeps;
  opts["retries"] = options.retries;
  opts["continuation"] = options.continuation;
  opts["layering"] = options.layering;
  opts["piece_moves"] = options.piece_moves;
  opts["max_stretch"] = bounds.max_stretch;
  opts["max_flips"] = bounds.max_flips;
  opts["max_move"] = bounds.max_move;
  j["options"] = opts;
  j["iterations"] = result.iterations;
  j["stalled"] = result.stalled;
  j["reverted"] = result.reverted;
  j["clearance"] = result.clearance;
  Json retries = Json::array();
  for (const RetryRecord& r : result.retries) {
    Json e;
    e["clearance"] = r.clearance;
    e["clean"] = r.clean;
    e["crossings"] = r.crossings;
    e["inside_vertices"] = r.inside_vertices;
    e["iterations"] = r.iterations;
    e["kept"] = r.kept;
    retries.push_back(e);
  }
  j["retries"] = retries;
  j["continuation"] = continuation_json(result.continuation);
  j["scaled_continuation"] = continuation_json(result.scaled_continuation);
  j["second_scaled_continuation"] = continuation_json(result.second_scaled_continuation);
  if (result.piece_moves.ran) {
    const PieceMoveRecord& p = result.piece_moves;
    Json e;
    e["tangled"] = p.tangled;
    e["moved"] = p.moved;
    e["largest_move"] = p.largest_move;
    e["clean"] = p.clean;
    e["kept"] = p.kept;
    Json pieces = Json::array();
    for (const PieceMove& move : p.pieces)
      pieces.push_back({{"mesh", move.mesh}, {"vertex", move.vertex}, {"shift", move.shift}});
    e["pieces"] = pieces;
    j["piece_moves"] = e;
  } else {
    j["piece_moves"] = nullptr;
  }
  if (result.layering.ran) {
    const LayeringRecord& l = result.layering;
    Json e;
    e["layers"] = layers_json(l.layers);
    e["clean"] = l.clean;
    e["crossings"] = l.crossings;
    e["inside_vertices"] = l.inside_vertices;
    e["max_stretch"] = l.max_stretch;
    e["kept"] = l.kept;
    Json orders = Json::array();
    for (const LayeringOrderRecord& o : l.orders) {
      Json one;
      one["rule"] = to_string(o.rule);
      one["layers"] = layers_json(o.layers);
      one["clean"] = o.clean;
      one["crossings"] = o.crossings;
      one["inside_vertices"] = o.inside_vertices;
      one["max_stretch"] = o.max_stretch;
      one["kept"] = o.kept;
      orders.push_back(one);
    }
    e["orders"] = orders;
    j["layering"] = e;
  } else {
    j["layering"] = nullptr;
  }
  j["before"] = counts_json(result.before);
  j["after"] = counts_json(verified.counts);
  Json history = Json::array();
  for (const IterationRecord& r : result.history) {
    Json h;
    h["iteration"] = r.iteration;
    h["crossings"] = r.crossings;
    h["contour_length"] = r.contour_length;
    h["elapsed_ms"] = r.elapsed_ms;
    h["stage"] = r.stage;
    history.push_back(h);
  }
  j["history"] = history;
  Json d;
  d["max"] = result.displacement.max;
  d["mean"] = result.displacement.mean;
  d["max_over_mean_edge"] = result.displacement.max_over_mean_edge;
  d["moved_vertices"] = result.displacement.moved_vertices;
  j["displacement"] = d;
  Json quality = Json::array();
  for (std::size_t m = 0; m < result.quality.size(); ++m) {
    if (m >= meshes.size() || meshes[m].role != Role::kMovable) continue;
    const QualityStats& q = result.quality[m];
    Json e;
    e["mesh"] = m;
    e["edge_change_mean"] = q.edge_change_mean;
    e["edge_change_p95"] = q.edge_change_p95;
    e["edge_change_max"] = q.edge_change_max;
    e["max_stretch"] = q.max_stretch;
    e["flipped_faces"] = q.flipped_faces;
    e["max_displacement"] = q.max_displacement;
    e["max_displacement_over_mean_edge"] = q.max_displacement_over_mean_edge;
    e["max_displacement_over_diagonal"] = q.max_displacement_over_diagonal;
    e["within_bounds"] = within_bounds(q, bounds);
    quality.push_back(e);
  }
  j["quality"] = quality;
  Json regions;
  regions["by_inside"] = result.illegal_regions_by_inside;
  regions["by_area"] = result.illegal_regions_by_area;
  j["regions"] = regions;
  Json relax;
  relax["sweeps"] = result.relax_sweeps;
  relax["vertices"] = result.relaxed_vertices;
  j["relax"] = relax;
  Json obstacles;
  obstacles["crossing_pairs"] = result.obstacle_crossing_pairs;
  j["obstacles"] = obstacles;
  Json contours = Json::array();
  for (const Contour& c : verified.contours) contours.push_back(contour_json(c));
  j["contours"] = contours;
  Json t;
  t["load"] = timings.load;
  t["detect"] = timings.detect;
  t["contours"] = timings.contours;
  t["resolve"] = timings.resolve;
  t["relax"] = result.relax_ms;  // part of resolve
  t["write"] = timings.write;
  t["verify"] = timings.verify;
  t["total"] = timings.total;
  j["timing_ms"] = t;
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string contours_obj(const Intersections& found) {
  std::ostringstream out;
  out.precision(17);
  out << "# untangle contours: " << found.contours.size() << "\n";
  std::size_t base = 1;
  for (std::size_t k = 0; k < found.contours.size(); ++k) {
    const Contour& c = found.contours[k];
    out << "o contour_" << k << "_" << to_string(c.tracks[0].type) << "_"
        << to_string(c.tracks[1].type) << (c.self ? "_self" : "") << "\n";
    for (const Vec3& p : c.polyline) out << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
    if (c.polyline.size() >= 2) {
      out << "l";
      for (std::size_t i = 0; i < c.polyline.size(); ++i) out << " " << base + i;
      if (c.closed && c.polyline.size() > 2) out << " " << base;
      out << "\n";
    }
    base += c.polyline.size();
  }
  return out.str();
}

void write_text_file_atomically(const std::string& path, const std::string& text) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    throw Error(ExitCode::kOutputNotWritten, path, "folder " + folder.string() + " does not exist");
  }
  const fs::path temp = folder / ("." + target.filename().string() + ".untangle-tmp");
  {
    std::ofstream file(temp, std::ios::binary | std::ios::trunc);
    if (!file) throw Error(ExitCode::kOutputNotWritten, path, "cannot create file");
    file << text;
    file.flush();
    if (!file) {
      file.close();
      fs::remove(temp, ec);
      throw Error(ExitCode::kOutputNotWritten, path, "write failed");
    }
  }
  fs::rename(temp, target, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw Error(ExitCode::kOutputNotWritten, path, "cannot rename temporary file into place");
  }
}

}  // namespace untangle
