// Generated test scenes: welded, consistently oriented primitives and the named scenes on them.
#include "scenes/scenes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <utility>

#include "geometry/vec3.h"
#include "untangle/error.h"
#include "untangle/read_meshes.h"

#ifndef UNTANGLE_COW_OFF
#define UNTANGLE_COW_OFF ""
#endif

namespace untangle::scenes {
namespace {

constexpr double kPi = 3.14159265358979323846;

Mesh new_mesh(const std::string& name) {
  Mesh mesh;
  mesh.name = name;
  mesh.role = Role::kMovable;
  return mesh;
}

// Every generated triangle is its own source face.
Mesh finish(Mesh mesh) {
  mesh.polygon.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    mesh.polygon[t] = static_cast<std::uint32_t>(t);
  }
  mesh.source_faces = mesh.triangles.size();
  return mesh;
}

std::uint32_t index(std::size_t i) { return static_cast<std::uint32_t>(i); }

// A surface of revolution around the z axis through `centre`. `profile` lists (radius, z) from
// top to bottom; a zero radius at either end is a pole (one vertex). Rings of `slices` vertices.
// Triangles are ordered so that normals point away from the axis (outward for closed shapes):
// with a = ring i slice j, b = ring i slice j+1, c = ring i+1 slice j+1, d = ring i+1 slice j,
// (d - a) runs down the profile and (b - a) around it, and down x around is outward.
Mesh revolve(Vec3 centre, const std::vector<std::pair<double, double>>& profile, int slices,
             const std::string& name) {
  if (slices < 3 || profile.size() < 2) throw std::invalid_argument("revolve: too few vertices");
  Mesh mesh = new_mesh(name);
  const bool top_pole = profile.front().first == 0.0;
  const bool bottom_pole = profile.back().first == 0.0;
  std::vector<std::uint32_t> ring_start(profile.size());
  for (std::size_t r = 0; r < profile.size(); ++r) {
    ring_start[r] = index(mesh.positions.size());
    const auto [rho, z] = profile[r];
    if ((r == 0 && top_pole) || (r + 1 == profile.size() && bottom_pole)) {
      mesh.positions.push_back(add(centre, {0.0, 0.0, z}));
      continue;
    }
    for (int j = 0; j < slices; ++j) {
      const double theta = 2.0 * kPi * j / slices;
      mesh.positions.push_back(add(centre, {rho * std::cos(theta), rho * std::sin(theta), z}));
    }
  }
  const std::uint32_t n = index(slices);
  for (std::size_t r = 0; r + 1 < profile.size(); ++r) {
    const bool pole_above = r == 0 && top_pole;
    const bool pole_below = r + 2 == profile.size() && bottom_pole;
    for (std::uint32_t j = 0; j < n; ++j) {
      const std::uint32_t jn = (j + 1) % n;
      if (pole_above) {
        const std::uint32_t top = ring_start[r];
        mesh.triangles.push_back({top, ring_start[r + 1] + j, ring_start[r + 1] + jn});
      } else if (pole_below) {
        const std::uint32_t bottom = ring_start[r + 1];
        mesh.triangles.push_back({ring_start[r] + j, bottom, ring_start[r] + jn});
      } else {
        const std::uint32_t a = ring_start[r] + j, b = ring_start[r] + jn;
        const std::uint32_t c = ring_start[r + 1] + jn, d = ring_start[r + 1] + j;
        mesh.triangles.push_back({a, d, c});
        mesh.triangles.push_back({a, c, b});
      }
    }
  }
  return finish(std::move(mesh));
}

// Rotation about the x axis by `angle`, then translation by `offset`.
Mesh tilted(Mesh mesh, double angle, Vec3 offset) {
  const double c = std::cos(angle), s = std::sin(angle);
  for (Vec3& p : mesh.positions) {
    p = add({p[0], c * p[1] - s * p[2], s * p[1] + c * p[2]}, offset);
  }
  return mesh;
}

Mesh obstacle(Mesh mesh) {
  mesh.role = Role::kObstacle;
  return mesh;
}

}  // namespace

