// The untangle command line: parses (CLI11), calls the library, maps results to exit codes.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "untangle/error.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"
#include "untangle/mesh_info.h"
#include "untangle/read_meshes.h"
#include "untangle/report.h"
#include "untangle/roles_by_name.h"
#include "untangle/version.h"
#include "untangle/write_meshes.h"

#include "batch.h"
#include "bench.h"
#include "formats.h"
#include "output_plan.h"
#include "pipeline.h"
#include "process_memory.h"
#include "simulate.h"
#include "render.h"

namespace {

using untangle::ExitCode;
using untangle::app::CommonOptions;
using untangle::app::load_all;
using untangle::app::ms_since;
using untangle::app::PipelineRun;
using untangle::app::run_pipeline;

constexpr const char* kExitCodes =
    "Exit codes:\n"
    "  0  success: nothing intersects (check), or the command did its job (bench: it ran)\n"
    "  1  internal error (batch: a job crashed or reached its time limit)\n"
    "  2  usage error (bad command line)\n"
    "  3  unreadable input (missing, empty, unknown format, corrupt, no triangles,\n"
    "     NaN or infinite coordinates, face indices out of range; bench: a --data\n"
    "     folder without garment/body pairs)\n"
    "  4  output not written\n"
    "  5  intersections or vertices inside an obstacle found (check) or remaining in the written\n"
    "     output (fix)\n"
    "  6  fix: the written output is intersection-free, but a movable mesh's shape is beyond\n"
    "     --max-stretch, --max-flips or --max-move (status distorted; the output is written)\n"
    "  batch exits with its worst job's code: 0, then 6, 5, 4, 3, 2, 1 from best to worst\n";

// " (default X)" for a help text, X read from the options struct that holds the default: a default
// is written in one place only (FixOptions, DetectOptions, BenchOptions).
template <typename T>
std::string default_is(const T& value) {
  std::ostringstream text;
  text << value;
  return " (default " + text.str() + ")";
}

// CLI11's help, except that a flag with a negated name (one option, so that the last one given
// wins) is listed as separate flags, one line each, instead of "--a,--b{false}".
class HelpFormatter : public CLI::Formatter {
 public:
  // The help lines (name, description) of the option named `name`.
  void split(const std::string& name, std::vector<std::pair<std::string, std::string>> lines) {
    split_[name] = std::move(lines);
  }
  std::string make_option(const CLI::Option* opt, bool is_positional) const override {
    const auto it = split_.find(opt->get_name());
    if (is_positional || it == split_.end()) return CLI::Formatter::make_option(opt, is_positional);
    std::stringstream out;
    for (const auto& [name, description] : it->second)
      CLI::detail::format_help(out, name, description, get_column_width());
    return out.str();
  }

