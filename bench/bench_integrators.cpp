// Which integrator for the cloth of `untangle simulate` (issue 19): the library's projective
// dynamics (lib/src/sim/cloth_model.*: one SimplicialLDLT factored at the start, local/global
// iterations) against XPBD (Macklin, Müller and Chentanez 2016, "XPBD: position-based simulation
// of compliant constrained dynamics"), written here and nowhere else, on the same ClothModel: the
// same particles, lumped masses, pins and springs (every edge a stretch spring, every pair of
// corners across an interior edge a bending spring), the same damping and gravity, and no
// collision. Both minimise the same energy: a spring of projective-dynamics weight w (in units of
// mass, already multiplied by h^2) has stiffness k = w / h^2, so its XPBD compliance alpha = 1 / k
// scaled by 1 / h^2 is alpha~ = 1 / w, the same at every step length.
//
// Scene: a square sheet (default 81 x 81 vertices, 2 scene units a side like the `spikes`
// example's) lying flat, pinned at the two corners of one side, swinging down and hanging under
// gravity (-9.81 in y), 1/60 s a frame, 4 steps a frame (the defaults of ClothOptions).
// Every step: v *= 1 - damping h; the integrator moves x from the start of the step; v = (x_end -
// x_start) / h. No speed cap, no correction: what is compared is the integrators alone.
// XPBD: per step the prediction x + h v + h^2 g, lambda reset to 0, then N Gauss-Seidel sweeps
// over the springs in their fixed order (deterministic; pinned particles have inverse mass 0).
//
// Printed per integrator and iteration count: setup ms (model and factorization), median and
// total ms per frame (steady_clock, one thread: the library's integrator does not use threads),
// the largest edge length over its rest length over the whole run and at the end, the mean
// |stretch - 1| over the edges at the end, the kinetic energy at the end, whether the run stayed
// stable (every position and velocity finite at every frame) and whether it kept every edge within
// 2x its rest length at every frame (the rule of `untangle simulate`). Also the lowest point at the
// end: both integrators converge, with more iterations, to the same implicit-Euler motion, so
// where the sheet has swung to shows how much motion the iterations left out (artificial damping).
//
// Usage: untangle_bench_integrators [--size N] [--frames N] [--substeps N] [--quick]
//                                   [--pd LIST] [--xpbd LIST]
//   --size N     vertices per side (default 81)
//   --frames N   frames (default 120, 2 s)
//   --substeps N steps per frame (default 4)
//   --pd LIST    projective-dynamics iteration counts, comma-separated (default 5,10,20; the
//                library's default is 10)
//   --xpbd LIST  XPBD iteration counts (default 10,20,40,80)
//   --quick      21 x 21, 30 frames (seconds)
// Exit status 1 when projective dynamics at the library's default iterations is not stable or
// stretches an edge beyond 2x.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "app/best_median.h"
#include "geometry/vec3.h"
#include "scenes/scenes.h"
#include "sim/cloth_model.h"
#include "untangle/simulate.h"

