// Generated scenes for self-intersections, loop vertices and layered garments (issue 4).
#include "scenes/self_scenes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <stdexcept>
#include <utility>

namespace untangle::scenes {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::uint32_t index(std::size_t i) { return static_cast<std::uint32_t>(i); }

Mesh finish(Mesh mesh) {
  mesh.polygon.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) mesh.polygon[t] = index(t);
  mesh.source_faces = mesh.triangles.size();
  return mesh;
}

// Makes the orientation of every connected part agree with its first triangle: a neighbour that
// runs a shared edge in the same direction is flipped (the generators glue patches whose own
// orientations need not match along the fold).
void orient_consistently(Mesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> faces_of_edge;
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      faces_of_edge[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  }
  auto runs = [&](std::uint32_t t, std::uint32_t a, std::uint32_t b) {
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[t][k] == a && mesh.triangles[t][(k + 1) % 3] == b) return true;
    return false;
  };
  std::vector<std::uint8_t> done(mesh.triangles.size(), 0);
  for (std::uint32_t seed = 0; seed < mesh.triangles.size(); ++seed) {
    if (done[seed]) continue;
    done[seed] = 1;
    std::vector<std::uint32_t> stack{seed};
    while (!stack.empty()) {
      const std::uint32_t t = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
        for (std::uint32_t u : faces_of_edge[{std::min(a, b), std::max(a, b)}]) {
          if (done[u]) continue;
          done[u] = 1;
          if (runs(u, a, b)) std::swap(mesh.triangles[u][1], mesh.triangles[u][2]);
          stack.push_back(u);
        }
      }
    }
  }
}

// Builds a mesh from grid patches; vertices with identical positions are one vertex, which is how
// patches are glued along a fold (both compute the fold's positions with the same expression).
class Builder {
 public:
  explicit Builder(const std::string& name) {
    mesh_.name = name;
    mesh_.role = Role::kMovable;
  }
  std::uint32_t vertex(const Vec3& p) {
    const auto [it, inserted] = index_.emplace(p, index(mesh_.positions.size()));
    if (inserted) mesh_.positions.push_back(p);
    return it->second;
  }
  // A grid patch of (rows) x (columns) vertices at pos(r, c), "union jack": each quad is split
  // along the diagonal through its corner with (r + c + parity) even (a hub with eight neighbours;
  // the other vertices have four).
  void patch(int rows, int columns, int parity, const std::function<Vec3(int, int)>& pos) {
    for (int r = 0; r + 1 < rows; ++r) {
      for (int c = 0; c + 1 < columns; ++c) {
        const std::uint32_t p00 = vertex(pos(r, c)), p10 = vertex(pos(r + 1, c)),
                            p11 = vertex(pos(r + 1, c + 1)), p01 = vertex(pos(r, c + 1));
        if ((r + c + parity) % 2 == 0) {
          mesh_.triangles.push_back({p00, p10, p11});
          mesh_.triangles.push_back({p00, p11, p01});
        } else {
          mesh_.triangles.push_back({p00, p10, p01});
          mesh_.triangles.push_back({p10, p11, p01});
        }
      }
    }
  }
  Mesh finish() {
    orient_consistently(mesh_);
    return scenes::finish(std::move(mesh_));
  }

 private:
  Mesh mesh_;
  std::map<Vec3, std::uint32_t> index_;
};

// ---- the Wicke configurations: a base in z = 0, x in [-2, 0], y in [-1.5, 1.5] (5 x 7 vertices,
// spacing 1/2), folded along its edge x = 0 into flaps that lie back over it ----

Vec3 base_point(int i, int j) { return {-2.0 + 0.5 * i, -1.5 + 0.5 * j, 0.0}; }

void add_base(Builder& b) {
  b.patch(5, 7, 0, [](int i, int j) { return base_point(i, j); });
}

// A flap on the fold x = 0 over fold rows [j0, j1], columns k = 0 (the fold) .. columns - 1, at
// height z(j, k) and sheared by `slide` along y per column.
void add_flap(Builder& b, int j0, int j1, int columns, int parity, double slide,
              const std::function<double(int, int)>& z) {
  b.patch(j1 - j0 + 1, columns, parity, [&](int r, int k) -> Vec3 {
    const int j = j0 + r;
    if (k == 0) return base_point(4, j);
    return {-0.4373 * k + 0.0231 * k * (j - 3), -1.5 + 0.5 * j + slide * k, z(j, k)};
  });
}

