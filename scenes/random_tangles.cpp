// Random tangles: seeded scenes of small sheets, tubes and closed meshes thrown through each other.
#include "scenes/random_tangles.h"

#include <array>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "scenes/self_scenes.h"

namespace untangle::scenes {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Every generated triangle is its own source face (as the builders of scenes.cpp do).
void number_source_faces(Mesh& mesh) {
  mesh.polygon.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) mesh.polygon[t] = static_cast<std::uint32_t>(t);
  mesh.source_faces = mesh.triangles.size();
}

// std::mt19937_64's output sequence is fixed by the standard; the distributions of <random> are
// not, so the mapping to doubles and ranges is our own.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) {  // in [lo, hi)
    return lo + (hi - lo) * (static_cast<double>(engine_() >> 11) * 0x1.0p-53);
  }
  int integer(int lo, int hi) {  // in [lo, hi]; the modulo bias is irrelevant here
    return lo + static_cast<int>(engine_() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  // One of lo, lo + step, ..., hi (exact when step is a power of two and the values small).
  double step_value(double lo, double hi, double step) {
    return lo + step * integer(0, static_cast<int>(std::lround((hi - lo) / step)));
  }

 private:
  std::mt19937_64 engine_;
};

enum class Kind { kSheet, kTube, kSphere, kBox, kTorus };

bool is_closed(Kind kind) { return kind == Kind::kSphere || kind == Kind::kBox || kind == Kind::kTorus; }

// The snapping grid of snapped scenes and the finer one tried when it would weld two vertices of a
// mesh or flatten a triangle. Powers of two: snapped coordinates (|c| < 8) and their differences
// and 2x2 products are exact in double, so the validity test below is exact.
constexpr double kCoarseGrid = 1.0 / 16.0;
constexpr double kFineGrid = 1.0 / 128.0;

Vec3 snapped_position(const Vec3& p, double grid) {
  return {std::round(p[0] / grid) * grid, std::round(p[1] / grid) * grid,
          std::round(p[2] / grid) * grid};
}

// Whether the mesh has two vertices at one position or a triangle with collinear corners (exact
// for snapped coordinates, see kCoarseGrid).
bool has_degenerate_geometry(const Mesh& mesh) {
  if (std::set<Vec3>(mesh.positions.begin(), mesh.positions.end()).size() != mesh.positions.size()) {
    return true;
  }
  for (const Triangle& t : mesh.triangles) {
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const Vec3 u = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const Vec3 v = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    if (u[1] * v[2] - u[2] * v[1] == 0.0 && u[2] * v[0] - u[0] * v[2] == 0.0 &&
        u[0] * v[1] - u[1] * v[0] == 0.0) {
      return true;
    }
  }
  return false;
}

// Snaps the mesh to the coarse grid, or the fine one when the coarse one degenerates it, or leaves
// it as it is. Returns the grid used (0 = none).
double snap(Mesh& mesh) {
  for (double grid : {kCoarseGrid, kFineGrid}) {
    Mesh candidate = mesh;
    for (Vec3& p : candidate.positions) p = snapped_position(p, grid);
    if (!has_degenerate_geometry(candidate)) {
      mesh = std::move(candidate);
      return grid;
    }
  }
  return 0.0;
}

// A sheet of random resolution and size in z = 0 centred on the origin; in general position also
// bent (a wave along x, or rolled into an arc about the y axis).
Mesh random_sheet(Random& random, bool snapped, const std::string& name, std::string& what) {
  const int nu = random.integer(4, 12), nv = random.integer(4, 12);
  const double su = snapped ? random.step_value(1.5, 3.0, 0.5) : random.uniform(1.6, 3.0);
  const double sv = snapped ? random.step_value(1.5, 3.0, 0.5) : random.uniform(1.6, 3.0);
  Mesh mesh = grid_sheet(nu, nv, {-0.5 * su, -0.5 * sv, 0.0}, {su, 0.0, 0.0}, {0.0, sv, 0.0}, name);
  what = "sheet " + std::to_string(nu) + "x" + std::to_string(nv);
  const int bend = snapped ? 0 : random.integer(0, 2);
  if (bend == 1) {
    const double amplitude = random.uniform(0.05, 0.3), frequency = random.uniform(1.0, 4.0);
    const double phase = random.uniform(0.0, 2.0 * kPi);
    for (Vec3& p : mesh.positions) p[2] += amplitude * std::sin(frequency * p[0] + phase);
    what += " wave";
  } else if (bend == 2) {
    const double curvature = random.uniform(0.3, 1.5);
    for (Vec3& p : mesh.positions) {
      const double angle = curvature * p[0];
      p = {std::sin(angle) / curvature, p[1], (1.0 - std::cos(angle)) / curvature - 0.3};
    }
    what += " arc";
  }
  return mesh;
}

Mesh random_mesh(Random& random, Kind kind, bool snapped, const std::string& name,
                 std::string& what) {
  // Sizes of snapped meshes are multiples of 1/4 so that flat faces land on grid planes together.
  const auto size = [&](double lo, double hi) {
    return snapped ? random.step_value(lo, hi, 0.25) : random.uniform(lo, hi);
  };
  const Vec3 origin = {0.0, 0.0, 0.0};
  switch (kind) {
    case Kind::kSheet:
      return random_sheet(random, snapped, name, what);
    case Kind::kTube: {
      const int slices = random.integer(6, 14), rings = random.integer(2, 7);
      what = "tube " + std::to_string(slices) + "x" + std::to_string(rings);
      return open_tube(origin, size(0.25, 0.75), size(1.25, 2.5), slices, rings, name);
    }
    case Kind::kSphere: {
      const int slices = random.integer(6, 14), stacks = random.integer(4, 9);
      what = "sphere " + std::to_string(slices) + "x" + std::to_string(stacks);
      return uv_sphere(origin, size(0.5, 1.0), slices, stacks, name);
    }
    case Kind::kBox: {
      const int cells = random.integer(1, 4);
      what = "box " + std::to_string(cells);
      const Vec3 half = {size(0.25, 0.75), size(0.25, 0.75), size(0.25, 0.75)};
      return box_surface(origin, half, cells, name);
    }
    case Kind::kTorus: {
      const int around = random.integer(8, 16), tube = random.integer(4, 8);
      what = "torus " + std::to_string(around) + "x" + std::to_string(tube);
      const double major = size(0.5, 1.0);
      return torus(origin, major, major * random.uniform(0.2, 0.45), around, tube, name);
    }
  }
  throw std::logic_error("random_mesh: unknown kind");
}

// Turns the mesh about x, then y, then z and moves it by up to `spread` along each axis: by
// arbitrary angles and offsets in general position, by quarter turns and multiples of 1/8 in
// snapped scenes.
Mesh random_placement(Random& random, Mesh mesh, bool snapped, double spread) {
  const auto angle = [&] {
    return snapped ? 0.5 * kPi * random.integer(0, 3) : random.uniform(0.0, 2.0 * kPi);
  };
  const auto offset = [&] {
    return snapped ? random.step_value(-spread, spread, 0.125) : random.uniform(-spread, spread);
  };
  const double ax = angle(), ay = angle(), az = angle();
  const Vec3 shift = {offset(), offset(), offset()};
  mesh = rotated(std::move(mesh), 0, ax, {0.0, 0.0, 0.0});
  mesh = rotated(std::move(mesh), 1, ay, {0.0, 0.0, 0.0});
  return rotated(std::move(mesh), 2, az, shift);
}

std::string grid_label(double grid) {
  if (grid == 0.0) return "unsnapped";
  return "snapped 1/" + std::to_string(std::lround(1.0 / grid));
}

}  // namespace