 private:
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> split_;
};

// Labels name the mesh inside its file only when the file holds several.
std::vector<std::string> labels_of(const std::vector<untangle::Mesh>& meshes) {
  std::vector<std::string> labels;
  for (const auto& m : meshes) {
    std::size_t same_file = 0;
    for (const auto& other : meshes) same_file += other.path == m.path ? 1 : 0;
    labels.push_back(untangle::mesh_label(m, same_file > 1));
  }
  return labels;
}

void emit_report(const std::string& target, const std::string& json) {
  if (target.empty()) return;
  if (target == "-") {
    std::fwrite(json.data(), 1, json.size(), stdout);
    std::fflush(stdout);
  } else {
    untangle::write_text_file_atomically(target, json);
  }
}

// Whether stdout carries a JSON report or a contour file, and so nothing else.
bool stdout_is_data(const CommonOptions& o) { return o.report == "-" || o.contours == "-"; }

int run_info(const CommonOptions& o) {
  untangle::app::check_written_files(o, {});
  const std::vector<untangle::Mesh> meshes = load_all(o);
  std::vector<untangle::MeshInfo> infos;
  for (const auto& m : meshes) infos.push_back(untangle::describe_mesh(m));
  const bool human = !o.quiet && o.report != "-";
  if (human) {
    const std::vector<std::string> labels = labels_of(meshes);
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      const auto& in = infos[i];
      std::printf("%s (%s)\n", labels[i].c_str(), untangle::to_string(meshes[i].role));
      std::printf("  vertices %zu, faces %zu, triangles %zu, welded vertices %zu\n", in.vertices,
                  in.faces, in.triangles, in.welded_vertices);
      std::printf("  components %zu, boundary loops %zu, non-manifold edges %zu, %s\n",
                  in.components, in.boundary_loops, in.non_manifold_edges,
                  in.closed ? "closed" : "open");
      std::printf("  zero-area triangles %zu, degenerate triangles %zu\n", in.zero_area_triangles,
                  in.degenerate_triangles);
      // What --obstacle-name and --movable-name can match.
      const std::vector<std::string> names = untangle::all_names({meshes[i]});
      if (!names.empty()) {
        std::string text;
        for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
        std::printf("  %s %s\n",
                    meshes[i].group_names.empty() ? "names (mesh, node):" : "names (o and g):",
                    text.c_str());
      }
      if (o.verbose) {
        std::printf("  boundary edges %zu, area %.6g, mean edge length %.6g\n", in.boundary_edges,
                    in.area, in.mean_edge_length);
      }
    }
  }
  emit_report(o.report, untangle::info_report_json(meshes, infos));
  return 0;
}

// The summary line of exact contacts (DESIGN §2), when there are any.
void print_contacts(const untangle::IntersectionCounts& c) {
  std::size_t seams = 0, repeated = 0, coplanar = 0;
  for (const untangle::MeshContact& m : c.contacts) {
    seams += m.seam_vertices;
    repeated += m.repeated_faces;
    coplanar += m.coplanar_pairs;
  }
  if (seams + repeated + coplanar == 0) return;
  std::printf("contacts (not crossings): %zu seam vertices, %zu repeated faces, %zu coplanar "
              "triangle pairs, between %zu pairs of meshes\n",
              seams, repeated, coplanar, c.contacts.size());
}

int run_check(const CommonOptions& o) {
  untangle::app::check_written_files(o, {});
  const auto start = std::chrono::steady_clock::now();
  const std::vector<untangle::Mesh> meshes =
      untangle::split_by_name(load_all(o), {}, untangle::app::name_patterns(o)).meshes;
  untangle::CheckTimingsMs timings;
  timings.load = ms_since(start);

  untangle::DetectOptions options;
  options.threads = o.threads;
  untangle::DetectTimings detect;
  std::vector<untangle::MeshInfo> infos;  // from detection's topology
  const untangle::Intersections found = untangle::find_intersections(meshes, options, &detect, &infos);
  timings.detect = detect.detect_ms;
  timings.contours = detect.contours_ms;

  emit_report(o.contours, untangle::contours_obj(found));
  timings.total = ms_since(start);

  const auto& c = found.counts;
  const bool clean = c.crossings == 0 && c.inside_vertices == 0;
  if (!o.quiet && !stdout_is_data(o)) {
    const std::vector<std::string> labels = labels_of(meshes);
    if (o.verbose) {
      for (std::size_t i = 0; i < meshes.size(); ++i) {
        std::printf("mesh %zu: %s (%s), %zu vertices, %zu faces, %zu boundary loops\n", i,
                    labels[i].c_str(), untangle::to_string(meshes[i].role), infos[i].vertices,
                    infos[i].faces, infos[i].boundary_loops);
      }
    }
    std::printf("crossings %zu, intersecting triangle pairs %zu, contours %zu (length %.6g)\n",
                c.crossings, c.triangle_pairs, c.contours, c.contour_length);
    if (c.inside_vertices > 0)
      std::printf("vertices inside obstacles %zu (winding number > 1/2)\n", c.inside_vertices);
    print_contacts(c);
    if (c.contours > 0) {
      std::printf("pairs: CL/CL %zu, BB/II %zu, BI/BI %zu, self %zu, other %zu; "
                  "loop vertices %zu, non-separating tracks %zu\n",
                  c.pairs_cl_cl, c.pairs_bb_ii, c.pairs_bi_bi, c.pairs_self, c.pairs_other,
                  c.loop_vertices, c.non_separating);
    }
    if (o.verbose) {
      for (std::size_t k = 0; k < found.contours.size(); ++k) {
        const auto& ct = found.contours[k];
        std::printf("  contour %zu: %s %s/%s %s, %zu crossings, length %.6g\n", k,
                    labels[ct.tracks[0].mesh].c_str(), untangle::to_string(ct.tracks[0].type),
                    untangle::to_string(ct.tracks[1].type), labels[ct.tracks[1].mesh].c_str(),
                    ct.crossings.size(), ct.length);
      }
    }
    std::printf("status: %s\n", clean ? "clean" : "intersecting");
  }
  emit_report(o.report, untangle::check_report_json(meshes, infos, found, timings));
  return clean ? 0 : static_cast<int>(ExitCode::kIntersecting);
}


