// Pieces moved whole (piece_moves.h): which pieces the kept attempt leaves tangled, then the
// shortest clear translation of each, smallest piece first.
#include "resolve/piece_moves.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "detect/detect_crossings.h"
#include "detect/triangle_bvh.h"
#include "geometry/vec3.h"
#include "resolve/inside_vertices.h"
#include "resolve/scene_measures.h"
#include "topology/scene_topology.h"

namespace untangle {
namespace {

// The 26 directions of a frame: its axes (largest spread first, each way), then the diagonals of
// two axes, then those of three; the sign of each axis makes the third moment of the piece's
// vertices along it non-negative, so that the order follows the piece and not the coordinates.
std::vector<Vec3> piece_directions(const std::vector<Vec3>& points,
                                   const std::vector<std::uint32_t>& vertices) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const std::uint32_t v : vertices)
    centre += Eigen::Vector3d(points[v][0], points[v][1], points[v][2]);
  centre /= static_cast<double>(vertices.size());
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  for (const std::uint32_t v : vertices) {
    const Eigen::Vector3d d = Eigen::Vector3d(points[v][0], points[v][1], points[v][2]) - centre;
    spread += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(spread);
  std::array<Vec3, 3> axis;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = solver.eigenvectors().col(2 - k);  // eigenvalues ascend
    double third = 0.0;
    for (const std::uint32_t v : vertices) {
      const double s = (Eigen::Vector3d(points[v][0], points[v][1], points[v][2]) - centre).dot(e);
      third += s * s * s;
    }
    const double sign = third < 0.0 ? -1.0 : 1.0;
    axis[k] = {sign * e[0], sign * e[1], sign * e[2]};
  }
  std::vector<Vec3> directions;
  for (int nonzero = 1; nonzero <= 3; ++nonzero)
    for (int a = 1; a >= -1; --a)
      for (int b = 1; b >= -1; --b)
        for (int c = 1; c >= -1; --c) {
          if ((a != 0) + (b != 0) + (c != 0) != nonzero) continue;
          Vec3 d = add(add(scale(axis[0], a), scale(axis[1], b)), scale(axis[2], c));
          directions.push_back(unit(d));
        }
  return directions;
}

// The search's view of one scene: its topology at the positions so far, the obstacles' inside.
class PieceSearch {
 public:
  PieceSearch(const SceneTopology& topo, const ObstacleWinding& winding)
      : topo_(topo), winding_(winding) {}

  // Whether the triangles `tris` (one piece, its vertices `vertices`) cross none of `others`
  // (a hierarchy over every other triangle) and no vertex of it lies inside an obstacle.
  bool clear(const std::vector<std::uint32_t>& tris, const std::vector<std::uint32_t>& vertices,
             const TriangleBvh& others) {
    const auto& dt = topo_.detect_tris();
    const std::vector<Vec3>& p = topo_.points;
    for (const std::uint32_t t : tris) {
      found_.clear();
      others.query(triangle_box(topo_, t), found_);
      const std::array<std::uint32_t, 3>& a = dt[t];
      for (const std::uint32_t u : found_) {
        const std::array<std::uint32_t, 3>& b = dt[u];
        if (triangles_surely_apart(p, a, b)) continue;
        for (int c = 0; c < 3; ++c) {
          if (edge_crosses_triangle(p, a[c], a[(c + 1) % 3], b[0], b[1], b[2])) return false;
          if (edge_crosses_triangle(p, b[c], b[(c + 1) % 3], a[0], a[1], a[2])) return false;
        }
      }
    }
    for (const std::uint32_t v : vertices)
      if (winding_.inside(p[v]) != kNone) return false;
    return true;
  }

 private:
  const SceneTopology& topo_;
  const ObstacleWinding& winding_;
  std::vector<std::uint32_t> found_;
};

}  // namespace