Mesh box_surface(Vec3 centre, Vec3 half, int cells, const std::string& name) {
  if (cells < 1) throw std::invalid_argument("box_surface: needs at least one cell per face");
  Mesh mesh;
  mesh.name = name;
  // Vertices keyed by lattice point in [0, cells]^3, so faces share their rims (welded).
  std::map<std::array<int, 3>, std::uint32_t> vertex_of;
  const auto vertex = [&](const std::array<int, 3>& lattice) {
    const auto [it, inserted] =
        vertex_of.emplace(lattice, static_cast<std::uint32_t>(mesh.positions.size()));
    if (inserted) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) p[k] = centre[k] + half[k] * (2.0 * lattice[k] / cells - 1.0);
      mesh.positions.push_back(p);
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign : {+1, -1}) {
      // (b, c, outward normal) right-handed, so (0,0) (1,0) (1,1) in (b, c) faces outward.
      int b = (axis + 1) % 3, c = (axis + 2) % 3;
      if (sign < 0) std::swap(b, c);
      for (int q = 0; q < cells; ++q) {
        for (int p = 0; p < cells; ++p) {
          const auto corner = [&](int dp, int dq) {
            std::array<int, 3> l{};
            l[axis] = sign > 0 ? cells : 0;
            l[b] = p + dp;
            l[c] = q + dq;
            return vertex(l);
          };
          const std::uint32_t v00 = corner(0, 0), v10 = corner(1, 0), v11 = corner(1, 1),
                              v01 = corner(0, 1);
          mesh.triangles.push_back({v00, v10, v11});
          mesh.triangles.push_back({v00, v11, v01});
        }
      }
    }
  }
  number_source_faces(mesh);
  return mesh;
}