int run_fix(CommonOptions o, const std::string& preview_dir) {
  // The picture is planned here and checked with the outputs by run_pipeline, before any work.
  const std::string preview = o.preview_png = untangle::app::plan_preview(preview_dir, o);
  const bool show = !o.quiet && !stdout_is_data(o);
  untangle::FixProgress progress;
  if (o.verbose && show) {
    progress = [](const untangle::IterationRecord& r) {
      std::fprintf(stderr, "iteration %d: %zu crossings, contour length %.6g, %.1f ms\n", r.iteration,
                   r.crossings, r.contour_length, r.elapsed_ms);
      return true;
    };
  }
  const PipelineRun run = run_pipeline(o, progress);
  untangle::app::write_preview(preview, run, o);
  const std::vector<std::string>& outputs = run.outputs;
  const untangle::FixResult& result = run.result;
  const untangle::Intersections& verified = run.verified;

  emit_report(o.contours, untangle::contours_obj(verified));
  const bool clean = verified.counts.crossings == 0 && verified.counts.inside_vertices == 0;
  const untangle::FixStatus status = untangle::judge_result(verified.counts, result.quality, o.bounds);
  if (show) {
    std::printf("before: %zu crossings, %zu contours, %zu inside; after %d iterations: %zu crossings, "
                "%zu contours, %zu inside\n",
                result.before.crossings, result.before.contours, result.before.inside_vertices,
                result.iterations, verified.counts.crossings, verified.counts.contours,
                verified.counts.inside_vertices);
    std::printf("moved %zu vertices, max %.6g (%.3g mean edge lengths), mean %.6g\n",
                result.displacement.moved_vertices, result.displacement.max,
                result.displacement.max_over_mean_edge, result.displacement.mean);
    for (const untangle::RetryRecord& r : result.retries) {
      std::printf("retried with clearance %.3g: %s, %zu crossings, %zu inside after %d iterations%s\n",
                  r.clearance, r.clean ? "clean" : "unresolved", r.crossings, r.inside_vertices,
                  r.iterations, r.kept ? " (kept)" : "");
    }
    const auto outcome = [](const untangle::ContinuationRecord& c) {
      return c.clean ? "clean" : c.gave_up ? "gave up" : "unresolved";
    };
    if (result.continuation.ran) {
      const untangle::ContinuationRecord& c = result.continuation;
      std::printf(
          "continuation (deepest inside vertex %.3g, %zu obstacle vertices shrunk by up to "
          "%.3g, %d steps): %s, %zu crossings, %zu inside, stretch %.3g%s\n",
          c.deepest, c.shrunk_vertices, c.largest_shrink, c.steps, outcome(c), c.crossings,
          c.inside_vertices, c.max_stretch, c.kept ? " (kept)" : " (not kept)");
    }
    for (const untangle::ContinuationRecord* scaled :
         {&result.scaled_continuation, &result.second_scaled_continuation}) {
      const untangle::ContinuationRecord& c = *scaled;
      if (!c.ran) continue;
      std::printf(
          "scaled continuation (obstacles scaled by %.3g about their centre, %s, %d steps): %s, "
          "%zu crossings, %zu inside, stretch %.3g%s\n",
          c.factor,
          c.chosen_by == untangle::ScaleChoice::kDepth ? "the least depth inside"
                                                       : "the fewest crossings",
          c.steps, outcome(c), c.crossings, c.inside_vertices, c.max_stretch,
          c.kept ? " (kept)" : " (not kept)");
    }
    if (result.piece_moves.ran) {
      const untangle::PieceMoveRecord& p = result.piece_moves;
      const std::vector<std::string> labels = labels_of(run.written);
      const char* repaired = p.moved == 0 ? "not run" : p.clean ? "clean" : "unresolved";
      const char* kept = p.moved == 0 ? "" : p.kept ? " (kept)" : " (not kept)";
      std::printf(
          "pieces moved whole: %zu of %zu tangled (longest move %.3g), then repaired: %s%s\n",
          p.moved, p.tangled, p.largest_move, repaired, kept);
      for (const untangle::PieceMove& move : p.pieces)
        std::printf("  %s piece at vertex %u moved by (%.6g, %.6g, %.6g)\n",
                    move.mesh < labels.size() ? labels[move.mesh].c_str() : "?", move.vertex + 1,
                    move.shift[0], move.shift[1], move.shift[2]);
    }
    if (result.layering.ran) {
      const untangle::LayeringRecord& l = result.layering;
      const std::vector<std::string> labels = labels_of(run.written);
      std::printf("layering (%zu layers, innermost first:", l.layers.size());
      for (std::size_t k = 0; k < l.layers.size(); ++k) {
        const untangle::LayerRecord& layer = l.layers[k];
        std::printf("%s %s piece %u", k == 0 ? "" : ",",
                    layer.mesh < labels.size() ? labels[layer.mesh].c_str() : "?", layer.component);
      }
      std::printf("): %s, %zu crossings, %zu inside, stretch %.3g%s\n",
                  l.clean ? "clean" : "unresolved", l.crossings, l.inside_vertices, l.max_stretch,
                  l.kept ? " (kept)" : " (not kept)");
      if (l.orders.size() > 1) {
        std::printf("layering orders tried:");
        for (std::size_t k = 0; k < l.orders.size(); ++k) {
          const untangle::LayeringOrderRecord& o = l.orders[k];
          std::printf("%s by %s: %s, %zu crossings, %zu inside, stretch %.3g%s", k == 0 ? "" : ";",
                      to_string(o.rule), o.clean ? "clean" : "unresolved", o.crossings,
                      o.inside_vertices, o.max_stretch, o.kept ? " (kept)" : "");
        }
        std::printf("\n");
      }
    }
    for (std::size_t k = 0; k < outputs.size(); ++k) std::printf("wrote %s\n", outputs[k].c_str());
    print_contacts(verified.counts);
    if (result.obstacle_crossing_pairs > 0) {
      std::printf("obstacles: %zu triangle pairs of closed obstacles cross (themselves or each "
                  "other), left as they are\n",
                  result.obstacle_crossing_pairs);
    }
    if (!clean) {
      const std::vector<std::string> labels = labels_of(run.written);
      for (std::size_t k = 0; k < verified.contours.size(); ++k) {
        const auto& ct = verified.contours[k];
        std::printf("  remaining contour %zu: %s %s/%s %s, %zu crossings\n", k,
                    labels[ct.tracks[0].mesh].c_str(), untangle::to_string(ct.tracks[0].type),
                    untangle::to_string(ct.tracks[1].type), labels[ct.tracks[1].mesh].c_str(),
                    ct.crossings.size());
      }
    }
    for (std::size_t m = 0; m < run.written.size() && m < result.quality.size(); ++m) {
      if (run.written[m].role != untangle::Role::kMovable) continue;
      const untangle::QualityStats& q = result.quality[m];
      std::printf("quality %s: edge change mean %.3g, p95 %.3g, max %.3g (stretch %.3g), %zu flipped "
                  "faces, max move %.3g diagonals%s\n",
                  run.written[m].path.c_str(), q.edge_change_mean, q.edge_change_p95,
                  q.edge_change_max, q.max_stretch, q.flipped_faces,
                  q.max_displacement_over_diagonal,
                  untangle::within_bounds(q, o.bounds) ? "" : " (beyond the bounds)");
    }
    if (result.reverted)
      std::printf("the repaired state, detected as check detects it, was worse than the input: "
                  "the input's positions were written\n");
    std::printf("status: %s%s\n", untangle::to_string(status),
                result.stalled && !clean ? " (stalled)" : "");
  }
  emit_report(o.report, untangle::fix_report_json(run.meshes, run.infos, outputs, run.options,
                                                   o.bounds, result, verified, run.timings));
  switch (status) {
    case untangle::FixStatus::kClean: return 0;
    case untangle::FixStatus::kDistorted: return static_cast<int>(ExitCode::kDistorted);
    case untangle::FixStatus::kUnresolved: break;
  }
  return static_cast<int>(ExitCode::kIntersecting);
}