// ---- primitives ----

Mesh grid_sheet(int nu, int nv, Vec3 origin, Vec3 u, Vec3 v, const std::string& name) {
  if (nu < 2 || nv < 2) throw std::invalid_argument("grid_sheet: needs at least 2 x 2 vertices");
  Mesh mesh = new_mesh(name);
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const double s = static_cast<double>(i) / (nu - 1), t = static_cast<double>(j) / (nv - 1);
      mesh.positions.push_back(add(origin, add(scale(u, s), scale(v, t))));
    }
  }
  // Normals along u x v; all diagonals from (i, j) to (i+1, j+1).
  for (int j = 0; j + 1 < nv; ++j) {
    for (int i = 0; i + 1 < nu; ++i) {
      const std::uint32_t a = index(j * nu + i), b = a + 1, c = index((j + 1) * nu + i + 1),
                          d = index((j + 1) * nu + i);
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  }
  return finish(std::move(mesh));
}

Mesh uv_sphere(Vec3 centre, double radius, int slices, int stacks, const std::string& name) {
  if (stacks < 2) throw std::invalid_argument("uv_sphere: needs at least 2 stacks");
  std::vector<std::pair<double, double>> profile;
  for (int i = 0; i <= stacks; ++i) {
    const double phi = kPi * i / stacks;
    const double rho = (i == 0 || i == stacks) ? 0.0 : radius * std::sin(phi);
    profile.emplace_back(rho, radius * std::cos(phi));
  }
  return revolve(centre, profile, slices, name);
}

Mesh open_tube(Vec3 centre, double radius, double length, int slices, int rings,
               const std::string& name) {
  if (rings < 2) throw std::invalid_argument("open_tube: needs at least 2 rings");
  std::vector<std::pair<double, double>> profile;
  for (int i = 0; i < rings; ++i) {
    profile.emplace_back(radius, length * (0.5 - static_cast<double>(i) / (rings - 1)));
  }
  return revolve(centre, profile, slices, name);
}

Mesh capsule(Vec3 centre, double radius, double length, int slices, int rings,
             const std::string& name) {
  if (rings < 2) throw std::invalid_argument("capsule: needs at least 2 rings");
  const int cap_stacks = std::max(2, slices / 4);
  std::vector<std::pair<double, double>> profile;
  for (int i = 0; i < cap_stacks; ++i) {  // top cap, pole to just above the top ring
    const double phi = 0.5 * kPi * i / cap_stacks;
    profile.emplace_back(i == 0 ? 0.0 : radius * std::sin(phi),
                         0.5 * length + radius * std::cos(phi));
  }
  for (int i = 0; i < rings; ++i) {
    profile.emplace_back(radius, length * (0.5 - static_cast<double>(i) / (rings - 1)));
  }
  for (int i = cap_stacks - 1; i >= 0; --i) {  // bottom cap, just below the bottom ring to pole
    const double phi = 0.5 * kPi * i / cap_stacks;
    profile.emplace_back(i == 0 ? 0.0 : radius * std::sin(phi),
                         -0.5 * length - radius * std::cos(phi));
  }
  return revolve(centre, profile, slices, name);
}