Mesh torus(Vec3 centre, double major, double minor, int around, int tube, const std::string& name) {
  if (around < 3 || tube < 3 || !(minor < major)) throw std::invalid_argument("torus: bad sizes");
  Mesh mesh;
  mesh.name = name;
  for (int i = 0; i < around; ++i) {
    const double u = 2.0 * kPi * i / around;
    for (int j = 0; j < tube; ++j) {
      const double v = 2.0 * kPi * j / tube;
      const double rho = major + minor * std::cos(v);
      mesh.positions.push_back({centre[0] + rho * std::cos(u), centre[1] + rho * std::sin(u),
                                centre[2] + minor * std::sin(v)});
    }
  }
  const auto at = [&](int i, int j) {
    return static_cast<std::uint32_t>((i % around) * tube + (j % tube));
  };
  // d/du x d/dv points away from the tube's core circle: (i, j) (i+1, j) (i+1, j+1) faces outward.
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < tube; ++j) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  number_source_faces(mesh);
  return mesh;
}

RandomTangle random_tangle(std::uint64_t seed) {
  Random random(seed);
  RandomTangle out;
  out.scene.name = "random_tangle_" + std::to_string(seed);
  out.snapped = random.chance(0.35);
  const int count = random.integer(2, 4);
  // How far apart the meshes' centres may be (they are about 1 to 3 across): small spreads make
  // deep overlaps, large ones shallow crossings and the odd scene that does not touch at all.
  const double spread = out.snapped ? random.step_value(0.25, 1.0, 0.25) : random.uniform(0.2, 1.0);
  std::vector<Kind> kinds;
  for (int i = 0; i < count; ++i) kinds.push_back(static_cast<Kind>(random.integer(0, 4)));
  // At most one obstacle, a closed mesh when there is one (the usual body under cloth).
  int obstacle = -1;
  if (random.chance(0.4)) {
    obstacle = random.integer(0, count - 1);
    for (int i = 0; i < count; ++i) {
      if (is_closed(kinds[i])) obstacle = i;
    }
  }
  std::string movable_text, obstacle_text;
  for (int i = 0; i < count; ++i) {
    std::string what;
    Mesh mesh = random_mesh(random, kinds[i], out.snapped, "m" + std::to_string(i), what);
    mesh = random_placement(random, std::move(mesh), out.snapped, spread);
    if (out.snapped) what += " " + grid_label(snap(mesh));
    if (i == obstacle) {
      mesh.role = Role::kObstacle;
      obstacle_text = what;
      out.scene.obstacles.push_back(std::move(mesh));
    } else {
      movable_text += (movable_text.empty() ? "" : ", ") + what;
      out.scene.movable.push_back(std::move(mesh));
    }
  }
  out.description = "seed " + std::to_string(seed) + (out.snapped ? " (snapped)" : "") +
                    ": movable " + movable_text;
  if (!obstacle_text.empty()) out.description += "; obstacle " + obstacle_text;
  return out;
}

}  // namespace untangle::scenes
