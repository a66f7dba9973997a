// CGAL reference for tests and benchmarks: intersecting triangle pairs and intersection polylines
// computed by CGAL's own Polygon_mesh_processing routines on the same meshes.
//
// Header-only (inline) because the build globs tests/test_*.cpp into the test binary and
// bench/bench_*.cpp into one executable each; both include this file.
//
// Conventions, matching untangle::Intersections::triangle_pairs:
// - a pair is {mesh A, triangle A, mesh B, triangle B} with (A, triA) < (B, triB), triangle indices
//   into Mesh::triangles; the list is sorted and free of duplicates;
// - within one mesh, vertices at identical positions are welded first (DESIGN §1), so that
//   "sharing a vertex / an edge" is decided on the welded topology; meshes are never merged;
// - within one mesh, CGAL::Polygon_mesh_processing::self_intersections decides: pairs sharing an
//   edge never count (unless coplanar and folded onto each other: CGAL counts that, untangle does
//   not; it cannot happen in non-degenerate scenes), pairs sharing one vertex count when the edge
//   opposite that vertex in one triangle meets the other triangle, i.e. when they meet beyond it;
// - a Surface_mesh cannot hold a non-manifold (pinched) welded vertex, e.g. two closed fans
//   touching at one point as in CGAL's own cow.off (vertices 44 and 2903): such a vertex gets one
//   Surface_mesh vertex per fan (fans = incident triangles connected across manifold edges).
//   CGAL then sees triangles of different fans as sharing nothing and tests them with a full
//   do_intersect, which is true for any two triangles touching at the shared point; those pairs
//   are re-decided on the welded topology with the rule CGAL applies to triangles sharing a
//   vertex (see redecide_welded_pair). Non-manifold edges (3+ triangles) are refused;
// - between two distinct meshes, CGAL::Polygon_mesh_processing::internal::
//   compute_face_face_intersection (box_intersection_d over face boxes, then
//   do_intersect(Triangle_3, Triangle_3): the routine behind PMP::do_intersect) decides;
// - degenerate triangles are left out of both routines and of the result, and listed in
//   ReferenceMesh::degenerate: a triangle is degenerate when two of its corners weld to the same
//   vertex (it cannot be a Surface_mesh face at all) or its three corners are collinear (CGAL's
//   self_intersections reports such a face only as the pair (f, f) and never tests it against
//   others). Callers comparing with untangle should require `degenerate` to be empty.
//
// Everything here is exact (Epick: filtered exact predicates), so on non-degenerate input the
// answer is the one true set of intersecting triangle pairs.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "untangle/mesh.h"

namespace untangle::cgal_reference {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using FaceIndex = SurfaceMesh::Face_index;
using VertexIndex = SurfaceMesh::Vertex_index;
using TrianglePair = std::array<std::uint32_t, 4>;

// One untangle::Mesh as a CGAL Surface_mesh, with the map back to Mesh::triangles.
struct ReferenceMesh {
  SurfaceMesh mesh;
  std::vector<std::uint32_t> triangle_of_face;  // by Surface_mesh face index: Mesh::triangles index
  std::vector<std::array<std::uint32_t, 3>> welded_of_face;  // by face: welded vertex ids, in order
  std::vector<FaceIndex> faces;           // the non-degenerate faces, handed to CGAL
  std::vector<std::uint32_t> degenerate;  // Mesh::triangles indices left out (sorted)
  std::size_t welded_vertices = 0;        // vertices after welding
  std::size_t split_vertices = 0;         // extra Surface_mesh vertices at non-manifold vertices
};

// Welds identical positions (exact equality), splits non-manifold vertices into their fans and
// builds the Surface_mesh. Throws std::runtime_error on a non-manifold edge, or when Surface_mesh
// refuses a face (inconsistent orientation, duplicate face).
inline ReferenceMesh to_reference_mesh(const Mesh& mesh) {
  ReferenceMesh out;
  const std::string label = "cgal_reference: mesh '" + mesh.name + "' ";

  // Weld.
  std::map<Vec3, std::uint32_t> by_position;
  std::vector<std::uint32_t> welded(mesh.positions.size());
  std::vector<Vec3> welded_position;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto [it, inserted] =
        by_position.emplace(mesh.positions[i], static_cast<std::uint32_t>(welded_position.size()));
    if (inserted) welded_position.push_back(mesh.positions[i]);
    welded[i] = it->second;
  }
  out.welded_vertices = welded_position.size();