// Column heights of a flap that rises and then dives through the base between columns 2 and 3.
double diving(int k) {
  static constexpr double kHeights[] = {0.0, 0.2813, 0.1563, -0.3437};
  return kHeights[k];
}

}  // namespace

// ---- mesh operations ----

Mesh subdivide_midpoint(const Mesh& mesh) {
  Mesh out = mesh;
  out.triangles.clear();
  out.polygon.clear();
  out.triangle_group.clear();
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
  auto mid = [&](std::uint32_t a, std::uint32_t b) {
    const std::pair<std::uint32_t, std::uint32_t> key{std::min(a, b), std::max(a, b)};
    const auto it = midpoint.find(key);
    if (it != midpoint.end()) return it->second;
    const Vec3& p = mesh.positions[key.first];
    const Vec3& q = mesh.positions[key.second];
    const std::uint32_t id = index(out.positions.size());
    out.positions.push_back({0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])});
    midpoint.emplace(key, id);
    return id;
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto [a, b, c] = mesh.triangles[t];
    const std::uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    const Triangle children[4] = {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}};
    for (const Triangle& child : children) {
      out.triangles.push_back(child);
      if (t < mesh.polygon.size()) out.polygon.push_back(mesh.polygon[t]);
      if (t < mesh.triangle_group.size()) out.triangle_group.push_back(mesh.triangle_group[t]);
    }
  }
  return out;
}

Mesh subdivide_midpoint(const Mesh& mesh, int levels) {
  Mesh out = mesh;
  for (int level = 0; level < levels; ++level) out = subdivide_midpoint(out);
  return out;
}

Mesh permuted(const Mesh& mesh, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  // Fisher-Yates with the raw generator output: the same permutation on every standard library.
  auto shuffled = [&](std::size_t n) {
    std::vector<std::uint32_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = index(i);
    for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[random() % i]);
    return order;
  };
  const std::vector<std::uint32_t> new_of_old = shuffled(mesh.positions.size());
  const std::vector<std::uint32_t> face_order = shuffled(mesh.triangles.size());
  Mesh out = mesh;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    out.positions[new_of_old[v]] = mesh.positions[v];
  }
  for (std::size_t t = 0; t < face_order.size(); ++t) {
    const std::uint32_t old = face_order[t];
    const Triangle& tri = mesh.triangles[old];
    const std::size_t first = random() % 3;  // rotating the corners keeps the orientation
    for (std::size_t k = 0; k < 3; ++k) out.triangles[t][k] = new_of_old[tri[(first + k) % 3]];
    if (old < mesh.polygon.size()) out.polygon[t] = mesh.polygon[old];
    if (old < mesh.triangle_group.size()) out.triangle_group[t] = mesh.triangle_group[old];
  }
  return out;
}

Mesh merged(const Mesh& a, const Mesh& b, const std::string& name) {
  Mesh out = a;
  out.name = name;
  out.group_names.clear();
  out.triangle_group.clear();
  const std::uint32_t offset = index(a.positions.size());
  out.positions.insert(out.positions.end(), b.positions.begin(), b.positions.end());
  for (const Triangle& t : b.triangles)
    out.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return finish(std::move(out));
}

Mesh rotated(Mesh mesh, int axis, double angle, Vec3 offset) {
  const double c = std::cos(angle), s = std::sin(angle);
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  for (Vec3& p : mesh.positions) {
    const double pu = p[u], pv = p[v];
    p[u] = c * pu - s * pv;
    p[v] = s * pu + c * pv;
    for (int k = 0; k < 3; ++k) p[k] += offset[k];
  }
  return mesh;
}

// ---- the Wicke configurations ----

const char* to_string(WickeCase c) {
  switch (c) {
    case WickeCase::kClosed:
      return "closed";
    case WickeCase::kBoundaryBoundary:
      return "boundary_boundary";
    case WickeCase::kBoundaryInterior:
      return "boundary_interior";
    case WickeCase::kLoopVertex:
      return "loop_vertex";
    case WickeCase::kCrossing:
      return "crossing_contours";
    case WickeCase::kFigureEight:
      return "figure_eight";
    case WickeCase::kLoopToLoop:
      return "loop_to_loop";
  }
  return "?";
}

