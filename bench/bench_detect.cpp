// Benchmark of detection against CGAL in one process: sheets of growing resolution through the
// cow; untangle::find_intersections against CGAL's Polygon_mesh_processing routines.
//
// Usage: untangle_bench_detect [--quick] [--jitter] [--write DIR] [--files A.obj B.obj [N]]
//   --quick  only n = 81, 9 repeats (default: n in {41, 81, 121, 161, 201, 281}, 5 repeats)
//   --jitter  every sheet vertex moved by up to 0.1 cell sizes along each axis (fixed seed): a
//             sheet like real cloth, never flat to the last bit, where neither side's shortcuts
//             for axis planes apply (the flat sheets favour ours and cost CGAL exact arithmetic)
//   --write DIR  only write the cow and the jittered 141 x 141 sheet through it as DIR/cow.obj
//             and DIR/sheet.obj (the inputs of the whole-process comparison with
//             untangle_bench_cgal_check, docs/PERFORMANCE.md)
//   --files A.obj B.obj [N]  only our detection stage on these two OBJ files (A movable, B an
//             obstacle), one thread, N runs (default 15): best and median, and how many of each
//             mesh's triangles lie in flat patches (the self pairs detection skips)
// Exit status: 0 success; 1 the cow is not installed (libcgal-demo); 2 pair counts disagree (or
// the contours with and without the separation floods).
//
// What is compared (DESIGN §9: targets are ratios against CGAL on the same meshes):
// - pairs: our detection stage (DetectTimings::detect_ms: welding/topology, broad and narrow
//   phase, all pairs within and between meshes) against CGAL's face-face pair routines on the
//   same pairs: PMP::self_intersections on each mesh plus PMP::internal::
//   compute_face_face_intersection between sheet and cow ("CGAL pairs"); the mutual part alone
//   ("CGAL face-face") is listed too;
// - curves: the whole of find_intersections (detection + contours + classification) against
//   PMP::surface_intersection (polylines of sheet ∩ cow, corefinement's intersection graph).
//   Between the meshes it is timed twice: with the separation floods of the contours' tracks and
//   the smaller side's area (the default; region analysis, DESIGN §4, which CGAL's routine does not
//   do) and without them (DetectOptions::separation off: detection, linking crossings into
//   contours and track types, what surface_intersection's polylines amount to).
// CGAL's input conversion to Surface_mesh (welding included) is done once, outside the timings;
// ours welds inside every timed call. Times are wall-clock (std::chrono::steady_clock), best and
// median over the repeats; ratios are CGAL median / our median (> 1: we are faster), and for the
// two headline comparisons (between the meshes, the sheet alone) also CGAL best / our best.
// Those two are timed in alternation, one run of ours then one of CGAL's per repeat, so that a
// change of machine load during the run falls on both sides alike.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "app/best_median.h"
#include "cgal_reference.h"
#include "detect/detect_crossings.h"
#include "detect/triangle_bvh.h"
#include "io/read_obj.h"
#include "topology/scene_topology.h"
#include "scenes/scenes.h"
#include "untangle/intersections.h"
#include "untangle/mesh.h"

namespace {

using untangle::app::Stat;
using untangle::app::stat_of;
using untangle::cgal_reference::TrianglePair;

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since)
      .count();
}

// Runs f() `repeats` times; returns the wall time of each run in ms.
template <class F>
std::vector<double> time_runs(int repeats, F&& f) {
  std::vector<double> ms;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    f();
    ms.push_back(elapsed_ms(start));
  }
  return ms;
}

struct OursRun {
  Stat total, detect, contours, prepared;  // prepared: total less welding/topology
  untangle::Intersections result;
};

// Timings of repeated calls of find_intersections, one call at a time.
struct OursSamples {
  std::vector<double> total, detect, contours, prepared;
  untangle::Intersections result;