void add_common(CLI::App& cmd, CommonOptions& o, bool with_check_options) {
  cmd.add_option("meshes", o.inputs, "Mesh files (every format assimp reads)")->required();
  cmd.add_option("--report", o.report, "Write a JSON report to FILE ('-' = stdout, which then carries nothing else)")
      ->option_text("FILE");
  cmd.add_flag("-q,--quiet", o.quiet, "Print nothing but errors");
  cmd.add_flag("-v,--verbose", o.verbose, "Print more detail");
  if (with_check_options) {
    cmd.add_option("--obstacle", o.obstacles, "A mesh that never moves (repeatable)")
        ->allow_extra_args(false)
        ->option_text("MESH");
    cmd.add_option("--obstacle-name", o.obstacle_names,
                   "Meshes, nodes, OBJ objects or groups of the movable inputs whose name matches "
                   "the glob PATTERN are obstacles (repeatable)")
        ->allow_extra_args(false)
        ->option_text("PATTERN");
    cmd.add_option("--movable-name", o.movable_names,
                   "Only meshes, nodes, OBJ objects or groups of the movable inputs whose name "
                   "matches the glob PATTERN move; the rest are obstacles (repeatable)")
        ->allow_extra_args(false)
        ->option_text("PATTERN");
    cmd.add_option("--contours", o.contours, "Write the contour polylines as OBJ to FILE ('-' = stdout, which then carries nothing else)")
        ->option_text("FILE");
    cmd.add_option("--threads", o.threads,
                   "Worker threads, 0 = all cores; the same result for every N" +
                       default_is(o.threads))
        ->check(CLI::NonNegativeNumber)
        ->option_text("N");
  }
}