PieceMoveRecord move_pieces_whole(std::vector<Mesh>& meshes, const std::vector<Mesh>& kept,
                                  const FixOptions& options, const PinMask& pins,
                                  const Rounding& round,
                                  const std::vector<std::vector<std::uint32_t>>& input_vertex,
                                  const ObstacleWinding* earlier) {
  PieceMoveRecord record;
  SceneTopology topo = build_topology(meshes);
  std::vector<Role> role;
  for (const Mesh& m : meshes) role.push_back(m.role);
  const std::size_t pieces = topo.component_mesh.size();
  auto movable = [&](std::uint32_t c) { return role[topo.component_mesh[c]] == Role::kMovable; };
  // The piece of a mesh's input vertex (as the input's topology welds it).
  auto piece_of = [&](std::uint32_t mesh, std::uint32_t vertex) {
    return topo.vertex_component[topo.welded[mesh][vertex]];
  };

  // The obstacles' winding numbers, the repair's where given: they never move.
  const ObstacleWinding winding(topo, role, options.threads, earlier);

  // Triangles per component (pieces and the obstacles' components alike), per mesh.
  std::vector<std::size_t> size(pieces, 0), mesh_size(meshes.size(), 0);
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
    ++size[topo.tri_component(t)];
    ++mesh_size[topo.tri_mesh[t]];
  }
  // The pieces the kept attempt leaves tangled: a crossing with another piece or an obstacle, or
  // a vertex inside an obstacle. Everything a tangled piece is tangled with must be small too
  // (`small`): a garment piece crosses the body it is on, which a clear translation carries it
  // off (the shipped garment on its body x 1.02, left unresolved without retries: its top slid
  // forward off the torso and its trousers back, each by less than half its size).
  std::vector<std::uint8_t> tangled(pieces, 0);
  bool small = true;
  {
    const SceneTopology at = build_topology(kept);
    DetectSettings settings;
    settings.threads = options.threads;
    settings.skip_among.assign(meshes.size(), false);
    for (std::size_t m = 0; m < meshes.size(); ++m)
      settings.skip_among[m] = role[m] == Role::kObstacle;
    const CrossingSet crossings = detect_crossings(at, settings);
    auto piece_at = [&](std::uint32_t welded) {
      const std::uint32_t mesh = at.vertex_mesh[welded];
      return piece_of(mesh, at.representative[welded]);
    };
    for (const RawCrossing& c : crossings.items) {
      const std::uint32_t a = piece_at(at.edges[c.edge][0]);
      const std::uint32_t t = at.tri_source[c.face];
      const std::uint32_t face_mesh = at.tri_mesh[c.face];
      const std::uint32_t b = piece_of(face_mesh, kept[face_mesh].triangles[t][0]);
      if (a == b) continue;
      if (movable(a)) tangled[a] = 1;
      if (movable(b)) tangled[b] = 1;
      small = small && size[a] <= kMaxPieceTriangles && size[b] <= kMaxPieceTriangles;
    }
    const ObstacleWinding at_winding(at, role, options.threads, &winding);
    std::vector<std::uint32_t> inside;
    if (at_winding.any()) find_inside_vertices(at, role, at_winding, {}, options.threads, inside);
    for (std::uint32_t v = 0; v < inside.size(); ++v) {
      if (inside[v] == kNone) continue;
      tangled[piece_at(v)] = 1;
      small = small && size[piece_at(v)] <= kMaxPieceTriangles &&
              mesh_size[inside[v]] <= kMaxPieceTriangles;
    }
  }
  if (!small) return record;

  // Every tangled piece free to move and sharing no vertex with an obstacle, or nothing.
  const SceneMeasures measures = measure_scene(topo, meshes, pins, options.threads);
  std::vector<std::vector<std::uint32_t>> piece_tris(pieces), piece_vertices(pieces);
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t)
    if (tangled[topo.tri_component(t)]) piece_tris[topo.tri_component(t)].push_back(t);
  for (std::uint32_t v = 0; v < topo.points.size(); ++v)
    if (tangled[topo.vertex_component[v]]) piece_vertices[topo.vertex_component[v]].push_back(v);
  std::vector<std::uint32_t> order;
  for (std::uint32_t c = 0; c < pieces; ++c) {
    if (!tangled[c]) continue;
    if (piece_tris[c].empty()) return record;
    for (const std::uint32_t v : piece_vertices[c])
      if (!measures.free[v]) return record;
    order.push_back(c);
  }
  if (order.empty()) return record;
  record.ran = true;
  record.tangled = order.size();
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return piece_tris[a].size() < piece_tris[b].size();
  });

  PieceSearch search(topo, winding);
  std::vector<std::uint8_t> moved_vertex(topo.points.size(), 0);
  std::vector<std::uint32_t> slot(pieces, kNone);  // per piece: its entry of record.pieces
  for (const std::uint32_t c : order) {
    const std::vector<std::uint32_t>& tris = piece_tris[c];
    const std::vector<std::uint32_t>& vertices = piece_vertices[c];
    std::vector<std::uint32_t> rest;
    rest.reserve(topo.tris.size() - tris.size());
    for (std::uint32_t t = 0; t < topo.tris.size(); ++t)
      if (topo.tri_component(t) != c) rest.push_back(t);
    const TriangleBvh others(topo, rest);
    if (search.clear(tris, vertices, others)) continue;  // freed by a piece moved before it
    Box3 box = triangle_box(topo, tris[0]);
    for (const std::uint32_t t : tris) box = merged(box, triangle_box(topo, t));
    const double diagonal = norm(sub(box.hi, box.lo));
    if (!(diagonal > 0.0)) continue;
    const std::vector<Vec3> directions = piece_directions(topo.points, vertices);
    std::vector<Vec3> from(vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) from[i] = topo.points[vertices[i]];
    bool freed = false;
    double length = 0.0;
    for (int k = 1; k <= kPieceLongest && !freed; ++k) {
      length = diagonal * k / kPieceSteps;
      for (const Vec3& d : directions) {
        const Vec3 shift = scale(d, length);
        for (std::size_t i = 0; i < vertices.size(); ++i) {
          const Vec3 p = add(from[i], shift);
          topo.points[vertices[i]] = round ? round(p) : p;
        }
        if (search.clear(tris, vertices, others)) {
          freed = true;
          break;
        }
      }
    }
    if (!freed) {
      for (std::size_t i = 0; i < vertices.size(); ++i) topo.points[vertices[i]] = from[i];
      continue;
    }
    ++record.moved;
    record.largest_move = std::max(record.largest_move, length);
    for (const std::uint32_t v : vertices) moved_vertex[v] = 1;
    PieceMove move;
    move.mesh = topo.component_mesh[c];
    move.vertex = kNone;
    move.shift = sub(topo.points[vertices[0]], from[0]);
    slot[c] = static_cast<std::uint32_t>(record.pieces.size());
    record.pieces.push_back(move);
  }
  for (std::uint32_t m = 0; m < meshes.size(); ++m)
    for (std::uint32_t i = 0; i < meshes[m].positions.size(); ++i) {
      const std::uint32_t v = topo.welded[m][i];
      if (!moved_vertex[v]) continue;
      meshes[m].positions[i] = topo.points[v];
      std::uint32_t& lowest = record.pieces[slot[topo.vertex_component[v]]].vertex;
      lowest = std::min(lowest, input_vertex[m][i]);
    }
  return record;
}

}  // namespace untangle