  void run_once(const std::vector<untangle::Mesh>& meshes, int threads, bool self,
                bool separation = true) {
    untangle::DetectOptions options;
    options.threads = threads;
    options.self_intersections = self;
    options.separation = separation;
    untangle::DetectTimings timings;
    const auto start = std::chrono::steady_clock::now();
    result = untangle::find_intersections(meshes, options, &timings);
    total.push_back(elapsed_ms(start));
    prepared.push_back(total.back() - timings.topology_ms);
    detect.push_back(timings.detect_ms);
    contours.push_back(timings.contours_ms);
  }
  OursRun stats() const {
    return {stat_of(total), stat_of(detect), stat_of(contours), stat_of(prepared), result};
  }
};

OursRun run_ours(const std::vector<untangle::Mesh>& meshes, int threads, int repeats,
                 bool self = true) {
  OursSamples samples;
  for (int r = 0; r < repeats; ++r) samples.run_once(meshes, threads, self);
  return samples.stats();
}

struct Row {
  int n = 0;
  std::size_t vertices = 0, triangles = 0;
  std::size_t pairs_ours = 0, pairs_cgal = 0, pairs_face_face = 0;
  std::size_t only_ours = 0, only_cgal = 0;
  std::size_t crossings = 0, contours = 0, polylines = 0, polyline_points = 0;
  OursRun all, one;  // threads = 0 (all cores) and threads = 1
  OursRun between;   // threads = 0, pairs of different meshes only (the job of surface_intersection)
  OursRun between_curves;  // the same without the separation floods (DetectOptions::separation)
  std::size_t pairs_between = 0;
  Stat cgal_pairs, cgal_face_face, cgal_surface;
  OursRun sheet_self;  // the sheet alone, against itself (`check` on the sheet)
  Stat cgal_sheet_self;  // PMP::self_intersections on the sheet's prepared Surface_mesh
  std::size_t sheet_self_pairs = 0, cgal_sheet_self_pairs = 0;
  double convert_ms = 0.0;
};

// Whether two results have the same pairs, contours (crossings in walk order) and track types.
bool same_curves(const untangle::Intersections& a, const untangle::Intersections& b) {
  if (a.triangle_pairs != b.triangle_pairs || a.contours.size() != b.contours.size()) return false;
  for (std::size_t i = 0; i < a.contours.size(); ++i) {
    const untangle::Contour &c = a.contours[i], &d = b.contours[i];
    if (c.crossings != d.crossings || c.tracks[0].type != d.tracks[0].type ||
        c.tracks[1].type != d.tracks[1].type)
      return false;
  }
  return true;
}

// Moves every vertex of the sheet (a grid, positions[0] and [1] neighbours) by up to 0.1 of its cell size along each axis,
// the same way for every run (a fixed seed).
void jitter_sheet(untangle::Mesh& sheet) {
  const untangle::Vec3 &a = sheet.positions[0], &b = sheet.positions[1];
  double cell = 0.0;
  for (int k = 0; k < 3; ++k) cell = std::max(cell, std::abs(b[k] - a[k]));
  std::mt19937 rng(24);
  std::uniform_real_distribution<double> offset(-0.1 * cell, 0.1 * cell);
  for (untangle::Vec3& p : sheet.positions)
    for (double& c : p) c += offset(rng);
}

double ratio(const Stat& cgal, const Stat& ours) {
  return ours.median > 0.0 ? cgal.median / ours.median : 0.0;
}

double ratio_best(const Stat& cgal, const Stat& ours) {
  return ours.best > 0.0 ? cgal.best / ours.best : 0.0;
}

std::string best_median(const Stat& s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%9.2f /%9.2f", s.best, s.median);
  return buf;
}