std::vector<WickeCase> all_wicke_cases() {
  return {WickeCase::kClosed,     WickeCase::kBoundaryBoundary, WickeCase::kBoundaryInterior,
          WickeCase::kLoopVertex, WickeCase::kCrossing,         WickeCase::kFigureEight,
          WickeCase::kLoopToLoop};
}

Mesh wicke_scene(WickeCase c) {
  Builder b(std::string("wicke_") + to_string(c));
  add_base(b);
  const double rising = 0.2813;  // flap height per column above the base
  switch (c) {
    case WickeCase::kClosed:
      // (a) Closed contour: a flap over the whole fold, 3 columns; its vertex (3, 2), two columns
      // from the fold (four neighbours, none on the fold), pushed below the base. The flap's bump
      // passes through the base: one closed contour, CL on the flap around the vertex, CL on the
      // base.
      add_flap(b, 0, 6, 4, 0, 0.0391,
               [&](int j, int k) { return j == 3 && k == 2 ? -0.2031 : rising * k; });
      break;
    case WickeCase::kBoundaryBoundary:
      // (b) Boundary to boundary on one part, interior ends on the other: a flap over fold rows
      // 2..4 only (narrower than the base) rises and then dives through the base between its
      // columns 2 and 3. The contour runs across the flap from one side edge to the other (BB on
      // the flap) and ends where those side edges pierce the base (II on the base).
      add_flap(b, 2, 4, 4, 0, 0.0391, [](int, int k) { return diving(k); });
      break;
    case WickeCase::kBoundaryInterior:
      // (c) Boundary to interior on both: the diving flap over fold rows 3..5, sheared toward +y
      // so that where it dives it sticks out past the base's edge y = 1.5. The contour runs from
      // the flap's side edge (inside the base) to the base's edge (inside the flap): BI / BI.
      add_flap(b, 3, 5, 4, 0, 0.3437, [](int, int k) { return diving(k); });
      break;
    case WickeCase::kLoopVertex:
      // (d) Contour through a loop vertex: the flap (2 columns, all fold rows) lies above the
      // base for rows 0..2 and below it for rows 3..6: the fold passes 180 degrees between rows 2
      // and 3. The flap triangle (fold 2, flap (3, 1), flap (2, 1)) shares fold vertex 2 with the
      // base triangles it crosses: the contour starts at that loop vertex and runs across the
      // flap to its outer edge.
      add_flap(b, 0, 6, 3, 0, 0.0391,
               [&](int j, int k) { return j <= 2 ? rising * k : -0.1719 * k; });
      break;
    case WickeCase::kCrossing:
      // (e) Two contours crossing each other: the diving flap of (b) on the fold x = 0 and a
      // second diving flap on the base's edge y = 1.5 (columns 1..3) folded back toward -y. Each
      // dives through the base, and they dive through each other: the contours of the two flaps
      // with the base cross on the base (a triple point, where the flaps' own contour passes too).
      add_flap(b, 2, 4, 4, 0, 0.0391, [](int, int k) { return diving(k); });
      b.patch(3, 5, 0, [](int r, int k) -> Vec3 {
        static constexpr double kHeights[] = {0.0, 0.3437, 0.2187, 0.0937, -0.4063};
        const int i = 1 + r;
        if (k == 0) return base_point(i, 6);
        return {-2.0 + 0.5 * i + 0.0391 * k, 1.5 - 0.4373 * k + 0.0231 * k * (i - 2), kHeights[k]};
      });
      break;
    case WickeCase::kFigureEight:
      // (f) Figure-eight: the flap (2 columns) with its vertex (3, 1) pushed below the base; in
      // this triangulation (parity 1) that vertex has four neighbours, one of them fold vertex 3.
      // Its two triangles at the fold vertex cross the base from there: one contour leaves fold
      // vertex 3, goes round the pushed vertex and returns to fold vertex 3; its tracks are two
      // loops through that vertex.
      add_flap(b, 0, 6, 3, 1, 0.0391,
               [&](int j, int k) { return j == 3 && k == 1 ? -0.1719 : rising * k; });
      break;
    case WickeCase::kLoopToLoop:
      // (g) Loop to loop: as (f) but with parity 0, where vertex (3, 1) is a hub with eight
      // neighbours, among them fold vertices 2, 3 and 4. The triangles on fold 2 and fold 4 cross
      // the base: one contour from loop vertex 2 round the pushed vertex to loop vertex 4.
      add_flap(b, 0, 6, 3, 0, 0.0391,
               [&](int j, int k) { return j == 3 && k == 1 ? -0.1719 : rising * k; });
      break;
  }
  return b.finish();
}