namespace {

using untangle::ClothModel;
using untangle::ClothOptions;
using untangle::Mesh;
using untangle::Vec3;
using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

struct Settings {
  int size = 81;
  int frames = 120;
  int substeps = 4;
  std::vector<int> pd = {5, 10, 20};
  std::vector<int> xpbd = {10, 20, 40, 80};
};

struct Row {
  std::string integrator;
  int iterations = 0;
  double setup_ms = 0.0;
  double median_ms = 0.0, total_ms = 0.0;
  double max_stretch_run = 0.0, max_stretch_end = 0.0, mean_strain_end = 0.0;
  double kinetic_end = 0.0, lowest_end = 0.0;
  bool stable = true;     // finite at every frame
  bool within_2x = true;  // no edge beyond 2x its rest length at any frame
};

// The scene: the sheet flat at y = 0, pinned at the corners (0, 0) and (size - 1, 0).
struct Scene {
  std::vector<Mesh> meshes;
  untangle::PinMask pins;
};

Scene hanging_sheet(int size) {
  Scene scene;
  scene.meshes.push_back(untangle::scenes::grid_sheet(size, size, {-1.0, 0.0, -1.0}, {2.0, 0.0, 0.0},
                                                      {0.0, 0.0, 2.0}, "sheet"));
  scene.pins.assign(1, std::vector<std::uint8_t>(scene.meshes[0].positions.size(), 0));
  scene.pins[0][0] = 1;
  scene.pins[0][static_cast<std::size_t>(size - 1)] = 1;
  return scene;
}

// What the state looks like now: stretch of the edges, energy, lowest point; false when a
// position is not finite.
bool measure(const ClothModel& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
             double& max_stretch, double& mean_strain, double& kinetic, double& lowest) {
  max_stretch = 0.0;
  mean_strain = 0.0;
  kinetic = 0.0;
  lowest = INFINITY;
  bool finite = true;
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(x[i][c]) && std::isfinite(v[i][c]);
    kinetic += 0.5 * model.mass[i] * untangle::dot(v[i], v[i]);
    lowest = std::min(lowest, x[i][1]);
  }
  std::size_t edges = 0;
  for (const ClothModel::Spring& sp : model.springs) {
    if (!sp.stretch) continue;
    const double s = untangle::norm(untangle::sub(x[sp.a], x[sp.b])) / sp.rest;
    max_stretch = std::max(max_stretch, s);
    mean_strain += std::abs(s - 1.0);
    ++edges;
  }
  if (edges > 0) mean_strain /= static_cast<double>(edges);
  return finite;
}

// One XPBD step of length h on the model's springs: x in (start of the step), x out (its end).
void xpbd_step(const ClothModel& model, const std::vector<double>& inverse_mass,
               const ClothOptions& options, double h, int iterations, std::vector<Vec3>& x,
               const std::vector<Vec3>& v, std::vector<double>& lambda) {
  const std::size_t n = x.size();
  for (std::size_t i = 0; i < n; ++i)
    if (inverse_mass[i] > 0.0)
      x[i] = untangle::add(untangle::add(x[i], untangle::scale(v[i], h)),
                           untangle::scale(options.gravity, h * h));
  std::fill(lambda.begin(), lambda.end(), 0.0);
  for (int iteration = 0; iteration < iterations; ++iteration) {
    for (std::size_t k = 0; k < model.springs.size(); ++k) {
      const ClothModel::Spring& sp = model.springs[k];
      const double wa = inverse_mass[sp.a], wb = inverse_mass[sp.b];
      if (wa + wb == 0.0) continue;
      const Vec3 d = untangle::sub(x[sp.a], x[sp.b]);
      const double len = untangle::norm(d);
      if (!(len > 0.0)) continue;
      const Vec3 dir = untangle::scale(d, 1.0 / len);
      const double compliance = 1.0 / sp.weight;  // alpha / h^2 with alpha = 1 / (weight / h^2)
      const double c = len - sp.rest;
      const double dl = (-c - compliance * lambda[k]) / (wa + wb + compliance);
      lambda[k] += dl;
      x[sp.a] = untangle::add(x[sp.a], untangle::scale(dir, wa * dl));
      x[sp.b] = untangle::sub(x[sp.b], untangle::scale(dir, wb * dl));
    }
  }
}

