// How time and memory grow with size (issue 6): sheets of n x n vertices (41 to 501) cutting
// through a closed body, and a garment-like mesh subdivided up to about a million triangles with a
// body poking through it. For each scene: detection + contours (find_intersections, as `check`),
// the repair (fix_meshes), and the peak resident memory of the process that ran it.
//
// Usage: untangle_bench_scaling [--quick] [--threads N] [--sheet N]... [--garment R]...
//   --quick      the three smallest sheets and the smallest garment only
//   --sheet N    only an N x N sheet (repeatable); --garment R: only a garment of resolution R
// Every scene runs in a child process of its own (fork), so the peak resident memory printed is
// that scene's alone (getrusage of the child). Times are wall-clock, std::chrono::steady_clock.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "scenes/scenes.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"

namespace {

using untangle::Mesh;
using untangle::Vec3;

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since)
      .count();
}

struct Case {
  std::string name;
  int size = 0;  // n for sheets, the cube resolution for garments
  bool garment = false;
};

// A closed body: a capsule lying along x, cut across by the sheet at z = 0.0137.
std::vector<Mesh> sheet_scene(int n) {
  std::vector<Mesh> meshes;
  meshes.push_back(untangle::scenes::grid_sheet(n, n, {-1.4929, -1.4887, 0.0137}, {3.0, 0.0, 0.0},
                                                {0.0, 3.0, 0.0}, "sheet"));
  Mesh body = untangle::scenes::capsule({0.0, 0.0, 0.0}, 0.6, 1.6, 64, 24, "body");
  // The capsule's axis is z: turn it to lie along x (x, y, z) -> (z, y, -x).
  for (Vec3& p : body.positions) p = {p[2], p[1], -p[0]};
  for (auto& t : body.triangles) std::swap(t[1], t[2]);  // keep it outward after the mirror
  body.role = untangle::Role::kObstacle;
  meshes.push_back(std::move(body));
  return meshes;
}

// A garment-like mesh (four openings) of the given cube resolution with an upright capsule wider
// than its thin direction poking through its front and back.
std::vector<Mesh> garment_scene(int resolution) {
  std::vector<Mesh> meshes;
  meshes.push_back(untangle::scenes::garment_like({0.0, 0.0, 0.0}, 1.0, resolution, "garment"));
  Mesh body = untangle::scenes::capsule({0.0137, 0.0211, -0.0173}, 0.56, 1.4, 96, 32, "body");
  body.role = untangle::Role::kObstacle;
  meshes.push_back(std::move(body));
  return meshes;
}

struct Measured {
  std::size_t vertices = 0, triangles = 0, crossings = 0, contours = 0, after = 0;
  int iterations = 0;
  bool clean = false;
  double detect_ms = 0.0, contours_ms = 0.0, fix_ms = 0.0, fix_detect_ms = 0.0;
};

Measured run_case(const Case& c, int threads) {
  std::vector<Mesh> meshes = c.garment ? garment_scene(c.size) : sheet_scene(c.size);
  Measured m;
  m.vertices = meshes[0].positions.size();
  for (const Mesh& mesh : meshes) m.triangles += mesh.triangles.size();
  untangle::DetectOptions detect;
  detect.threads = threads;
  detect.skip_obstacle_pairs = true;  // as fix and its verification do: the body is not repaired
  untangle::DetectTimings timings;
  auto start = std::chrono::steady_clock::now();
  const untangle::Intersections found = untangle::find_intersections(meshes, detect, &timings);
  const double total = elapsed_ms(start);
  m.crossings = found.counts.crossings;
  m.contours = found.counts.contours;
  m.contours_ms = timings.contours_ms;
  m.detect_ms = total - timings.contours_ms;
  untangle::FixOptions options;
  options.threads = threads;
  start = std::chrono::steady_clock::now();
  const untangle::FixResult result = untangle::fix_meshes(meshes, options);
  m.fix_ms = elapsed_ms(start);
  m.fix_detect_ms = result.detect_ms;
  m.iterations = result.iterations;
  m.after = result.after.crossings;
  m.clean = result.clean;
  return m;
}