// The options of `fix` (parsed into `o`; --preview into `preview`).
void add_fix_options(CLI::App& cmd, CommonOptions& o, std::string& preview) {
  add_common(cmd, o, true);
  cmd.add_option("-o,--output", o.outputs, "Output file, once per movable input, in order")
      ->allow_extra_args(false)
      ->option_text("OUT");
  cmd.add_option("--output-dir", o.output_dir, "Write each output under DIR with its input's file name")
      ->option_text("DIR");
  cmd.add_option("--pin", o.pin_files,
                 "File of vertex indices that must not move (0-based, file order; 'INPUT VERTEX' for other inputs)")
      ->allow_extra_args(false)
      ->option_text("FILE");
  cmd.add_option("--pin-group", o.pin_groups, "Pin every vertex of the named group or mesh (repeatable)")
      ->allow_extra_args(false)
      ->option_text("NAME");
  cmd.add_option("--method", o.method,
                 "region: move whole illegal regions; paper: Eq. 1 on crossing edges only" +
                     default_is(o.method))
      ->check(CLI::IsMember({"region", "paper"}))
      ->option_text("region|paper");
  cmd.add_option("--max-iterations", o.max_iterations,
                 "Iteration cap" + default_is(o.max_iterations))
      ->check(CLI::NonNegativeNumber)
      ->option_text("N");
  cmd.add_option("--clearance", o.clearance,
                 "Gap left between surfaces, in mean edge lengths of the moving mesh" +
                     default_is(o.clearance))
      ->check(CLI::NonNegativeNumber)
      ->option_text("X");
  // One option with a negated name, so that the last of the two given wins; listed as two flags.
  const char* const kInside = "A closed obstacle's inside decides the illegal side";
  const char* const kArea = "The paper's rule everywhere: the smaller region is illegal";
  CLI::Option* inside_rule =
      cmd.add_flag("--outside-closed-obstacles,!--orientation-free", o.outside_closed,
                   std::string(kInside) + "; --orientation-free: " + kArea);
  auto help = std::make_shared<HelpFormatter>();
  const std::string default_mark = " (default)";
  const bool inside_default = o.outside_closed;
  help->split(inside_rule->get_name(),
              {{"--outside-closed-obstacles", kInside + (inside_default ? default_mark : "")},
               {"--orientation-free", kArea + (inside_default ? "" : default_mark)}});
  cmd.formatter(help);
  cmd.add_flag_callback("--no-relax", [&o] { o.relax = false; },
               "Skip the shape relaxation after a clean repair (moved vertices and the rings around "
               "them relax toward the input's shape, every step kept clean)");
  cmd.add_option("--relax-sweeps", o.relax_sweeps,
                 "Sweeps of the shape relaxation at most (fewer: faster, the shape less relaxed)" +
                     default_is(o.relax_sweeps))
      ->check(CLI::Range(0, 1000))
      ->option_text("N");
  cmd.add_option("--retries", o.retries,
                 "Retries of an unresolved run, from the input, each with the clearance doubled; "
                 "the first clean one is kept" + default_is(o.retries))
      ->check(CLI::Range(0, 8))
      ->option_text("N");
  cmd.add_flag_callback(
      "--no-continuation", [&o] { o.continuation = false; },
      "Skip the continuation: where a run is left unresolved, or stretched or "
      "flipped beyond the bounds, with vertices inside a closed obstacle, fix "
      "runs once more with the obstacles shrunk inward, then grown back in "
      "steps, repaired and relaxed after each, and where that is not within the "
      "bounds and one mesh moves, once more with the obstacles scaled down about "
      "their centre to where the mesh lies least deep inside them, and where that is "
      "not within the bounds either, to where it crosses them least (each "
      "adds seconds where it runs; up to 32 repairs, giving up after four in a "
      "row end unresolved)");
  cmd.add_flag("--continuation", o.continuation,
               "The continuation where a run calls for it (the default; --no-continuation "
               "turns it off)");
  cmd.add_flag_callback("--no-layering", [&o] { o.layering = false; },
                        "Do not lay garments worn together one at a time when the run is left "
                        "unresolved or beyond the bounds (each alone on the obstacles, then each "
                        "over the ones nearer them, those grown back from the obstacles' surface "
                        "in steps)");
  cmd.add_flag_callback(
      "--no-piece-moves", [&o] { o.piece_moves = false; },
      "Do not move small interlocked pieces whole when the run is left unresolved (pieces of at "
      "most 2048 triangles tangled only with things as small, each by the shortest translation "
      "found that clears it, then the repair once more)");
  cmd.add_option("--max-stretch", o.bounds.max_stretch,
                 "Quality bound: no edge of a movable mesh longer or shorter than X times its input "
                 "length" + default_is(o.bounds.max_stretch))
      ->check(CLI::Range(1.0, 1e300))
      ->option_text("X");
  cmd.add_option("--max-flips", o.bounds.max_flips,
                 "Quality bound: faces per movable mesh whose normal may turn over" +
                     default_is(o.bounds.max_flips))
      ->option_text("N");
  cmd.add_option("--max-move", o.bounds.max_move,
                 "Quality bound: largest vertex move, in its mesh's bounding-box diagonals" +
                     default_is(o.bounds.max_move))
      ->check(CLI::NonNegativeNumber)
      ->option_text("X");
  cmd.add_flag("--overwrite", o.overwrite, "Replace existing files it writes: outputs, their side files, report, contours (never an input)");
  cmd.add_flag("--allow-loss", o.allow_loss,
               "Write an output that cannot keep all of its input (animations, skins, textures: "
               "refused otherwise, naming what would be lost)");
  untangle::app::add_preview_option(cmd, preview, o);
}

}  // namespace