  // Triangles that can be faces (three distinct welded corners).
  std::vector<std::uint32_t> kept;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    for (std::uint32_t v : tri) {
      if (v >= mesh.positions.size()) {
        throw std::runtime_error(label + "triangle " + std::to_string(t) +
                                 " has a vertex index out of range");
      }
    }
    const std::uint32_t a = welded[tri[0]], b = welded[tri[1]], c = welded[tri[2]];
    if (a == b || b == c || c == a) {
      out.degenerate.push_back(static_cast<std::uint32_t>(t));
    } else {
      kept.push_back(static_cast<std::uint32_t>(t));
    }
  }

  // Fans: union the corners (slot 3k + i of kept triangle k) at each end of every manifold edge.
  std::vector<std::uint32_t> parent(3 * kept.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const auto corner_of = [&](std::size_t k, int i) { return welded[mesh.triangles[kept[k]][i]]; };
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::pair<std::size_t, int>>> edges;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = corner_of(k, i), b = corner_of(k, (i + 1) % 3);
      edges[{std::min(a, b), std::max(a, b)}].push_back({k, i});  // edge from corner i to i+1
    }
  }
  for (const auto& [edge, uses] : edges) {
    if (uses.size() > 2) {
      throw std::runtime_error(label + "has a non-manifold edge (" + std::to_string(uses.size()) +
                               " triangles, first " + std::to_string(kept[uses[0].first]) + ")");
    }
    if (uses.size() != 2) continue;
    for (std::uint32_t end : {edge.first, edge.second}) {
      std::uint32_t slot[2];
      for (int u = 0; u < 2; ++u) {
        const auto [k, i] = uses[u];
        slot[u] = static_cast<std::uint32_t>(3 * k + (corner_of(k, i) == end ? i : (i + 1) % 3));
      }
      parent[find(slot[0])] = find(slot[1]);
    }
  }

  // One Surface_mesh vertex per fan, created in order of first use.
  std::map<std::uint32_t, VertexIndex> vertex_of_fan;
  std::vector<bool> welded_used(welded_position.size(), false);
  for (std::size_t k = 0; k < kept.size(); ++k) {
    VertexIndex v[3];
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t w = corner_of(k, i);
      const auto [it, inserted] =
          vertex_of_fan.emplace(find(static_cast<std::uint32_t>(3 * k + i)), VertexIndex());
      if (inserted) {
        const Vec3& p = welded_position[w];
        it->second = out.mesh.add_vertex(Point(p[0], p[1], p[2]));
        if (welded_used[w]) ++out.split_vertices;
        welded_used[w] = true;
      }
      v[i] = it->second;
    }
    const FaceIndex f = out.mesh.add_face(v[0], v[1], v[2]);
    if (f == SurfaceMesh::null_face()) {
      throw std::runtime_error(label + "triangle " + std::to_string(kept[k]) +
                               " cannot be added to a CGAL Surface_mesh (inconsistently oriented "
                               "or duplicate)");
    }
    if (static_cast<std::size_t>(f) != out.triangle_of_face.size()) {
      throw std::runtime_error(label + "unexpected Surface_mesh face numbering");
    }
    out.triangle_of_face.push_back(kept[k]);
    out.welded_of_face.push_back({corner_of(k, 0), corner_of(k, 1), corner_of(k, 2)});
    if (CGAL::collinear(out.mesh.point(v[0]), out.mesh.point(v[1]), out.mesh.point(v[2]))) {
      out.degenerate.push_back(kept[k]);
    } else {
      out.faces.push_back(f);
    }
  }
  std::sort(out.degenerate.begin(), out.degenerate.end());
  return out;
}

inline std::vector<ReferenceMesh> to_reference_meshes(const std::vector<Mesh>& meshes) {
  std::vector<ReferenceMesh> out;
  out.reserve(meshes.size());
  for (const Mesh& mesh : meshes) out.push_back(to_reference_mesh(mesh));
  return out;
}

inline TrianglePair ordered_pair(std::uint32_t mesh_a, std::uint32_t tri_a, std::uint32_t mesh_b,
                                 std::uint32_t tri_b) {
  if (std::make_pair(mesh_b, tri_b) < std::make_pair(mesh_a, tri_a)) {
    std::swap(mesh_a, mesh_b);
    std::swap(tri_a, tri_b);
  }
  return {mesh_a, tri_a, mesh_b, tri_b};
}

