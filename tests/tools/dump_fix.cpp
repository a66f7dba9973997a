// untangle_dump_fix [--random N] [--threads N] [--continuation 0|1]: runs fix_meshes on every
// generated scene (named scenes, the Wicke configurations plain, subdivided and permuted, the
// larger self-intersections, layers, the cow scenes, random tangles 0..N-1) and prints one line per
// scene: status, iterations, crossings before and after, moved vertices, and a 64-bit FNV-1a hash
// of every resulting position written as %a; on stderr, the scene's name and its wall milliseconds.
// `--continuation 1` or `0` sets FixOptions::continuation (else its default). Two builds whose
// dumps are equal gave bit-identical results: the check that a refactoring changed no behaviour
// (docs/CONTRIBUTING.md).
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "scenes/random_tangles.h"
#include "scenes/scenes.h"
#include "scenes/self_scenes.h"
#include "untangle/fix.h"

namespace {

using untangle::Mesh;

std::uint64_t hash_positions(const std::vector<Mesh>& meshes) {
  std::uint64_t h = 1469598103934665603ull;
  char buffer[128];
  for (const Mesh& m : meshes)
    for (const untangle::Vec3& p : m.positions) {
      const int n = std::snprintf(buffer, sizeof buffer, "%a %a %a\n", p[0], p[1], p[2]);
      for (int i = 0; i < n; ++i) {
        h ^= static_cast<unsigned char>(buffer[i]);
        h *= 1099511628211ull;
      }
    }
  return h;
}

int continuation = -1;  // --continuation: -1 the default

void dump(const std::string& name, std::vector<Mesh> meshes, int threads) {
  untangle::FixOptions options;
  options.threads = threads;
  if (continuation >= 0) options.continuation = continuation != 0;
  const auto start = std::chrono::steady_clock::now();
  const untangle::FixResult r = untangle::fix_meshes(meshes, options);
  int last_stage = r.history.empty() ? 1 : r.history.back().stage;
  std::printf("%s %s it=%d stage=%d before=%zu after=%zu moved=%zu max=%a hash=%016llx\n",
              name.c_str(), r.clean ? "clean" : (r.stalled ? "stalled" : "unresolved"),
              r.iterations, last_stage, r.before.crossings, r.after.crossings,
              r.displacement.moved_vertices, r.displacement.max,
              static_cast<unsigned long long>(hash_positions(meshes)));
  std::fflush(stdout);
  std::fprintf(
      stderr, "%s %.0f ms\n", name.c_str(),
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

std::vector<Mesh> one(Mesh m) { return {std::move(m)}; }

}  // namespace

int main(int argc, char** argv) {
  namespace s = untangle::scenes;
  int random = 1500, threads = 2;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--random") random = std::atoi(argv[i + 1]);
    else if (flag == "--threads") threads = std::atoi(argv[i + 1]);
    else if (flag == "--continuation")
      continuation = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr,
                   "usage: untangle_dump_fix [--random N] [--threads N] [--continuation 0|1]\n");
      return 2;
    }
  }
  for (const s::Scene& scene : s::named_scenes()) dump(scene.name, s::scene_meshes(scene), threads);
  for (s::WickeCase c : s::all_wicke_cases()) {
    for (int levels : {0, 2, 4})
      dump(std::string("wicke_") + s::to_string(c) + "_" + std::to_string(levels),
           one(s::subdivide_midpoint(s::wicke_scene(c), levels)), threads);
    dump(std::string("wicke_") + s::to_string(c) + "_permuted",
         one(s::permuted(s::wicke_scene(c), 0x5eed0004u)), threads);
  }
  dump("folded_through_itself", one(s::folded_through_itself(41, 25)), threads);
  dump("spiral_roll", one(s::spiral_roll(97, 17)), threads);
  dump("pinched_tube", one(s::pinched_tube(48, 31)), threads);
  dump("three_layers", s::scene_meshes(s::three_layers(48, 25)), threads);
  dump("interleaved_layers", s::scene_meshes(s::interleaved_layers(48, 25)), threads);
  dump("turned_down_collar_32", s::scene_meshes(s::turned_down_collar(32, 17)), threads);
  dump("turned_down_collar_64", s::scene_meshes(s::turned_down_collar(64, 33)), threads);
  {
    Mesh sheet = s::grid_sheet(33, 33, {-1.6137, -1.5929, 0.3637}, {3.2, 0, 0}, {0, 3.2, 0}, "sheet");
    Mesh obstacle = s::self_intersecting_obstacle(24);
    obstacle.role = untangle::Role::kObstacle;
    dump("sheet_on_self_intersecting_obstacle", {sheet, obstacle}, threads);
  }
  for (double side : {1.8, 2.4}) dump("panel_in_body_" + std::to_string(side),
                                      s::scene_meshes(s::panel_in_body(side)), threads);
  dump("sheet_through_capsule_41", s::scene_meshes(s::sheet_through_capsule(41)), threads);
  if (!s::cow_path().empty()) {
    dump("sheet_through_cow_40", s::scene_meshes(s::sheet_through_cow(40)), threads);
    for (double y : {0.1853, 0.1953, 0.2053, 0.2103})
      dump("sheet_over_cow_rump_" + std::to_string(y), s::scene_meshes(s::sheet_over_cow_rump(y, 41)),
           threads);
  }
  for (int seed = 0; seed < random; ++seed) {
    const s::RandomTangle t = s::random_tangle(static_cast<std::uint64_t>(seed));
    dump(t.scene.name, s::scene_meshes(t.scene), threads);
  }
  return 0;
}