int main(int argc, char** argv) {
  untangle::app::prefer_huge_pages();
  CLI::App app{"untangle: find and repair intersecting triangle meshes (garments, bodies, cloth)",
               "untangle"};
  app.footer(kExitCodes);
  // A callback: the assimp line loads the assimp module, which only --version should pay for.
  app.set_version_flag("--version", std::function<std::string()>(untangle::version_text),
                       "Print the versions of untangle, CGAL, assimp and Eigen");
  app.require_subcommand(1);

  // Only the subcommands named on the command line get their options. CLI11 builds strings,
  // validators and std::functions for every option: those of all eight commands cost every
  // process about half a millisecond of CPU (issue 24). CLI11 takes a subcommand only by its
  // exact name among the arguments, so one not named is never parsed, and the help of
  // `untangle` lists the subcommands by name and description alone.
  const auto named = [argc, argv](const char* name) {
    for (int i = 1; i < argc; ++i)
      if (std::strcmp(argv[i], name) == 0) return true;
    return false;
  };
  CommonOptions info_options, check_options;
  check_options.threads = untangle::DetectOptions{}.threads;
  CLI::App* info = app.add_subcommand("info", "Describe each mesh: counts, boundary loops, closedness");
  if (named("info")) {
    add_common(*info, info_options, false);
    info->add_flag("--overwrite", info_options.overwrite, "Replace an existing report file (never an input)");
  }
  info->footer(kExitCodes);
  CLI::App* check = app.add_subcommand(
      "check", "Find every crossing between and within meshes; build and classify contours");
  if (named("check")) {
    add_common(*check, check_options, true);
    check->add_flag("--overwrite", check_options.overwrite,
                    "Replace an existing report or contour file (never an input)");
  }
  check->footer(kExitCodes);
  CommonOptions fix_options;
  std::string fix_preview;
  CLI::App* fix = app.add_subcommand(
      "fix", "Move vertices of the movable meshes until nothing intersects; write the result");
  if (named("fix")) add_fix_options(*fix, fix_options, fix_preview);
  fix->footer(kExitCodes);
  CLI::App* formats = app.add_subcommand("formats", "List the file formats untangle reads and writes");
  formats->footer(kExitCodes);
  untangle::app::BenchOptions bench_options;
  CLI::App* bench = app.add_subcommand(
      "bench", "Time the repair on built-in generated scenes (and garment/body pairs with --data)");
  if (named("bench")) {
    bench->add_option("--repeat", bench_options.repeat,
                      "Runs per scene and method; best and median are reported" +
                          default_is(bench_options.repeat))
        ->check(CLI::PositiveNumber)
        ->option_text("N");
    bench->add_option("--method", bench_options.method,
                      "Method(s) to time: region, paper or both" + default_is(bench_options.method))
        ->check(CLI::IsMember({"region", "paper", "both"}))
        ->option_text("region|paper|both");
    bench->add_option("--plot", bench_options.plot_dir,
                      "Write DIR/<scene>.csv and DIR/<scene>.svg: crossings and contour length per iteration against elapsed ms")
        ->option_text("DIR");
    bench->add_option("--data", bench_options.data_dir,
                      "Also every garment DIR/garments/<prefix>_*.obj against DIR/bodies/<prefix>_generic.obj (as shipped and scaled 1.02), and every two garments for one body worn together")
        ->option_text("DIR");
    bench->add_flag("--json", bench_options.json, "Print the tables and histories as JSON on stdout instead");
    bench->add_flag("--quick", bench_options.quick, "The small suite: four small scenes, accuracy on one");
    bench->add_option("--threads", bench_options.threads,
                      "Worker threads, 0 = all cores; the same result for every N" +
                          default_is(bench_options.threads))
        ->check(CLI::NonNegativeNumber)
        ->option_text("N");
  }
  bench->footer(kExitCodes);
  untangle::app::SimulateOptions simulate_options;
  CLI::Option* frames_option = nullptr;
  CLI::App* simulate = app.add_subcommand(
      "simulate", "Drop cloth on an example obstacle, corrected by the repair after every step");
  if (named("simulate")) {
    simulate->add_option("scene", simulate_options.scene_file,
                         "Scene file (JSON: meshes, roles, pins, schedules, cloth parameters)");
    simulate->add_option("--example", simulate_options.example,
                         "A built-in scene instead of a scene file: ball, box, spikes, cow or fitting "
                         "(its scene file is written as DIR/scene.json)")
        ->check(CLI::IsMember({"ball", "box", "spikes", "cow", "fitting"}))
        ->option_text("ball|box|spikes|cow|fitting");
    simulate->add_option("--output-dir", simulate_options.output_dir,
                         "Write DIR/<mesh>.obj (the start) and DIR/<mesh>_<frame>.obj per saved frame")
        ->required()
        ->option_text("DIR");
    frames_option = simulate->add_option("--frames", simulate_options.frames,
                         "Frames to simulate; a scene file's `frames` otherwise" + default_is(simulate_options.frames))
        ->check(CLI::PositiveNumber)
        ->option_text("N");
    simulate->add_option("--save-every", simulate_options.save_every,
                         "Write every K-th frame (and the last)" + default_is(simulate_options.save_every))
        ->check(CLI::PositiveNumber)
        ->option_text("K");
    simulate->add_option("--report", simulate_options.report,
                         "Write a JSON report to FILE ('-' = stdout, which then carries nothing else)")
        ->option_text("FILE");
    simulate->add_option("--threads", simulate_options.threads,
                         "Worker threads, 0 = all cores; the same result for every N" +
                             default_is(simulate_options.threads))
        ->check(CLI::NonNegativeNumber)
        ->option_text("N");
    simulate->add_option("--preview", simulate_options.preview,
                         "Write DIR/frame_<frame>.png per saved frame and DIR/contact_sheet.png")
        ->option_text("DIR");
    simulate->add_flag("--overwrite", simulate_options.overwrite,
                       "Replace frame files and the report left by an earlier run");
    simulate->add_flag("-q,--quiet", simulate_options.quiet, "Print nothing but errors");
  }
  simulate->footer(kExitCodes);
  untangle::app::RenderCliOptions render_options;
  CLI::App* render =
      untangle::app::add_render_command(app, render_options, kExitCodes, named("render"));
  untangle::app::BatchOptions batch_options;
  CLI::App* batch =
      untangle::app::add_batch_command(app, batch_options, kExitCodes, named("batch"));

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "error: %s (run 'untangle --help' for usage)\n", e.what());
    return static_cast<int>(ExitCode::kUsage);
  }

  try {
    if (info->parsed()) return run_info(info_options);
    if (check->parsed()) return run_check(check_options);
    if (fix->parsed()) return run_fix(fix_options, fix_preview);
    if (bench->parsed()) return untangle::app::run_bench(bench_options);
    if (simulate->parsed()) {
      simulate_options.frames_given = frames_option->count() > 0;
      return untangle::app::run_simulate(simulate_options);
    }
    if (render->parsed()) return untangle::app::run_render(render_options);
    if (batch->parsed()) return untangle::app::run_batch(batch_options);
    if (formats->parsed()) return untangle::app::run_formats();
  } catch (const untangle::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return static_cast<int>(e.code());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory\n");
    return static_cast<int>(ExitCode::kInternal);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: internal: %s\n", e.what());
    return static_cast<int>(ExitCode::kInternal);
  }
  return static_cast<int>(ExitCode::kUsage);
}