inline void sort_unique(std::vector<TrianglePair>& pairs) {
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

// Corners shared by two faces: on the welded topology and as Surface_mesh vertices.
inline int shared_welded(const ReferenceMesh& rm, FaceIndex f, FaceIndex g) {
  int shared = 0;
  for (std::uint32_t a : rm.welded_of_face[static_cast<std::size_t>(f)]) {
    for (std::uint32_t b : rm.welded_of_face[static_cast<std::size_t>(g)]) shared += a == b;
  }
  return shared;
}
inline int shared_surface_mesh(const ReferenceMesh& rm, FaceIndex f, FaceIndex g) {
  int shared = 0;
  for (VertexIndex a : CGAL::vertices_around_face(rm.mesh.halfedge(f), rm.mesh)) {
    for (VertexIndex b : CGAL::vertices_around_face(rm.mesh.halfedge(g), rm.mesh)) {
      shared += a == b;
    }
  }
  return shared;
}

// A pair CGAL reported although the faces share more welded corners than Surface_mesh vertices
// (a vertex split at a non-manifold vertex): sharing a welded edge never counts; sharing one
// welded vertex counts when, as in CGAL's internal do_faces_intersect, the edge of one triangle
// opposite the shared vertex meets the other triangle.
inline bool redecide_welded_pair(const ReferenceMesh& rm, FaceIndex f, FaceIndex g) {
  if (shared_welded(rm, f, g) >= 2) return false;
  std::array<Point, 3> pf, pg;
  int i = 0;
  for (VertexIndex v : CGAL::vertices_around_face(rm.mesh.halfedge(f), rm.mesh)) {
    pf[i++] = rm.mesh.point(v);
  }
  i = 0;
  for (VertexIndex v : CGAL::vertices_around_face(rm.mesh.halfedge(g), rm.mesh)) {
    pg[i++] = rm.mesh.point(v);
  }
  // Welded means identical position: find the shared corner by its point.
  int i_f = -1, i_g = -1;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      if (pf[a] == pg[b]) i_f = a, i_g = b;
    }
  }
  if (i_f < 0) return true;  // cannot happen: a shared welded vertex has one position
  const Kernel::Triangle_3 tf(pf[0], pf[1], pf[2]), tg(pg[0], pg[1], pg[2]);
  const Kernel::Segment_3 sf(pf[(i_f + 1) % 3], pf[(i_f + 2) % 3]);
  const Kernel::Segment_3 sg(pg[(i_g + 1) % 3], pg[(i_g + 2) % 3]);
  return CGAL::do_intersect(tf, sg) || CGAL::do_intersect(tg, sf);
}

// Intersecting pairs within one mesh: CGAL::Polygon_mesh_processing::self_intersections over the
// non-degenerate faces, pairs at split vertices re-decided on the welded topology. Unsorted.
inline void append_self_pairs(const ReferenceMesh& rm, std::uint32_t mesh_index,
                              std::vector<TrianglePair>& out) {
  std::vector<std::pair<FaceIndex, FaceIndex>> faces;
  CGAL::Polygon_mesh_processing::self_intersections(rm.faces, rm.mesh, std::back_inserter(faces));
  for (const auto& [f, g] : faces) {
    if (f == g) continue;  // CGAL's marker of a degenerate face; none are in rm.faces
    if (rm.split_vertices != 0 && shared_welded(rm, f, g) != shared_surface_mesh(rm, f, g) &&
        !redecide_welded_pair(rm, f, g)) {
      continue;
    }
    out.push_back(ordered_pair(mesh_index, rm.triangle_of_face[static_cast<std::size_t>(f)],
                               mesh_index, rm.triangle_of_face[static_cast<std::size_t>(g)]));
  }
}

// Raw CGAL face-face pairs between two distinct meshes (the timed routine of the benchmark).
inline std::vector<std::pair<FaceIndex, FaceIndex>> face_face_intersection(const ReferenceMesh& a,
                                                                           const ReferenceMesh& b) {
  std::vector<std::pair<FaceIndex, FaceIndex>> faces;
  CGAL::Polygon_mesh_processing::internal::compute_face_face_intersection(
      a.faces, b.faces, a.mesh, b.mesh, std::back_inserter(faces),
      CGAL::parameters::default_values(), CGAL::parameters::default_values());
  return faces;
}

// Intersecting pairs between two distinct meshes. Unsorted.
inline void append_face_face_pairs(const ReferenceMesh& a, std::uint32_t mesh_a,
                                   const ReferenceMesh& b, std::uint32_t mesh_b,
                                   std::vector<TrianglePair>& out) {
  for (const auto& [f, g] : face_face_intersection(a, b)) {
    out.push_back(ordered_pair(mesh_a, a.triangle_of_face[static_cast<std::size_t>(f)], mesh_b,
                               b.triangle_of_face[static_cast<std::size_t>(g)]));
  }
}

// All intersecting triangle pairs of a scene (within each mesh and between each two meshes),
// in the format of untangle::Intersections::triangle_pairs: ordered, sorted, unique.
inline std::vector<TrianglePair> triangle_pairs(const std::vector<ReferenceMesh>& meshes) {
  std::vector<TrianglePair> out;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    append_self_pairs(meshes[i], static_cast<std::uint32_t>(i), out);
    for (std::size_t j = i + 1; j < meshes.size(); ++j) {
      append_face_face_pairs(meshes[i], static_cast<std::uint32_t>(i), meshes[j],
                             static_cast<std::uint32_t>(j), out);
    }
  }
  sort_unique(out);
  return out;
}

