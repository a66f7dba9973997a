// Projective dynamics for the cloth: the global matrix factored once, a local projection of each
// spring per iteration.
#include "sim/cloth_model.h"

#include <algorithm>
#include <cmath>

#include "geometry/ldlt_columns.h"
#include "geometry/vec3.h"
#include "untangle/error.h"

namespace untangle {
namespace {

// Rings of particles round a face plane's corners that its lift moves with them, by 3/4, 1/2
// and 1/4 of it. On the cow (with the cloth's thickness) the frames' largest edge ratio over
// frames 17 to 19 was 2.98, 3.25 and 4.32 with the corners lifted alone, 2.14, 2.21 and 1.82 with
// the rings (docs/PERFORMANCE.md, *The cow: the horns*).
constexpr int kFaceRings = 3;

}  // namespace

void build_cloth_model(const std::vector<Mesh>& meshes, const PinMask& pins,
                       const ClothOptions& options, ClothModel& model) {
  std::vector<Mesh> cloth;
  for (std::uint32_t m = 0; m < meshes.size(); ++m)
    if (meshes[m].role == Role::kMovable) {
      cloth.push_back(meshes[m]);
      model.cloth_mesh.push_back(m);
    }
  model.topo = build_topology(cloth);
  const SceneTopology& topo = model.topo;
  const std::size_t n = topo.points.size();
  if (topo.tris.empty())
    throw Error(ExitCode::kUnreadableInput, "", "the scene has no cloth triangles to simulate");
  // Lumped masses: a third of each triangle's area to each corner.
  model.mass.assign(n, 0.0);
  for (const auto& tri : topo.tris) {
    const double a = triangle_area(topo.points[tri[0]], topo.points[tri[1]], topo.points[tri[2]]);
    for (std::uint32_t v : tri) model.mass[v] += options.density * a / 3.0;
  }
  double mean_mass = 0.0;
  for (double m : model.mass) mean_mass += m;
  mean_mass /= static_cast<double>(n);
  for (double& m : model.mass)
    if (!(m > 0.0)) m = mean_mass > 0.0 ? mean_mass : 1.0;  // isolated or degenerate corners
  model.pinned.assign(n, 0);
  for (std::size_t k = 0; k < model.cloth_mesh.size(); ++k) {
    const std::uint32_t m = model.cloth_mesh[k];
    if (m >= pins.size()) continue;
    for (std::size_t i = 0; i < pins[m].size() && i < topo.welded[k].size(); ++i)
      if (pins[m][i]) model.pinned[topo.welded[k][i]] = 1;
  }
  model.unknown.assign(n, kNone);
  std::uint32_t free_count = 0;
  for (std::uint32_t v = 0; v < n; ++v)
    if (!model.pinned[v]) model.unknown[v] = free_count++;

  // Springs: every edge (stretch and shear), and across every edge with two faces the distance
  // between the two opposite corners (bending).
  auto add_spring = [&](std::uint32_t a, std::uint32_t b, double stiffness, bool stretch) {
    const double rest = norm(sub(topo.points[a], topo.points[b]));
    if (!(rest > 0.0)) return;
    const double weight = stiffness * 0.5 * (model.mass[a] + model.mass[b]);
    model.springs.push_back({a, b, rest, weight, stretch});
  };
  for (const auto& e : topo.edges) add_spring(e[0], e[1], options.stretch, true);
  for (const ClothModel::Spring& sp : model.springs) model.mean_edge += sp.rest;
  if (!model.springs.empty()) model.mean_edge /= static_cast<double>(model.springs.size());
  if (options.bend > 0.0) {
    for (std::uint32_t e = 0; e < topo.edges.size(); ++e) {
      if (topo.edge_face_count(e) != 2) continue;
      std::uint32_t opposite[2];
      for (int k = 0; k < 2; ++k) {
        const auto& tri = topo.tris[topo.edge_faces[topo.edge_face_begin[e] + k]];
        opposite[k] = tri[0];
        for (std::uint32_t v : tri)
          if (v != topo.edges[e][0] && v != topo.edges[e][1]) opposite[k] = v;
      }
      if (opposite[0] != opposite[1]) add_spring(opposite[0], opposite[1], options.bend, false);
    }
  }

  // M + sum w A^T A over the free particles (the system of all three coordinates is the same).
  std::vector<Eigen::Triplet<double>> entries;
  for (std::uint32_t v = 0; v < n; ++v)
    if (model.unknown[v] != kNone)
      entries.emplace_back(model.unknown[v], model.unknown[v], model.mass[v]);
  for (const ClothModel::Spring& s : model.springs) {
    const std::uint32_t ia = model.unknown[s.a], ib = model.unknown[s.b];
    if (ia != kNone) entries.emplace_back(ia, ia, s.weight);
    if (ib != kNone) entries.emplace_back(ib, ib, s.weight);
    if (ia != kNone && ib != kNone) {
      entries.emplace_back(ia, ib, -s.weight);
      entries.emplace_back(ib, ia, -s.weight);
    }
  }
  if (free_count == 0) return;  // everything pinned: nothing moves
  Eigen::SparseMatrix<double> matrix(free_count, free_count);
  matrix.setFromTriplets(entries.begin(), entries.end());
  model.solver.compute(matrix);
  if (model.solver.info() != Eigen::Success)
    throw Error(ExitCode::kUnreadableInput, "", "the cloth's system matrix cannot be factored");
  model.factored = true;
}

void integrate_step(const ClothModel& model, const ClothOptions& options, double h,
                    std::vector<Vec3>& x, const std::vector<Vec3>& v,
                    const ContactSet& contacts, std::vector<std::uint32_t>* touching) {
  const std::size_t n = x.size();
  if (!model.factored) return;
  // The inertial target s = x + h v + h^2 g; pinned particles stay.
  std::vector<Vec3> s(n);
  for (std::size_t i = 0; i < n; ++i)
    s[i] = model.pinned[i] ? x[i] : add(add(x[i], scale(v[i], h)), scale(options.gravity, h * h));
  std::vector<Vec3> now = s;
  const auto free_count = static_cast<std::size_t>(model.solver.rows());
  std::vector<std::array<double, 3>> rhs(free_count);  // one row per unknown: x, y, z
  if (touching) touching->assign(n, 0);
  std::vector<int> ring(contacts.faces.empty() ? 0 : n, -1);  // per particle, in a face's tent
  std::vector<std::uint32_t> tent;
  for (int iteration = 0; iteration < options.solver_iterations; ++iteration) {
    const bool last = iteration + 1 == options.solver_iterations;
    rhs.assign(free_count, {0.0, 0.0, 0.0});
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t k = model.unknown[i];
      if (k == kNone) continue;
      for (int c = 0; c < 3; ++c) rhs[k][c] += model.mass[i] * s[i][c];
    }
    // Local step: each spring's nearest state at its rest length; its share of the right side.
    for (const ClothModel::Spring& sp : model.springs) {
      const Vec3 d = sub(now[sp.a], now[sp.b]);
      const double len = norm(d);
      const Vec3 p = len > 0.0 ? scale(d, sp.rest / len) : Vec3{0.0, 0.0, 0.0};
      const std::uint32_t ia = model.unknown[sp.a], ib = model.unknown[sp.b];
      for (int c = 0; c < 3; ++c) {
        if (ia != kNone) rhs[ia][c] += sp.weight * (p[c] + (ib == kNone ? now[sp.b][c] : 0.0));
        if (ib != kNone) rhs[ib][c] += sp.weight * (-p[c] + (ia == kNone ? now[sp.a][c] : 0.0));
      }
    }
    // Global step: x, y and z solved with the factored matrix, the factor read once for the
    // three (ldlt_columns.h: the same bits as one solve per coordinate).
    ldlt_solve_columns(model.solver, rhs);
    for (std::size_t i = 0; i < n; ++i)
      if (model.unknown[i] != kNone)
        for (int c = 0; c < 3; ++c) now[i][c] = rhs[model.unknown[i]][c];
    if (!contacts.begin.empty())
      for (std::size_t i = 0; i < n; ++i) {
        if (model.unknown[i] == kNone) continue;
        for (std::uint32_t k = contacts.begin[i]; k < contacts.begin[i + 1]; ++k) {
          const ContactPlane& plane = contacts.planes[k];
          const double below = dot(sub(now[i], plane.point), plane.normal);
          if (below >= 0.0) continue;
          now[i] = sub(now[i], scale(plane.normal, below));
          if (last && touching) (*touching)[i] = k + 1;
        }
      }
    // Face planes: the point of the triangle moves out along the normal by lifting the corners
    // (each by as much, so the point by as much too) and kFaceRings rings of particles round them
    // by less and less, so that the cloth is tented over the vertex rather than spiked: a pinned
    // particle does not move.
    for (std::size_t k = 0; k < contacts.faces.size(); ++k) {
      const FacePlane& face = contacts.faces[k];
      Vec3 at{0.0, 0.0, 0.0};
      bool free = false;
      for (int j = 0; j < 3; ++j) {
        at = add(at, scale(now[face.corner[j]], face.weight[j]));
        free = free || model.unknown[face.corner[j]] != kNone;
      }
      const double below = dot(sub(at, face.plane.point), face.plane.normal);
      if (below >= 0.0 || !free) continue;
      tent.clear();
      for (std::uint32_t c : face.corner)
        if (ring[c] < 0) {
          ring[c] = 0;
          tent.push_back(c);
        }
      for (std::size_t from = 0, to = tent.size(), r = 1; r <= kFaceRings; ++r) {
        for (std::size_t t = from; t < to; ++t)
          for (std::uint32_t e = model.topo.vertex_edge_begin[tent[t]];
               e < model.topo.vertex_edge_begin[tent[t] + 1]; ++e) {
            const std::uint32_t w = model.topo.vertex_neighbors[e];
            if (ring[w] >= 0) continue;
            ring[w] = static_cast<int>(r);
            tent.push_back(w);
          }
        from = to;
        to = tent.size();
      }
      for (std::uint32_t v : tent) {
        if (model.unknown[v] != kNone) {
          const double share = 1.0 - static_cast<double>(ring[v]) / (kFaceRings + 1);
          now[v] = sub(now[v], scale(face.plane.normal, below * share));
          if (last && touching && ring[v] == 0)
            (*touching)[v] = static_cast<std::uint32_t>(contacts.planes.size() + 1 + k);
        }
      }
      for (std::uint32_t v : tent) ring[v] = -1;
    }
  }
  x = std::move(now);
}

}  // namespace untangle