// ---- larger self-intersections ----

Mesh folded_through_itself(int nt, int ny) {
  if (nt < 3 || ny < 2) throw std::invalid_argument("folded_through_itself: too few vertices");
  Builder b("folded_sheet");
  const double t0 = -1.45, t1 = 1.5137;
  b.patch(nt, ny, 0, [&](int i, int j) -> Vec3 {
    const double t = t0 + (t1 - t0) * i / (nt - 1);
    const double y = -1.0 + 2.0 * j / (ny - 1);
    // Narrower at t = -1 than at t = 1, so one part's side edges end inside the other part.
    return {t * t - 1.0, y * (1.0 + 0.08 * t) + 0.0173 * t, t * (t * t - 1.0) * (1.0 + 0.25 * y)};
  });
  return b.finish();
}

Mesh spiral_roll(int columns, int rows) {
  if (columns < 4 || rows < 2) throw std::invalid_argument("spiral_roll: too few vertices");
  Builder b("spiral");
  b.patch(columns, rows, 0, [&](int i, int j) -> Vec3 {
    const double theta = 6.0 * kPi * i / (columns - 1) + 0.0731;
    const double z = -1.0 + 2.0 * j / (rows - 1) + 0.0113;
    // Turns 0.16 apart; the wobble changes sign from one turn to the next (2.5 periods per turn)
    // and is strongest at mid-height, so neighbouring turns cross in closed patches.
    const double r =
        0.5 + 0.16 * theta / (2.0 * kPi) + 0.14 * std::sin(2.5 * theta + 0.3) * (1.0 - 0.8 * z * z);
    return {r * std::cos(theta), r * std::sin(theta), z};
  });
  return b.finish();
}

Mesh pinched_tube(int slices, int rings) {
  Mesh tube = open_tube({0.0, 0.0, 0.0}, 1.0, 3.0, slices, rings, "pinched_tube");
  for (Vec3& p : tube.positions) {
    const double phi = std::atan2(p[1], p[0]) - 0.0731;
    const double c = std::cos(phi);
    if (c <= 0.0) continue;
    const double dz = p[2] - 0.0437;
    p[0] -= 2.4 * c * c * c * c * std::exp(-dz * dz / 0.18);
  }
  return tube;
}

// ---- layers and obstacles ----

namespace {

// Scales each vertex's distance from the z axis to radius(phi, z).
Mesh with_radius(Mesh mesh, const std::function<double(double, double)>& radius) {
  for (Vec3& p : mesh.positions) {
    const double rho = std::hypot(p[0], p[1]);
    const double phi = std::atan2(p[1], p[0]);
    const double s = radius(phi, p[2]) / rho;
    p[0] *= s;
    p[1] *= s;
  }
  return mesh;
}

// A smooth dent centred at (phi0, z0) on the unit cylinder, 1 at the centre.
double dent(double phi, double z, double phi0, double z0) {
  const double d = std::remainder(phi - phi0, 2.0 * kPi);
  const double sigma = 0.45;
  return std::exp(-(d * d + (z - z0) * (z - z0)) / (sigma * sigma));
}

}  // namespace

Scene three_layers(int slices, int rings) {
  Scene scene;
  scene.name = "three_layers";
  scene.movable.push_back(with_radius(
      open_tube({0.0, 0.0, 0.0}, 1.0, 2.4, slices, rings, "dress"), [](double phi, double z) {
        return 1.0 - 0.17 * dent(phi, z, 0.23, -0.31)  // to 0.83: through the t-shirt only
               - 0.36 * dent(phi, z, 3.6, 0.47);       // to 0.64: through t-shirt and body
      }));
  scene.movable.push_back(with_radius(
      open_tube({0.0, 0.0, 0.0}, 0.9, 2.0, slices, rings, "t-shirt"),
      [](double phi, double z) { return 0.9 - 0.25 * dent(phi, z, 1.9, 0.35); }));  // to 0.65
  Mesh body = capsule({0.0, 0.0, 0.0}, 0.8, 2.4, slices, rings, "body");
  body.role = Role::kObstacle;
  scene.obstacles.push_back(body);
  return scene;
}