inline std::vector<TrianglePair> triangle_pairs(const std::vector<Mesh>& meshes) {
  return triangle_pairs(to_reference_meshes(meshes));
}

// Whether two triangles (given by their Mesh and index) intersect at all, by CGAL's exact
// do_intersect(Triangle_3, Triangle_3): for diagnosing disagreements.
inline bool do_triangles_intersect(const Mesh& ma, std::uint32_t ta, const Mesh& mb,
                                   std::uint32_t tb) {
  auto triangle = [](const Mesh& m, std::uint32_t t) {
    const auto p = [&](int k) {
      const Vec3& v = m.positions[m.triangles[t][k]];
      return Point(v[0], v[1], v[2]);
    };
    return Kernel::Triangle_3(p(0), p(1), p(2));
  };
  return CGAL::do_intersect(triangle(ma, ta), triangle(mb, tb));
}

// Whether two triangles meet in a degenerate way: coplanar, a vertex of one on the other (closed)
// triangle, or an edge of one meeting an edge of the other in a common plane. Corners at identical
// positions in the same mesh are shared (welded) and exempt. Exact. These are the contacts where
// CGAL (closed sets: touching is intersecting) and a symbolic perturbation may legitimately
// disagree; on non-degenerate input no intersecting pair is one.
inline bool degenerate_contact(const Mesh& ma, std::uint32_t ta, const Mesh& mb, std::uint32_t tb) {
  std::array<Point, 3> a, b;
  for (int i = 0; i < 3; ++i) {
    const Vec3& p = ma.positions[ma.triangles[ta][i]];
    const Vec3& q = mb.positions[mb.triangles[tb][i]];
    a[i] = Point(p[0], p[1], p[2]);
    b[i] = Point(q[0], q[1], q[2]);
  }
  const bool same_mesh = &ma == &mb;
  std::array<bool, 3> a_shared{}, b_shared{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (same_mesh && a[i] == b[j]) a_shared[i] = b_shared[j] = true;
    }
  }
  const Kernel::Triangle_3 tri_a(a[0], a[1], a[2]), tri_b(b[0], b[1], b[2]);
  if (CGAL::coplanar(a[0], a[1], a[2], b[0]) && CGAL::coplanar(a[0], a[1], a[2], b[1]) &&
      CGAL::coplanar(a[0], a[1], a[2], b[2])) {
    return true;
  }
  for (int i = 0; i < 3; ++i) {
    if (!a_shared[i] && CGAL::coplanar(b[0], b[1], b[2], a[i]) && CGAL::do_intersect(tri_b, a[i])) {
      return true;
    }
    if (!b_shared[i] && CGAL::coplanar(a[0], a[1], a[2], b[i]) && CGAL::do_intersect(tri_a, b[i])) {
      return true;
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Point &p = a[i], &q = a[(i + 1) % 3], &r = b[j], &s = b[(j + 1) % 3];
      if (same_mesh && (p == r || p == s || q == r || q == s)) continue;  // meet at a shared corner
      if (CGAL::coplanar(p, q, r, s) &&
          CGAL::do_intersect(Kernel::Segment_3(p, q), Kernel::Segment_3(r, s))) {
        return true;
      }
    }
  }
  return false;
}

// The intersection of two meshes as polylines, by CGAL::Polygon_mesh_processing::
// surface_intersection (corefinement's intersection graph, without refining the meshes). Returns
// the number of polylines; `points` (when given) receives their total number of points.
inline std::size_t surface_intersection_polylines(const ReferenceMesh& a, const ReferenceMesh& b,
                                                  std::size_t* points = nullptr) {
  std::vector<std::vector<Point>> polylines;
  CGAL::Polygon_mesh_processing::surface_intersection(a.mesh, b.mesh,
                                                      std::back_inserter(polylines));
  if (points != nullptr) {
    *points = 0;
    for (const auto& polyline : polylines) *points += polyline.size();
  }
  return polylines.size();
}

// The vertices of `movable` that CGAL's Side_of_triangle_mesh puts on the bounded side of the
// closed mesh `closed_body`.
inline std::size_t inside_count(const Mesh& movable, const Mesh& closed_body) {
  const ReferenceMesh ref = to_reference_mesh(closed_body);
  const CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel> side(ref.mesh);
  std::size_t n = 0;
  for (const Vec3& p : movable.positions)
    n += side(Kernel::Point_3(p[0], p[1], p[2])) == CGAL::ON_BOUNDED_SIDE ? 1 : 0;
  return n;
}

}  // namespace untangle::cgal_reference