// Runs the case in a child process; the child writes its numbers through a pipe.
bool run_isolated(const Case& c, int threads, Measured& out, long& peak_kb) {
  int fds[2];
  if (pipe(fds) != 0) return false;
  const pid_t pid = fork();
  if (pid < 0) return false;
  if (pid == 0) {
    close(fds[0]);
    const Measured m = run_case(c, threads);
    const ssize_t written = write(fds[1], &m, sizeof m);
    _exit(written == static_cast<ssize_t>(sizeof m) ? 0 : 1);
  }
  close(fds[1]);
  Measured m;
  std::size_t got = 0;
  while (got < sizeof m) {
    const ssize_t r = read(fds[0], reinterpret_cast<char*>(&m) + got, sizeof m - got);
    if (r <= 0) break;
    got += static_cast<std::size_t>(r);
  }
  close(fds[0]);
  int status = 0;
  struct rusage usage {};
  if (wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0 ||
      got != sizeof m)
    return false;
  out = m;
  peak_kb = usage.ru_maxrss;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  int threads = 0;
  std::vector<Case> only;  // --sheet N / --garment R: just these
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else if ((std::strcmp(argv[i], "--sheet") == 0 || std::strcmp(argv[i], "--garment") == 0) &&
               i + 1 < argc) {
      const bool garment = argv[i][2] == 'g';
      const int size = std::atoi(argv[++i]);
      only.push_back(
          {std::string(garment ? "garment r" : "sheet n=") + std::to_string(size), size, garment});
    } else if (std::strcmp(argv[i], "-h") == 0 || std::strcmp(argv[i], "--help") == 0) {
      std::printf("usage: %s [--quick] [--threads N] [--sheet N]... [--garment R]...\n", argv[0]);
      return 0;
    } else {
      std::fprintf(stderr, "error: unknown argument '%s' (usage: %s [--quick] [--threads N])\n",
                   argv[i], argv[0]);
      return 2;
    }
  }
  std::vector<Case> cases = only;
  if (only.empty())
    for (int n :
         quick ? std::vector<int>{41, 81, 161} : std::vector<int>{41, 81, 161, 241, 321, 401, 501})
      cases.push_back({"sheet " + std::to_string(n) + "x" + std::to_string(n), n, false});
  if (only.empty())
    for (int r : quick ? std::vector<int>{32} : std::vector<int>{32, 64, 128, 256, 360})
      cases.push_back({"garment r" + std::to_string(r), r, true});

  std::printf(
      "untangle scaling: sheets through a closed capsule, garment-like meshes with a body "
      "through them; threads %d; one child process per scene\n\n",
      threads);
  std::printf("%-18s %9s %10s %9s %5s %10s %9s %9s %5s %6s %10s %8s %12s\n", "scene", "vertices",
              "triangles", "crossings", "cont", "detect ms", "contours", "fix ms", "iter", "after",
              "fix det ms", "peak MB", "ns/tri check");
  double first_ns = 0.0;
  for (const Case& c : cases) {
    Measured m;
    long peak_kb = 0;
    if (!run_isolated(c, threads, m, peak_kb)) {
      std::printf("%-18s failed\n", c.name.c_str());
      continue;
    }
    const double ns_per_triangle =
        1e6 * (m.detect_ms + m.contours_ms) / static_cast<double>(m.triangles);
    if (first_ns == 0.0) first_ns = ns_per_triangle;
    std::printf("%-18s %9zu %10zu %9zu %5zu %10.1f %9.1f %9.1f %5d %6zu %10.1f %8.1f %12.0f\n",
                c.name.c_str(), m.vertices, m.triangles, m.crossings, m.contours, m.detect_ms,
                m.contours_ms, m.fix_ms, m.iterations, m.after, m.fix_detect_ms,
                static_cast<double>(peak_kb) / 1024.0, ns_per_triangle);
    std::fflush(stdout);
  }
  std::printf(
      "\nns/tri check: detection + contours per triangle of the scene (flat = linear growth)."
      "\nfix det ms: detection inside fix, all iterations (the first full, then only what "
      "moved).\n");
  return 0;
}