Scene interleaved_layers(int slices, int rings) {
  Scene scene;
  scene.name = "interleaved_layers";
  // The dress is 0.002 outside the t-shirt on average; its gentle wobble (0.01, slopes under
  // 10 degrees) takes about two fifths of it inside, in patches all over.
  scene.movable.push_back(with_radius(
      open_tube({0.0, 0.0, 0.0}, 0.9, 2.2, slices, rings, "dress"), [](double phi, double z) {
        const double w = kPi * z / 2.2;
        return 0.902 + 0.01 * (0.6 * std::sin(6.0 * phi + 0.37) * std::sin(4.0 * w + 0.21) +
                               0.4 * std::sin(9.0 * phi + 1.1) * std::sin(6.0 * w + 0.7));
      }));
  // The t-shirt: other vertex counts, so that no vertex of one lies on the other.
  scene.movable.push_back(open_tube({0.0, 0.0, 0.0}, 0.9, 2.0, slices - 7, rings - 3, "t-shirt"));
  Mesh body = capsule({0.0, 0.0, 0.0}, 0.8, 2.4, slices, rings, "body");
  body.role = Role::kObstacle;
  scene.obstacles.push_back(body);
  return scene;
}

Scene turned_down_collar(int slices, int band_rings) {
  if (slices < 3 || band_rings < 2) throw std::invalid_argument("turned_down_collar: too few vertices");
  Scene scene;
  scene.name = "turned_down_collar";
  // The dress's rings from its collar's hem (z = 0.55) up to the fold and down its band: z of each.
  const int collar_rings = std::max(2, band_rings / 5);
  std::vector<double> ring_z;
  for (int i = 0; i < collar_rings; ++i) ring_z.push_back(0.55 + 0.38 * i / (collar_rings - 1));
  for (int i = 0; i < band_rings; ++i) ring_z.push_back(0.95 - 2.0 * i / (band_rings - 1));
  const int rings = static_cast<int>(ring_z.size());
  Mesh dress = open_tube({0.0, 0.0, 0.0}, 1.0, 1.0, slices, rings, "dress");
  for (int r = 0; r < rings; ++r) {
    for (int j = 0; j < slices; ++j) {
      Vec3& p = dress.positions[static_cast<std::size_t>(r) * slices + j];
      const double phi = std::atan2(p[1], p[0]);
      const double z = ring_z[r];
      double rho = 0.0;
      if (r < collar_rings) {
        // The collar is pressed onto the band, 0.004 outside it on average, and wobbles by as
        // much: over the sharp fold its triangles cross the band's through shared vertices.
        rho = 0.906 + 0.004 * std::sin(7.0 * phi + 0.9);
      } else {
        // The band wobbles round the t-shirt as interleaved_layers' dress does.
        const double w = kPi * z / 2.2;
        rho = 0.902 + 0.01 * (0.6 * std::sin(6.0 * phi + 0.37) * std::sin(4.0 * w + 0.21) +
                              0.4 * std::sin(9.0 * phi + 1.1) * std::sin(6.0 * w + 0.7));
      }
      p = {rho * std::cos(phi), rho * std::sin(phi), z};
    }
  }
  scene.movable.push_back(std::move(dress));
  // The t-shirt reaches under the collar; other vertex counts than the dress.
  scene.movable.push_back(
      open_tube({0.0, 0.0, -0.05}, 0.9, 1.9, slices - 7, band_rings - 3, "t-shirt"));
  Mesh body = capsule({0.0, 0.0, 0.0}, 0.8, 2.4, slices, band_rings, "body");
  body.role = Role::kObstacle;
  scene.obstacles.push_back(body);
  return scene;
}

Mesh self_intersecting_obstacle(int slices) {
  const Mesh along_y =
      rotated(capsule({0.0, 0.0, 0.0}, 0.5, 1.6, slices, 9, "a"), 0, 0.5 * kPi, {0.0, 0.0, 0.0});
  const Mesh along_x = rotated(capsule({0.0, 0.0, 0.0}, 0.45, 1.4, slices, 9, "b"), 1, 0.5 * kPi,
                               {0.31, 0.23, 0.07});
  Mesh both = merged(along_y, along_x, "two_capsules");
  both.role = Role::kObstacle;
  return both;
}

}  // namespace untangle::scenes