// The top is a height field over a (count*cells) x (count*cells) grid: in each of the count x count
// cells a round cone of radius 0.45 * cell and height `height` with its tip on a grid vertex; the
// flat parts lie at base_centre's z. Walls go down to a flat bottom 0.1 * size lower, closed by a
// fan around one centre vertex.
Mesh cone_spikes(Vec3 base_centre, double size, int count, double height, const std::string& name) {
  if (count < 1) throw std::invalid_argument("cone_spikes: needs at least one spike");
  constexpr int kCells = 10;     // grid cells per spike cell (even: the tip is a grid vertex)
  const int n = count * kCells;  // grid cells per side
  const double cell = size / count, radius = 0.45 * cell, depth = 0.1 * size;
  const double x0 = base_centre[0] - 0.5 * size, y0 = base_centre[1] - 0.5 * size;
  Mesh mesh = new_mesh(name);
  auto top = [&](int i, int j) { return index(j * (n + 1) + i); };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      // Distance to the tip of this vertex's spike cell (cell boundaries are far from any cone).
      const int ci = std::min(i / kCells, count - 1), cj = std::min(j / kCells, count - 1);
      const double dx = static_cast<double>(i - ci * kCells - kCells / 2) * size / n;
      const double dy = static_cast<double>(j - cj * kCells - kCells / 2) * size / n;
      const double r = std::sqrt(dx * dx + dy * dy);
      const double z = r < radius ? height * (1.0 - r / radius) : 0.0;
      mesh.positions.push_back({x0 + size * i / n, y0 + size * j / n, base_centre[2] + z});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {  // normals up (+z)
      mesh.triangles.push_back({top(i, j), top(i + 1, j), top(i + 1, j + 1)});
      mesh.triangles.push_back({top(i, j), top(i + 1, j + 1), top(i, j + 1)});
    }
  }
  // The top's boundary counter-clockwise seen from above (x up, then y up, then back).
  std::vector<std::uint32_t> rim;
  for (int i = 0; i < n; ++i) rim.push_back(top(i, 0));
  for (int j = 0; j < n; ++j) rim.push_back(top(n, j));
  for (int i = n; i > 0; --i) rim.push_back(top(i, n));
  for (int j = n; j > 0; --j) rim.push_back(top(0, j));
  const std::uint32_t bottom_start = index(mesh.positions.size());
  for (std::uint32_t v : rim) {
    const Vec3& p = mesh.positions[v];
    mesh.positions.push_back({p[0], p[1], base_centre[2] - depth});
  }
  const std::uint32_t bottom_centre = index(mesh.positions.size());
  mesh.positions.push_back({base_centre[0], base_centre[1], base_centre[2] - depth});
  const std::uint32_t m = index(rim.size());
  for (std::uint32_t k = 0; k < m; ++k) {
    const std::uint32_t kn = (k + 1) % m;
    const std::uint32_t a = rim[k], b = rim[kn], c = bottom_start + kn, d = bottom_start + k;
    // Wall quad: the rim runs counter-clockwise, so (a, d, c) and (a, c, b) face outward.
    mesh.triangles.push_back({a, d, c});
    mesh.triangles.push_back({a, c, b});
    mesh.triangles.push_back({bottom_centre, c, d});  // bottom, facing down
  }
  return finish(std::move(mesh));
}