Row run(const Settings& settings, bool xpbd, int iterations) {
  const Scene scene = hanging_sheet(settings.size);
  ClothOptions options;
  options.substeps = settings.substeps;
  options.solver_iterations = iterations;
  const double h = options.time_step / options.substeps;
  Row row;
  row.integrator = xpbd ? "XPBD (Gauss-Seidel)" : "projective dynamics (LDLT)";
  row.iterations = iterations;
  ClothModel model;
  const auto t0 = Clock::now();
  untangle::build_cloth_model(scene.meshes, scene.pins, options, model);
  row.setup_ms = ms_between(t0, Clock::now());
  std::vector<Vec3> x = model.topo.points, v(x.size(), Vec3{0.0, 0.0, 0.0});
  std::vector<double> inverse_mass(x.size(), 0.0), lambda(model.springs.size(), 0.0);
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!model.pinned[i]) inverse_mass[i] = 1.0 / model.mass[i];
  const double keep = std::max(0.0, 1.0 - options.damping * h);
  std::vector<double> frame_ms;
  for (int frame = 0; frame < settings.frames; ++frame) {
    const auto f0 = Clock::now();
    for (int step = 0; step < options.substeps; ++step) {
      for (Vec3& vel : v) vel = untangle::scale(vel, keep);
      const std::vector<Vec3> start = x;
      if (xpbd)
        xpbd_step(model, inverse_mass, options, h, iterations, x, v, lambda);
      else
        untangle::integrate_step(model, options, h, x, v);
      for (std::size_t i = 0; i < x.size(); ++i)
        v[i] = untangle::scale(untangle::sub(x[i], start[i]), 1.0 / h);
    }
    frame_ms.push_back(ms_between(f0, Clock::now()));
    double max_stretch = 0.0, mean_strain = 0.0, kinetic = 0.0, lowest = 0.0;
    const bool finite = measure(model, x, v, max_stretch, mean_strain, kinetic, lowest);
    row.max_stretch_run = std::max(row.max_stretch_run, max_stretch);
    if (!(max_stretch <= 2.0)) row.within_2x = false;
    if (!finite) {
      row.stable = false;
      break;
    }
  }
  for (double t : frame_ms) row.total_ms += t;
  row.median_ms = untangle::app::stat_of(frame_ms).median;
  measure(model, x, v, row.max_stretch_end, row.mean_strain_end, row.kinetic_end, row.lowest_end);
  return row;
}

std::vector<int> parse_list(const char* text) {
  std::vector<int> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const int k = std::atoi(item.c_str());
    if (k < 1) {
      std::fprintf(stderr, "bad iteration count '%s'\n", item.c_str());
      std::exit(2);
    }
    out.push_back(k);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  for (int i = 1; i < argc; ++i) {
    const bool more = i + 1 < argc;
    if (std::strcmp(argv[i], "--quick") == 0) {
      settings.size = 21;
      settings.frames = 30;
    } else if (std::strcmp(argv[i], "--size") == 0 && more) {
      settings.size = std::max(2, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--frames") == 0 && more) {
      settings.frames = std::max(1, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--substeps") == 0 && more) {
      settings.substeps = std::max(1, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--pd") == 0 && more) {
      settings.pd = parse_list(argv[++i]);
    } else if (std::strcmp(argv[i], "--xpbd") == 0 && more) {
      settings.xpbd = parse_list(argv[++i]);
    } else {
      std::fprintf(stderr,
                   "usage: %s [--size N] [--frames N] [--substeps N] [--pd LIST] [--xpbd LIST] "
                   "[--quick]\n",
                   argv[0]);
      return 2;
    }
  }
  const ClothOptions defaults;
  std::printf("sheet %d x %d (%d particles), 2 units a side, pinned at two corners; %d frames of "
              "%.4g s, %d steps a frame; stretch %g, bend %g, damping %g/s\n",
              settings.size, settings.size, settings.size * settings.size, settings.frames,
              defaults.time_step, settings.substeps, defaults.stretch, defaults.bend,
              defaults.damping);
  std::printf("%-28s %5s %9s %11s %11s %12s %12s %12s %12s %9s %7s %7s\n", "integrator",
              "iter", "setup ms", "ms/frame", "total ms", "stretch max", "stretch end",
              "mean|s-1|", "kinetic end", "lowest y", "stable", "<=2x");
  bool pd_default_stable = true;
  auto print = [](const Row& r) {
    std::printf("%-28s %5d %9.1f %11.2f %11.1f %12.4f %12.4f %12.3e %12.4e %9.4f %7s %7s\n",
                r.integrator.c_str(), r.iterations, r.setup_ms, r.median_ms, r.total_ms,
                r.max_stretch_run, r.max_stretch_end, r.mean_strain_end, r.kinetic_end,
                r.lowest_end, r.stable ? "yes" : "no", r.within_2x ? "yes" : "no");
    std::fflush(stdout);
  };
  for (int k : settings.pd) {
    const Row r = run(settings, false, k);
    if (k == defaults.solver_iterations && !(r.stable && r.within_2x)) pd_default_stable = false;
    print(r);
  }
  for (int k : settings.xpbd) print(run(settings, true, k));
  return pd_default_stable ? 0 : 1;
}