// --files: detection alone (topology built once, outside the timing), one thread.
int time_files(const std::vector<std::string>& files, int runs) {
  std::vector<untangle::Mesh> meshes;
  try {
    meshes.push_back(untangle::read_obj(files[0], untangle::Role::kMovable));
    meshes.push_back(untangle::read_obj(files[1], untangle::Role::kObstacle));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  const untangle::SceneTopology topo = untangle::build_topology(meshes);
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    std::vector<bool> include(meshes.size(), false);
    include[m] = true;
    untangle::TriangleBvh tree(topo, include);
    tree.mark_flat_patches(topo);
    std::printf("%s: %zu triangles, %zu in %zu flat patches\n", files[m].c_str(), tree.size(),
                tree.flat_patch_triangles(), tree.flat_patch_count());
  }
  untangle::DetectSettings settings;
  settings.threads = 1;
  std::vector<double> ms;
  std::size_t crossings = 0;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    crossings = untangle::detect_crossings(topo, settings).items.size();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::printf("detect_crossings, one thread: %zu crossings, best / median of %d: %s ms\n", crossings,
              runs, best_median(stat_of(ms)).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, jitter = false;
  std::string write_dir;
  int profile_runs = 0;  // --profile N [between|self]: only ours at n = 81, N times
  std::vector<std::string> files;  // --files A B [N]
  int file_runs = 15;
  std::string profile_part;  // empty: both
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--jitter") == 0) {
      jitter = true;
    } else if (std::strcmp(argv[i], "--write") == 0 && i + 1 < argc) {
      write_dir = argv[++i];
    } else if (std::strcmp(argv[i], "--profile") == 0 && i + 1 < argc) {
      profile_runs = std::max(1, std::atoi(argv[++i]));
      if (i + 1 < argc && argv[i + 1][0] != '-') profile_part = argv[++i];
    } else if (std::strcmp(argv[i], "--files") == 0 && i + 2 < argc) {
      files = {argv[i + 1], argv[i + 2]};
      i += 2;
      if (i + 1 < argc && argv[i + 1][0] != '-') file_runs = std::max(1, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "-h") == 0 || std::strcmp(argv[i], "--help") == 0) {
      std::printf("usage: %s [--quick] [--jitter] [--write DIR] [--profile N [between|self]]\n"
                  "       %s --files A.obj B.obj [N]\n"
                  "  --quick  only n = 81 with 9 repeats\n"
                  "  --jitter  sheets jittered by up to 0.1 cell sizes (fixed seed)\n"
                  "  --write DIR  only write DIR/cow.obj and DIR/sheet.obj (jittered, n = 141)\n"
                  "  --profile N  only ours at n = 81, N times: between the meshes, then the sheet "
                  "alone (for a profiler)\n"
                  "  --files A B [N]  only our detection on A (movable) and B (obstacle), one "
                  "thread, N runs (default 15), and the triangles in flat patches\n",
                  argv[0], argv[0]);
      return 0;
    } else {
      std::fprintf(stderr, "error: unknown argument '%s' (usage: %s [--quick])\n", argv[i],
                   argv[0]);
      return 2;
    }
  }
  if (!files.empty()) return time_files(files, file_runs);
  const std::string cow = untangle::scenes::cow_path();
  if (cow.empty() || !std::filesystem::is_regular_file(cow)) {
    std::fprintf(stderr,
                 "error: cow.off not found%s%s: this benchmark needs Debian's libcgal-demo "
                 "(/usr/share/doc/libcgal-demo/data.tar.gz); install it "
                 "(apt-get install libcgal-demo) and re-run cmake\n",
                 cow.empty() ? "" : " at ", cow.c_str());
    return 1;
  }
  if (!write_dir.empty()) {
    untangle::scenes::Scene scene = untangle::scenes::sheet_through_cow(141);
    jitter_sheet(scene.movable.at(0));
    std::filesystem::create_directories(write_dir);
    const untangle::scenes::SceneFiles files = untangle::scenes::write_scene_files(scene, write_dir);
    std::filesystem::rename(files.movable.at(0), std::filesystem::path(write_dir) / "sheet.obj");
    std::filesystem::rename(files.obstacles.at(0), std::filesystem::path(write_dir) / "cow.obj");
    std::printf("wrote %s/sheet.obj and %s/cow.obj\n", write_dir.c_str(), write_dir.c_str());
    return 0;
  }
  if (profile_runs > 0) {
    untangle::scenes::Scene scene = untangle::scenes::sheet_through_cow(81);
    if (jitter) jitter_sheet(scene.movable.at(0));
    const std::vector<untangle::Mesh> meshes = untangle::scenes::scene_meshes(scene);
    if (profile_part != "self") {
      const OursRun run = run_ours(meshes, 0, profile_runs, false);
      std::printf("ours between, n = 81: total %s, prepared %s ms (best / median of %d)\n",
                  best_median(run.total).c_str(), best_median(run.prepared).c_str(), profile_runs);
    }
    if (profile_part != "between") {
      const OursRun self = run_ours({meshes[0]}, 0, profile_runs);
      std::printf("ours sheet self, n = 81: total %s, prepared %s ms (best / median of %d)\n",
                  best_median(self.total).c_str(), best_median(self.prepared).c_str(), profile_runs);
    }
    return 0;
  }
  const std::vector<int> sizes = quick ? std::vector<int>{81}
                                       : std::vector<int>{41, 81, 121, 161, 201, 281};
  const int repeats = quick ? 9 : 5;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());

  std::vector<Row> rows;
  bool mismatch = false;
  for (int n : sizes) {
    std::fprintf(stderr, "n = %d ...\n", n);
    untangle::scenes::Scene scene = untangle::scenes::sheet_through_cow(n);
    if (jitter) jitter_sheet(scene.movable.at(0));
    std::vector<untangle::Mesh> meshes = scene.movable;
    meshes.insert(meshes.end(), scene.obstacles.begin(), scene.obstacles.end());
    if (meshes.size() != 2) {
      std::fprintf(stderr, "error: sheet_through_cow(%d) has %zu meshes, expected 2\n", n,
                   meshes.size());
      return 1;
    }
    Row row;
    row.n = n;
    for (const untangle::Mesh& m : meshes) {
      row.vertices += m.positions.size();
      row.triangles += m.triangles.size();
    }

    auto start = std::chrono::steady_clock::now();
    const std::vector<untangle::cgal_reference::ReferenceMesh> ref =
        untangle::cgal_reference::to_reference_meshes(meshes);
    row.convert_ms = elapsed_ms(start);
    for (std::size_t i = 0; i < ref.size(); ++i) {
      if (!ref[i].degenerate.empty()) {
        std::printf("note: n=%d mesh %zu: %zu degenerate triangles left out of CGAL's pairs\n", n,
                    i, ref[i].degenerate.size());
      }
    }

    row.all = run_ours(meshes, 0, repeats);
    row.one = run_ours(meshes, 1, repeats);
    // The headline comparisons, in alternation (see the top of this file).
    OursSamples between, between_curves, sheet_self;
    std::vector<double> cgal_surface, cgal_sheet_self;
    const std::vector<untangle::Mesh> sheet{meshes[0]};
    for (int r = 0; r < repeats; ++r) {
      between.run_once(meshes, 0, false);
      between_curves.run_once(meshes, 0, false, false);
      cgal_surface.push_back(time_runs(1, [&] {
        row.polylines = untangle::cgal_reference::surface_intersection_polylines(
            ref[0], ref[1], &row.polyline_points);
      })[0]);
      sheet_self.run_once(sheet, 0, true);
      cgal_sheet_self.push_back(time_runs(1, [&] {
        std::vector<TrianglePair> pairs;
        untangle::cgal_reference::append_self_pairs(ref[0], 0, pairs);
        row.cgal_sheet_self_pairs = pairs.size();
      })[0]);
    }
    row.between = between.stats();
    row.between_curves = between_curves.stats();
    row.cgal_surface = stat_of(cgal_surface);
    row.pairs_between = row.between.result.triangle_pairs.size();
    row.sheet_self = sheet_self.stats();
    row.cgal_sheet_self = stat_of(cgal_sheet_self);
    row.sheet_self_pairs = row.sheet_self.result.triangle_pairs.size();
    if (row.sheet_self_pairs != row.cgal_sheet_self_pairs) {
      mismatch = true;
      std::printf("!!!!!!!! MISMATCH n=%d: sheet self pairs ours %zu, CGAL %zu !!!!!!!!\n", n,
                  row.sheet_self_pairs, row.cgal_sheet_self_pairs);
    }

    std::vector<TrianglePair> cgal_pairs;
    row.cgal_pairs = stat_of(time_runs(
        repeats, [&] { cgal_pairs = untangle::cgal_reference::triangle_pairs(ref); }));
    row.cgal_face_face = stat_of(time_runs(repeats, [&] {
      row.pairs_face_face = untangle::cgal_reference::face_face_intersection(ref[0], ref[1]).size();
    }));

    const std::vector<TrianglePair>& ours = row.all.result.triangle_pairs;
    row.pairs_ours = ours.size();
    row.pairs_cgal = cgal_pairs.size();
    row.crossings = row.all.result.crossings.size();
    row.contours = row.all.result.contours.size();
    std::vector<TrianglePair> diff;
    std::set_difference(ours.begin(), ours.end(), cgal_pairs.begin(), cgal_pairs.end(),
                        std::back_inserter(diff));
    row.only_ours = diff.size();
    diff.clear();
    std::set_difference(cgal_pairs.begin(), cgal_pairs.end(), ours.begin(), ours.end(),
                        std::back_inserter(diff));
    row.only_cgal = diff.size();
    if (!same_curves(row.between.result, row.between_curves.result)) {
      mismatch = true;
      std::printf("!!!!!!!! MISMATCH n=%d: contours differ without the floods !!!!!!!!\n", n);
    }
    if (row.pairs_between != row.pairs_face_face) {
      mismatch = true;
      std::printf("!!!!!!!! MISMATCH n=%d: pairs between meshes ours %zu, CGAL face-face %zu !!!!!!!!\n",
                  n, row.pairs_between, row.pairs_face_face);
    }
    if (ours != cgal_pairs || row.one.result.triangle_pairs != ours) {
      mismatch = true;
      std::printf("!!!!!!!! MISMATCH n=%d: pairs ours %zu (1 thread: %zu), CGAL %zu; only ours "
                  "%zu, only CGAL %zu !!!!!!!!\n",
                  n, ours.size(), row.one.result.triangle_pairs.size(), cgal_pairs.size(),
                  row.only_ours, row.only_cgal);
    }
    rows.push_back(std::move(row));
  }

  std::printf("\nuntangle detection vs CGAL %s, sheet through cow; %d repeats; %u cores "
              "(\"all\" = DetectOptions::threads 0, \"1t\" = threads 1)\n",
              CGAL_VERSION_STR, repeats, cores);
  std::printf("times in ms as best / median; speed-up = CGAL median / our median\n\n");

  std::printf("%5s %8s %8s %10s %10s %7s %10s %9s %9s %10s %10s\n", "n", "vertices",
              "triangles", "pairs ours", "pairs CGAL", "agree", "face-face", "crossings",
              "contours", "polylines", "CGAL conv");
  for (const Row& r : rows) {
    std::printf("%5d %8zu %8zu %10zu %10zu %7s %10zu %9zu %9zu %10zu %10.2f\n", r.n, r.vertices,
                r.triangles, r.pairs_ours, r.pairs_cgal,
                r.pairs_ours == r.pairs_cgal && r.only_ours == 0 && r.only_cgal == 0 ? "yes"
                                                                                    : "NO!",
                r.pairs_face_face, r.crossings, r.contours, r.polylines, r.convert_ms);
  }

  std::printf("\npairs: our detection stage vs CGAL self_intersections + "
              "compute_face_face_intersection\n");
  std::printf("%5s %21s %21s %21s %21s %9s %9s\n", "n", "ours detect (all)", "ours detect (1t)",
              "CGAL pairs", "CGAL face-face only", "x (all)", "x (1t)");
  for (const Row& r : rows) {
    std::printf("%5d %21s %21s %21s %21s %9.2f %9.2f\n", r.n, best_median(r.all.detect).c_str(),
                best_median(r.one.detect).c_str(), best_median(r.cgal_pairs).c_str(),
                best_median(r.cgal_face_face).c_str(), ratio(r.cgal_pairs, r.all.detect),
                ratio(r.cgal_pairs, r.one.detect));
  }

  std::printf("\nbetween the two meshes only (no self-intersections), the job of CGAL's "
              "face-face routine and surface_intersection:\n");
  std::printf(
      "  like for like: CGAL is timed on its prepared Surface_mesh, ours on prepared\n"
      "  topology (welding and edges left out on both sides); 'ours all' adds our welding,\n"
      "  'CGAL all' adds CGAL's conversion. 'ours det+contours' includes the separation\n"
      "  floods and smaller-side areas of the tracks (region analysis, which CGAL does not\n"
      "  do); 'ours no floods' leaves them out (DetectOptions::separation off): detection,\n"
      "  contours and track types, what surface_intersection's polylines amount to.\n");
  std::printf("%5s %8s %21s %21s %21s %21s %21s %9s %9s %9s %9s %9s %9s\n", "n", "pairs",
              "ours det+contours", "ours no floods", "CGAL surface_inters.", "ours all", "CGAL all",
              "x prep", "x best", "x prep nf", "x best nf", "x all", "x strict");
  for (const Row& r : rows) {
    Stat cgal_all = r.cgal_surface;
    cgal_all.best += r.convert_ms;
    cgal_all.median += r.convert_ms;
    std::printf("%5d %8zu %21s %21s %21s %21s %21s %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f\n", r.n,
                r.pairs_between, best_median(r.between.prepared).c_str(),
                best_median(r.between_curves.prepared).c_str(), best_median(r.cgal_surface).c_str(),
                best_median(r.between.total).c_str(), best_median(cgal_all).c_str(),
                ratio(r.cgal_surface, r.between.prepared),
                ratio_best(r.cgal_surface, r.between.prepared),
                ratio(r.cgal_surface, r.between_curves.prepared),
                ratio_best(r.cgal_surface, r.between_curves.prepared),
                ratio(cgal_all, r.between.total), ratio(r.cgal_surface, r.between.total));
  }
  std::printf(
      "  x prep = CGAL surface_intersection / ours without welding (medians); x best = the\n"
      "  same with the best runs; x prep nf, x best nf = the same for ours without the\n"
      "  separation floods; x all = both with input preparation; x strict = CGAL without,\n"
      "  ours with (the last two with the floods).\n");

  std::printf("\ncurves: find_intersections (detection + contours) vs CGAL surface_intersection\n");
  std::printf("%5s %21s %21s %21s %21s %9s %9s\n", "n", "ours total (all)", "ours total (1t)",
              "ours contours (all)", "CGAL surface_inters.", "x (all)", "x (1t)");
  for (const Row& r : rows) {
    std::printf("%5d %21s %21s %21s %21s %9.2f %9.2f\n", r.n, best_median(r.all.total).c_str(),
                best_median(r.one.total).c_str(), best_median(r.all.contours).c_str(),
                best_median(r.cgal_surface).c_str(), ratio(r.cgal_surface, r.all.total),
                ratio(r.cgal_surface, r.one.total));
  }

  std::printf("\nself-intersections of the sheet alone: ours (find_intersections on the sheet: "
              "detection and contours; prepared = less welding) vs CGAL self_intersections on its "
              "prepared Surface_mesh\n");
  std::printf("%5s %7s %21s %21s %21s %9s %9s %9s\n", "n", "pairs", "ours total", "ours prepared",
              "CGAL self_inters.", "x prep", "x best", "x all");
  for (const Row& r : rows) {
    std::printf("%5d %7zu %21s %21s %21s %9.2f %9.2f %9.2f\n", r.n, r.sheet_self_pairs,
                best_median(r.sheet_self.total).c_str(), best_median(r.sheet_self.prepared).c_str(),
                best_median(r.cgal_sheet_self).c_str(), ratio(r.cgal_sheet_self, r.sheet_self.prepared),
                ratio_best(r.cgal_sheet_self, r.sheet_self.prepared),
                ratio(r.cgal_sheet_self, r.sheet_self.total));
  }

  if (mismatch) {
    std::printf("\n!!!!!!!! MISMATCH: our triangle pairs differ from CGAL's (see above) !!!!!!!!\n");
    return 2;
  }
  return 0;
}