// A cube of resolution^3 cells, its surface projected radially onto an ellipsoid (a torso: 0.9,
// 0.5 and 1.2 times `size` along x, y, z). Removed: the whole -z face (waist), the middle of the
// +z face (neck: x cells [r/4, 3r/4), y cells [r/8, 7r/8)) and the middle of the +-x faces
// (sleeves: y cells [r/8, 7r/8), z cells [r/4, 3r/4)). Vertices are keyed by lattice point, so the
// cube's edges and corners are welded; only vertices of kept triangles exist.
Mesh garment_like(Vec3 centre, double size, int resolution, const std::string& name) {
  if (resolution < 8 || resolution % 8 != 0) {
    throw std::invalid_argument("garment_like: resolution must be a positive multiple of 8");
  }
  const int r = resolution;
  Mesh mesh = new_mesh(name);
  std::map<std::array<int, 3>, std::uint32_t> vertex_of;
  auto vertex = [&](const std::array<int, 3>& lattice) {
    auto it = vertex_of.find(lattice);
    if (it != vertex_of.end()) return it->second;
    const Vec3 q = {static_cast<double>(lattice[0]) / r - 0.5,
                    static_cast<double>(lattice[1]) / r - 0.5,
                    static_cast<double>(lattice[2]) / r - 0.5};
    const double len = norm(q);
    const Vec3 p =
        add(centre, {size * 0.9 * q[0] / len, size * 0.5 * q[1] / len, size * 1.2 * q[2] / len});
    const std::uint32_t id = index(mesh.positions.size());
    mesh.positions.push_back(p);
    vertex_of.emplace(lattice, id);
    return id;
  };
  auto in = [&](int c, int lo8, int hi8) { return c >= lo8 * r / 8 && c < hi8 * r / 8; };
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign : {+1, -1}) {
      // (b, c, outward normal) right-handed.
      int b = (axis + 1) % 3, c = (axis + 2) % 3;
      if (sign < 0) std::swap(b, c);
      for (int q = 0; q < r; ++q) {
        for (int p = 0; p < r; ++p) {
          std::array<int, 3> cellc{};  // the cell's lower lattice corner, for the hole tests
          cellc[axis] = sign > 0 ? r : 0;
          cellc[b] = p;
          cellc[c] = q;
          if (axis == 2 && sign < 0) continue;                                              // waist
          if (axis == 2 && sign > 0 && in(cellc[0], 2, 6) && in(cellc[1], 1, 7)) continue;  // neck
          if (axis == 0 && in(cellc[1], 1, 7) && in(cellc[2], 2, 6)) continue;  // sleeves
          auto corner = [&](int dp, int dq) {
            std::array<int, 3> l = cellc;
            l[b] += dp;
            l[c] += dq;
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
  return finish(std::move(mesh));
}

std::string cow_path() { return UNTANGLE_COW_OFF; }

// ---- named scenes ----

// Yields 1 contour: CL (sheet) / CL (sphere), both separating.
// Sheet (21 x 21, 800 triangles) 0.0137 above the equator of a closed sphere (radius 1): one closed
// contour, CL on the sheet and CL on the sphere; both sides of both tracks hold vertices. The sheet
// is shifted off x = 0 and y = 0 too: there its grid lines would meet the sphere's meridian edges
// exactly (edge touching edge).
Scene sheet_through_sphere() {
  Scene scene;
  scene.name = "sheet_through_sphere";
  scene.movable.push_back(
      grid_sheet(21, 21, {-1.4929, -1.4887, 0.0137}, {3.0, 0.0, 0.0}, {0.0, 3.0, 0.0}, "sheet"));
  scene.obstacles.push_back(obstacle(uv_sphere({0.0, 0.0, 0.0}, 1.0, 24, 16, "sphere")));
  return scene;
}

// Yields 1 contour: BB (strip, separating) / II (sheet).
// Strip (3 x 20 vertices, vertical in the plane y = 0.0137, x in [-0.1437, 0.1563]) through a
// horizontal sheet: the contour runs across the strip's width from one long boundary edge to the
// other (BB on the strip) and lies inside the sheet (II on the sheet).
Scene strip_through_sheet() {
  Scene scene;
  scene.name = "strip_through_sheet";
  scene.movable.push_back(
      grid_sheet(3, 20, {-0.1437, 0.0137, -0.9827}, {0.3, 0.0, 0.0}, {0.0, 0.0, 2.0}, "strip"));
  scene.movable.push_back(
      grid_sheet(21, 21, {-1.0, -1.0, 0.0}, {2.0, 0.0, 0.0}, {0.0, 2.0, 0.0}, "sheet"));
  return scene;
}

// Yields 1 contour: BI (flat) / BI (tilted).
// A unit sheet at z = 0 and a sheet tilted 55 degrees about the line x + y = 1.6137 that starts
// above the first sheet's interior and runs out past its x = 1 edge near the (1, 1) corner: the
// contour runs from the tilted sheet's boundary (inside the flat one) to the flat sheet's boundary
// (inside the tilted one): BI on both.
Scene sheets_corner() {
  Scene scene;
  scene.name = "sheets_corner";
  scene.movable.push_back(
      grid_sheet(21, 21, {0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, "flat"));
  const double s = std::sqrt(0.5), theta = 55.0 * kPi / 180.0, width = 0.6;
  const Vec3 along = {s, -s, 0.0};  // direction of the line
  const Vec3 across = {s * std::cos(theta), s * std::cos(theta), std::sin(theta)};
  const Vec3 start = {0.7137, 0.9, 0.0};  // on x + y = 1.6137, inside the flat sheet
  const Vec3 origin = sub(start, scale(across, 0.4567 * width));
  scene.movable.push_back(
      grid_sheet(17, 13, origin, scale(along, 0.8), scale(across, width), "tilted"));
  return scene;
}

// Yields 1 self-intersection contour: BB / II, both tracks on the ribbon.
// A ribbon (61 x 8 vertices) along the nodal cubic x = t^2 - 1, z = t (t^2 - 1), t in
// [-1.45, 1.5137], which crosses itself at t = -1 and t = 1; the ribbon is narrower at t = -1
// (width 0.85) than at t = 1 (1.15) and lies within it there: one self-intersection contour, BB on
// the narrow part and II on the wide part.
Scene folded_sheet() {
  Scene scene;
  scene.name = "folded_sheet";
  constexpr int kNt = 61, kNv = 8;
  const double t0 = -1.45, t1 = 1.5137;
  Mesh mesh = new_mesh("ribbon");
  for (int j = 0; j < kNv; ++j) {
    for (int i = 0; i < kNt; ++i) {
      const double t = t0 + (t1 - t0) * i / (kNt - 1);
      const double v = static_cast<double>(j) / (kNv - 1);
      const double y = 0.5 + 0.0173 * t + (v - 0.5) * (1.0 + 0.15 * t);
      mesh.positions.push_back({t * t - 1.0, y, t * (t * t - 1.0)});
    }
  }
  for (int j = 0; j + 1 < kNv; ++j) {
    for (int i = 0; i + 1 < kNt; ++i) {
      const std::uint32_t a = index(j * kNt + i), b = a + 1, c = index((j + 1) * kNt + i + 1),
                          d = index((j + 1) * kNt + i);
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  }
  scene.movable.push_back(finish(std::move(mesh)));
  return scene;
}

// Yields 2 contours: BB (tube, non-separating, joining its two loops) / II (capsule).
// An open tube (radius 1, z in [-1, 1], two boundary loops) around a capsule (radius 0.6,
// cylinder length 3) whose axis is 0.7 off the tube's axis and tilted by 0.0937 rad: the capsule
// sticks out of the tube wall along its whole length on one side. Two contours, each running from
// one tube loop to the other: BB on the tube (neither separates the tube alone; together they cut
// out the band inside the capsule), II on the capsule.
Scene tube_around_body() {
  Scene scene;
  scene.name = "tube_around_body";
  scene.movable.push_back(open_tube({0.0, 0.0, 0.0}, 1.0, 2.0, 32, 11, "tube"));
  scene.obstacles.push_back(obstacle(
      tilted(capsule({0.0, 0.0, 0.0}, 0.6, 3.0, 24, 16, "body"), 0.0937, {0.7, 0.0131, 0.0173})));
  return scene;
}

// Yields 2 contours: BB (garment, non-separating, neck loop to sleeve loop) / II (sphere).
// A garment (sphere with four holes: neck, two sleeves, waist; resolution 16) and a sphere
// (radius 0.385) centred on its right shoulder, between the neck hole and the right sleeve hole.
// The sphere covers the rims of both holes where they face each other, so its intersection
// curve is cut by them into two contours (front and back), each running from the neck loop to the
// sleeve loop: BB on the garment (non-separating alone), II on the sphere.
Scene garment_four_loops() {
  Scene scene;
  scene.name = "garment_four_loops";
  scene.movable.push_back(garment_like({0.0, 0.0, 0.0}, 1.0, 16, "garment"));
  // The garment's surface point in the cube direction (1, 0, 1), nudged off the symmetry planes.
  const double s = std::sqrt(0.5);
  const Vec3 shoulder = {0.9 * s + 0.0137, 0.0211, 1.2 * s - 0.0173};
  scene.obstacles.push_back(obstacle(uv_sphere(shoulder, 0.385, 24, 12, "shoulder")));
  return scene;
}

// Yields 9 contours: CL (sheet) / CL (spikes), all separating.
// A sheet (27 x 27) at height 0.2237 over 3 x 3 cone spikes of height 0.6 (one closed obstacle):
// every tip pokes through, nine closed contours, CL on the sheet and CL on the spikes, each
// enclosing vertices of both (the cut radius 0.19 exceeds the sheet's spacing 0.1).
Scene sheet_on_spikes() {
  Scene scene;
  scene.name = "sheet_on_spikes";
  scene.movable.push_back(
      grid_sheet(27, 27, {-1.2863, -1.2929, 0.2237}, {2.6, 0.0, 0.0}, {0.0, 2.6, 0.0}, "sheet"));
  scene.obstacles.push_back(obstacle(cone_spikes({0.0, 0.0, 0.0}, 2.0, 3, 0.6, "spikes")));
  return scene;
}

// Yields 4 contours: BB (panel) / II (body), one across each corner.
// A square panel at height 0.0137 through a closed sphere of radius 1. At side 1.8 the middle of
// the panel, most of its area, is inside the body; only its four corners stick out. "The smaller
// region is illegal" would push the corners in; the body's inside says the middle is illegal.
// Vertices about 0.05 apart at every side (37 x 37 at the default 1.8).
Scene panel_in_body(double side) {
  Scene scene;
  scene.name = "panel_in_body";
  const int n = static_cast<int>(std::lround(side / 0.05)) + 1;
  scene.movable.push_back(grid_sheet(n, n, {-0.5 * side - 0.0029, -0.5 * side + 0.0013, 0.0137},
                                     {side, 0.0, 0.0}, {0.0, side, 0.0}, "panel"));
  scene.obstacles.push_back(obstacle(uv_sphere({0.0, 0.0, 0.0}, 1.0, 48, 24, "body")));
  return scene;
}

// Yields >= 1 contour between sheet and cow, all CL (sheet) / CL (cow).
// The cow (closed) cut across the middle of its longest bounding-box axis by an n x n sheet 1.2
// times the box in the other two axes: only closed contours, CL on the sheet and CL on the cow.
Scene sheet_through_cow(int n) {
  const std::string path = cow_path();
  if (path.empty()) throw std::runtime_error("sheet_through_cow: the cow (libcgal-demo) is absent");
  Scene scene;
  scene.name = "sheet_through_cow";
  for (Mesh& mesh : read_meshes(path, Role::kObstacle)) scene.obstacles.push_back(std::move(mesh));
  Vec3 lo = scene.obstacles.front().positions.front(), hi = lo;
  for (const Mesh& mesh : scene.obstacles) {
    for (const Vec3& p : mesh.positions) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    }
  }
  const Vec3 extent = sub(hi, lo), middle = scale(add(lo, hi), 0.5);
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (extent[k] > extent[axis]) axis = k;
  }
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  Vec3 origin = middle, u{}, v{};
  origin[axis] += 0.0137 * extent[axis];
  origin[b] -= 0.6 * extent[b] - 0.0071 * extent[b];
  origin[c] -= 0.6 * extent[c] - 0.0053 * extent[c];
  u[b] = 1.2 * extent[b];
  v[c] = 1.2 * extent[c];
  scene.movable.push_back(grid_sheet(n, n, origin, u, v, "sheet"));
  return scene;
}

Scene sheet_over_cow_rump(double y, int n) {
  const std::string path = cow_path();
  if (path.empty()) throw std::runtime_error("sheet_over_cow_rump: the cow (libcgal-demo) is absent");
  Scene scene;
  scene.name = "sheet_over_cow_rump";
  for (Mesh& mesh : read_meshes(path, Role::kObstacle)) scene.obstacles.push_back(std::move(mesh));
  // The cow spans x -0.5 (tail) to 0.5 (head), z -0.163 to 0.163; the sheet reaches from behind
  // the tail to the middle of the back, where the back is lower than the rump.
  scene.movable.push_back(grid_sheet(n, n, {-0.5513, y, -0.2037}, {0.6024, 0.0, 0.0},
                                     {0.0, 0.0, 0.4048}, "sheet"));
  return scene;
}

Scene sheet_through_capsule(int n) {
  Scene scene;
  scene.name = "sheet_through_capsule_" + std::to_string(n);
  // 0.0137 above the middle ring of the cylinder, shifted off the capsule's meridian planes.
  scene.movable.push_back(
      grid_sheet(n, n, {-1.4929, -1.4887, 0.0137}, {3.0, 0.0, 0.0}, {0.0, 3.0, 0.0}, "sheet"));
  scene.obstacles.push_back(obstacle(capsule({0.0, 0.0, 0.0}, 0.6, 1.6, 48, 17, "capsule")));
  return scene;
}

std::vector<Scene> named_scenes() {
  return {sheet_through_sphere(), strip_through_sheet(), sheets_corner(),  folded_sheet(),
          tube_around_body(),     garment_four_loops(),  sheet_on_spikes()};
}

std::vector<Mesh> scene_meshes(const Scene& scene) {
  std::vector<Mesh> meshes = scene.movable;
  for (const Mesh& mesh : scene.obstacles) {
    meshes.push_back(mesh);
    meshes.back().role = Role::kObstacle;
  }
  return meshes;
}

std::vector<Mesh> scaled_about_centre(std::vector<Mesh> meshes, double factor) {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Mesh& m : meshes) {
    for (const Vec3& p : m.positions) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    }
  }
  const Vec3 centre = scale(add(lo, hi), 0.5);
  for (Mesh& m : meshes)
    for (Vec3& p : m.positions) p = add(centre, scale(sub(p, centre), factor));
  return meshes;
}

std::vector<std::pair<std::string, std::string>> garment_body_pairs_in(
    const std::string& garments, const std::string& bodies, std::vector<std::string>& notes) {
  namespace fs = std::filesystem;
  std::vector<std::pair<std::string, std::string>> pairs;  // garment path, body path
  for (const fs::directory_entry& entry : fs::directory_iterator(garments)) {
    const fs::path& p = entry.path();
    if (!entry.is_regular_file() || p.extension() != ".obj") continue;
    const std::string stem = p.stem().string();
    const std::size_t underscore = stem.find('_');
    if (underscore == std::string::npos || stem.substr(underscore) == "_generic") continue;
    const fs::path body = fs::path(bodies) / (stem.substr(0, underscore) + "_generic.obj");
    if (!fs::is_regular_file(body)) {
      notes.push_back(p.string() + ": no body " + body.string() + ", left out");
      continue;
    }
    pairs.emplace_back(p.string(), body.string());
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<std::pair<std::string, std::string>> garment_body_pairs(const std::string& dir,
                                                                    std::vector<std::string>& notes) {
  namespace fs = std::filesystem;
  const fs::path garments_dir = fs::path(dir) / "garments";
  const fs::path bodies_dir = fs::path(dir) / "bodies";
  if (!fs::is_directory(garments_dir) || !fs::is_directory(bodies_dir)) {
    throw Error(ExitCode::kUnreadableInput, dir,
                "no garments/ and bodies/ folders (expected garments/<prefix>_*.obj and "
                "bodies/<prefix>_generic.obj)");
  }
  auto pairs = garment_body_pairs_in(garments_dir.string(), bodies_dir.string(), notes);
  if (pairs.empty()) {
    throw Error(ExitCode::kUnreadableInput, dir,
                "no garments/<prefix>_*.obj with a matching bodies/<prefix>_generic.obj");
  }
  return pairs;
}

Scene sewn_garment(bool dent, bool repeated) {
  constexpr double kRadius = 0.5, kLength = 2.0;
  constexpr int kSlices = 24, kRings = 9;
  // The body's cylinder ring i lies at z = length * (0.5 - i / (rings - 1)) (capsule); rings 2
  // and 6 are the seams, computed by the same expression so that the positions agree bit for bit.
  auto ring_z = [](int i) { return kLength * (0.5 - static_cast<double>(i) / (kRings - 1)); };
  Scene scene;
  scene.name = std::string("sewn_garment") + (dent ? "_dent" : "") + (repeated ? "_repeated" : "");
  scene.obstacles.push_back(obstacle(capsule({0, 0, 0}, kRadius, kLength, kSlices, kRings, "body")));
  std::vector<std::pair<double, double>> profile{{kRadius, ring_z(2)}};
  constexpr int kInner = 9;  // rings between the seams, 0.1 apart
  for (int k = 1; k <= kInner; ++k) profile.emplace_back(0.58, ring_z(2) - 0.1 * k);
  profile.emplace_back(kRadius, ring_z(6));
  Mesh garment = revolve({0, 0, 0}, profile, kSlices, "garment");
  if (dent) {
    const std::size_t middle = static_cast<std::size_t>(kSlices) * 5;  // ring 5, z = 0
    for (std::size_t j = 0; j < 4; ++j) {
      Vec3& p = garment.positions[middle + j];
      p = {p[0] * 0.46 / 0.58, p[1] * 0.46 / 0.58, p[2]};
    }
  }
  scene.movable.push_back(std::move(garment));
  if (repeated) {
    for (std::vector<Mesh>* list : {&scene.movable, &scene.obstacles}) {
      for (Mesh& mesh : *list) {
        const std::size_t n = mesh.triangles.size();
        for (std::size_t t = 0; t < n; ++t) {
          const Triangle tri = mesh.triangles[t];
          mesh.triangles.push_back({tri[0], tri[2], tri[1]});
        }
        mesh = finish(std::move(mesh));
      }
    }
  }
  return scene;
}

Scene rotated_scene(Scene scene, Vec3 angles) {
  for (std::vector<Mesh>* list : {&scene.movable, &scene.obstacles}) {
    for (Mesh& mesh : *list) {
      for (Vec3& p : mesh.positions) {
        for (int axis = 0; axis < 3; ++axis) {
          const double c = std::cos(angles[axis]), s = std::sin(angles[axis]);
          const int u = (axis + 1) % 3, v = (axis + 2) % 3;
          const double pu = p[u], pv = p[v];
          p[u] = c * pu - s * pv;
          p[v] = s * pu + c * pv;
        }
      }
    }
  }
  scene.name += "_rotated";
  return scene;
}

void write_obj(const Mesh& mesh, const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) throw Error(ExitCode::kOutputNotWritten, path, "cannot open for writing");
  std::fprintf(file, "# untangle test scene mesh '%s': %zu vertices, %zu triangles\n",
               mesh.name.c_str(), mesh.positions.size(), mesh.triangles.size());
  for (const Vec3& p : mesh.positions)
    std::fprintf(file, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
  for (const Triangle& t : mesh.triangles) {
    std::fprintf(file, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
  }
  const bool ok = std::ferror(file) == 0;
  if (std::fclose(file) != 0 || !ok) {
    throw Error(ExitCode::kOutputNotWritten, path, "write failed");
  }
}

SceneFiles write_scene_files(const Scene& scene, const std::string& folder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) throw Error(ExitCode::kOutputNotWritten, folder, "cannot create folder: " + ec.message());
  SceneFiles files;
  for (std::size_t i = 0; i < scene.movable.size(); ++i) {
    files.movable.push_back(folder + "/movable_" + std::to_string(i) + ".obj");
    write_obj(scene.movable[i], files.movable.back());
  }
  for (std::size_t i = 0; i < scene.obstacles.size(); ++i) {
    files.obstacles.push_back(folder + "/obstacle_" + std::to_string(i) + ".obj");
    write_obj(scene.obstacles[i], files.obstacles.back());
  }
  return files;
}

}  // namespace untangle::scenes
