// Detection: bounding-volume hierarchies for candidate pairs, exact perturbed predicates for crossings.
#include "detect/detect_crossings.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "detect/cull_triangles.h"
#include "detect/orientation.h"
#include "detect/run_parallel.h"
#include "detect/update_steps.h"

namespace untangle {
namespace {

bool contains(const std::array<std::uint32_t, 3>& tri, std::uint32_t v) {
  return tri[0] == v || tri[1] == v || tri[2] == v;
}

// Whether the line pq meets the interior of triangle (a, b, c) under the perturbation: it turns
// the same way around all three edges.
bool line_through_triangle(const std::vector<Vec3>& points, std::uint32_t p, std::uint32_t q,
                           std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  const int s1 = orient_sos(points, p, q, a, b);
  const int s2 = orient_sos(points, p, q, b, c);
  if (s1 != s2) return false;
  return orient_sos(points, p, q, c, a) == s1;
}

// Tests the edges of `t` that t owns (t is their lowest incident triangle) and that share no vertex
// with `f`, against f. `side[k]`: the exact side of t's corner k of f's plane when already known
// (surely_apart), else 0; a zero is decided by the perturbation.
void test_owned_edges(const SceneTopology& topo, std::uint32_t t, std::uint32_t f,
                      const std::array<int, 3>& side, std::vector<RawCrossing>& out) {
  const auto& tri = topo.detect_tris()[t];
  const auto& face = topo.detect_tris()[f];
  auto side_of = [&](int k) {
    return side[k] != 0 ? side[k] : orient_sos(topo.points, face[0], face[1], face[2], tri[k]);
  };
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t e = topo.tri_edges[t][k];
    if (topo.edge_faces[topo.edge_face_begin[e]] != t) continue;
    const std::uint32_t p = tri[k], q = tri[(k + 1) % 3];
    if (contains(face, p) || contains(face, q)) continue;
    if (side_of(k) == side_of((k + 1) % 3)) continue;
    if (line_through_triangle(topo.points, p, q, face[0], face[1], face[2])) {
      out.push_back({e, f,
                     crossing_point(topo.points[p], topo.points[q], topo.points[face[0]],
                                    topo.points[face[1]], topo.points[face[2]])});
    }
  }
}

// Exact filtered orientation without perturbation (0 when exactly coplanar). Planes normal to an
// axis go through AxisPlane instead.
int orient_exact(const std::vector<Vec3>& points, std::uint32_t a, std::uint32_t b, std::uint32_t c,
                 std::uint32_t d) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  auto p = [&](std::uint32_t i) { return K::Point_3(points[i][0], points[i][1], points[i][2]); };
  return static_cast<int>(CGAL::orientation(p(a), p(b), p(c), p(d)));
}

// What the pruning test needs of one triangle alone (TriPlane): found once per triangle in
// detection (a flat sheet's triangle meets a dozen others) and for the retested triangles of an
// update, once per run for the skipped meshes when their caller keeps them, per pair elsewhere.
TriPlane tri_plane(const std::vector<Vec3>& P, const std::array<std::uint32_t, 3>& tri) {
  const Vec3 &p0 = P[tri[0]], &p1 = P[tri[1]], &p2 = P[tri[2]];
  int axis = -1;
  for (int k = 2; k >= 0; --k)
    if (p0[k] == p1[k] && p0[k] == p2[k]) axis = k;
  const Vec3 e1{p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
  const Vec3 e2{p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
  const Vec3 n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  int drop = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(n[k]) > std::abs(n[drop])) drop = k;
  const int turn = orient_2d(p0, p1, p2, drop);
  int axis_turn = 0;
  if (axis >= 0) axis_turn = axis == drop ? AxisPlane::turn_for(turn, axis) : AxisPlane::turn_of(p0, p1, p2, axis);
  return {static_cast<std::int8_t>(axis), static_cast<std::int8_t>(axis_turn),
          static_cast<std::int8_t>(drop), static_cast<std::int8_t>(turn)};
}

// The class of the direction from s to r in the projection along `drop` onto axes (i, j), counter-
// clockwise from +i: 0 on the +i half-axis, 1 in the open quadrant (+, +), 2 on +j, ... 7 in
// (+, -); exact (comparisons only). A turn of less than a half circle advances it by 0 to 4.
int direction_class(const Vec3& s, const Vec3& r, int drop) {
  const int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
  const int u = (r[i] > s[i]) - (r[i] < s[i]), v = (r[j] > s[j]) - (r[j] < s[j]);
  static constexpr int kClass[3][3] = {{5, 4, 3}, {6, -1, 2}, {7, 0, 1}};  // [u + 1][v + 1]
  return kClass[u + 1][v + 1];
}

// Per welded vertex of the meshes flagged in `fans_of` (others 0): 1 when the triangles around it
// form one flat fan that winds around it exactly once, so that any two of them that share only
// that vertex meet only there (the sector test of surely_apart_at would say so after up to eight
// orientations). Conditions, all exact: every edge at the vertex has two faces that run through
// it in opposite directions (the sectors form cycles of rays); every triangle at it lies in one
// plane normal to an axis (AxisPlane; TriPlane drop equal to the axis) with the same nonzero turn
// there, so each sector is less than a half circle counter-clockwise (or each clockwise); and the
// sectors' direction classes advance by 8 in all, one full turn (each cycle of rays turns a whole
// number of times, at least once). Flat sheets make nearly every interior vertex one of these.
std::vector<std::uint8_t> flat_fans(const SceneTopology& topo, const TriPlane* planes,
                                    const std::vector<bool>& fans_of, int threads) {
  std::vector<std::uint8_t> fan(topo.points.size(), 0);
  auto embedded = [&](std::uint32_t s) {
    int axis = -1, turn = 0, advance = 0;
    for (std::uint32_t i = topo.vertex_edge_begin[s]; i < topo.vertex_edge_begin[s + 1]; ++i) {
      const std::uint32_t e = topo.vertex_edges[i], x = topo.vertex_neighbors[i];
      if (topo.edge_face_count(e) != 2) return false;
      int forward = 0;
      for (std::uint32_t k = topo.edge_face_begin[e]; k < topo.edge_face_begin[e + 1]; ++k) {
        const std::uint32_t f = topo.edge_faces[k];
        const auto& tri = topo.tris[f];
        const int c = tri[0] == s ? 0 : tri[1] == s ? 1 : 2;
        if (tri[(c + 1) % 3] != x) continue;  // f runs x -> s: counted from its other edge at s
        ++forward;
        const TriPlane& p = planes[f];
        if (p.axis < 0 || p.drop != p.axis || p.turn == 0) return false;
        if (axis < 0) axis = p.axis, turn = p.turn;
        if (p.axis != axis || p.turn != turn) return false;
        const int from = direction_class(topo.points[s], topo.points[x], axis);
        const int to = direction_class(topo.points[s], topo.points[tri[(c + 2) % 3]], axis);
        advance += ((turn > 0 ? to - from : from - to) + 8) % 8;
      }
      if (forward != 1) return false;
    }
    return axis >= 0 && advance == 8;
  };
  const std::size_t meshes = topo.mesh_vertex_begin.size() - 1;
  for (std::size_t m = 0; m < meshes; ++m) {
    if (!fans_of[m]) continue;
    const std::uint32_t first = topo.mesh_vertex_begin[m], last = topo.mesh_vertex_begin[m + 1];
    run_parallel(threads, last - first, 1024, [&](std::size_t begin, std::size_t end) {
      for (std::size_t v = first + begin; v < first + end; ++v)
        fan[v] = embedded(static_cast<std::uint32_t>(v)) ? 1 : 0;
    });
  }
  return fan;
}

// Whether triangles t and u (sharing at most one vertex) provably yield no crossing under every
// infinitesimal perturbation, so the exact tests can be skipped: the non-shared corners of one lie
// strictly on one side of the other's plane, or the two are coplanar and a line through an edge of
// one strictly separates them (with a shared vertex: a line through it and an edge). Flat sheets
// make most neighbouring pairs coplanar, where the perturbed tests would otherwise do all the work.
// The exact sides found on the way are kept in `sides` for the edge tests (0 where not known).
struct PairSides {
  std::array<int, 3> of_t{}, of_u{};  // t's corners against u's plane, u's against t's
  bool coplanar = false;  // the two lie exactly in one plane (and no line separates them)
};

bool surely_apart_at(const std::vector<Vec3>& P, const std::array<std::uint32_t, 3>& a,
                     const std::array<std::uint32_t, 3>& b, const TriPlane& plane_a,
                     const TriPlane& plane_b, PairSides& sides) {
  auto one_side = [&](const std::array<std::uint32_t, 3>& plane, const TriPlane& info,
                      const std::array<std::uint32_t, 3>& other, bool& coplanar, std::array<int, 3>& side) {
    // A plane normal to an axis (flat sheets: nearly every plane) is decided exactly by one
    // comparison per point (AxisPlane). Other planes try the filter first.
    std::optional<PlaneFilter> filter;
    std::optional<AxisPlane> flat;
    if (info.axis >= 0) flat.emplace(P[plane[0]][info.axis], info.axis, info.axis_turn);
    else filter.emplace(P[plane[0]], P[plane[1]], P[plane[2]]);
    int pos = 0, neg = 0, zero = 0;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = other[k];
      if (contains(plane, v)) continue;
      int o = 0;
      if (flat) {
        o = flat->side(P[v]);
      } else {
        o = filter->side(P[v]);
        if (o == 0) o = orient_exact(P, plane[0], plane[1], plane[2], v);
      }
      side[k] = o;
      pos += o > 0;
      neg += o < 0;
      zero += o == 0;
    }
    coplanar = pos == 0 && neg == 0;
    return zero == 0 && (pos == 0 || neg == 0);
  };
  bool coplanar_b = false, coplanar_a = false;
  if (one_side(a, plane_a, b, coplanar_b, sides.of_u)) return true;
  // b's free corners in a's plane: b lies in that plane (or is degenerate), a in b's, and the test
  // from b's side can only find zeros.
  if (!coplanar_b && one_side(b, plane_b, a, coplanar_a, sides.of_t)) return true;
  if (!coplanar_b) return false;
  sides.coplanar = true;
  // Coplanar: project along the dominant axis of t's normal (skip degenerate projections).
  const int drop = plane_a.drop;
  const int turn_a = plane_a.turn;
  const int turn_b = plane_b.drop == drop ? plane_b.turn : orient_2d(P[b[0]], P[b[1]], P[b[2]], drop);
  if (turn_a == 0 || turn_b == 0) return false;
  // Sharing one vertex s: apart when no corner ray of one lies in the other's closed sector at s
  // (the sectors then meet only in s, with an angle between them on both sides). This decides the
  // pairs across a vertex of a flat grid, whose edges through s are collinear, so that no line
  // through an edge separates them.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (a[i] != b[j]) continue;
      const Vec3& centre = P[a[i]];
      // (tri[k], tri[k+1], tri[k+2]) turns like the triangle.
      auto sector = [&](const std::array<std::uint32_t, 3>& tri, int k, int turn) {
        std::array<std::uint32_t, 2> rays{tri[(k + 1) % 3], tri[(k + 2) % 3]};
        if (turn < 0) std::swap(rays[0], rays[1]);
        return rays;  // counter-clockwise in the projection
      };
      const auto sa = sector(a, i, turn_a), sb = sector(b, j, turn_b);
      auto inside = [&](const std::array<std::uint32_t, 2>& rays, std::uint32_t v) {
        return orient_2d(centre, P[rays[0]], P[v], drop) >= 0 &&
               orient_2d(centre, P[v], P[rays[1]], drop) >= 0;
      };
      return !inside(sa, sb[0]) && !inside(sa, sb[1]) && !inside(sb, sa[0]) && !inside(sb, sa[1]);
    }
  }
  // A line through two corners of one triangle separates when its third corner lies strictly on
  // one side and every corner of the other triangle not on the line lies strictly on the other,
  // with at most the shared vertex on the line.
  // The third corner's side of an edge line is the triangle's turn (the same for its three edges).
  auto separates = [&](const std::array<std::uint32_t, 3>& x, const std::array<std::uint32_t, 3>& y,
                       int own) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = x[k], j = x[(k + 1) % 3];
      bool ok = true;
      for (std::uint32_t v : y) {
        if (v == i || v == j) continue;
        if (orient_2d(P[i], P[j], P[v], drop) != -own) {
          ok = false;
          break;
        }
      }
      if (ok) return true;
    }
    return false;
  };
  return separates(a, b, turn_a) || separates(b, a, turn_b);
}

}  // namespace

TriPlane triangle_plane(const std::vector<Vec3>& points, const std::array<std::uint32_t, 3>& tri) {
  return tri_plane(points, tri);
}

bool triangles_surely_apart(const std::vector<Vec3>& points, const std::array<std::uint32_t, 3>& a,
                            const std::array<std::uint32_t, 3>& b) {
  PairSides sides;
  return surely_apart_at(points, a, b, tri_plane(points, a), tri_plane(points, b), sides);
}

bool triangles_surely_apart(const std::vector<Vec3>& points, const std::array<std::uint32_t, 3>& a,
                            const std::array<std::uint32_t, 3>& b, const TriPlane& plane_a,
                            const TriPlane& plane_b) {
  PairSides sides;
  return surely_apart_at(points, a, b, plane_a, plane_b, sides);
}

std::uint32_t CrossingSet::find(std::uint32_t edge, std::uint32_t face) const {
  auto it = std::lower_bound(items.begin(), items.end(), std::make_pair(edge, face),
                             [](const RawCrossing& c, const std::pair<std::uint32_t, std::uint32_t>& k) {
                               return c.edge != k.first ? c.edge < k.first : c.face < k.second;
                             });
  if (it == items.end() || it->edge != edge || it->face != face) return kNone;
  return static_cast<std::uint32_t>(it - items.begin());
}

bool edge_crosses_triangle(const std::vector<Vec3>& points, std::uint32_t p, std::uint32_t q,
                           std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  const int sp = orient_sos(points, a, b, c, p);
  const int sq = orient_sos(points, a, b, c, q);
  if (sp == sq) return false;
  return line_through_triangle(points, p, q, a, b, c);
}

Vec3 crossing_point(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const Vec3 v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const Vec3 n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double dp = n[0] * (p[0] - a[0]) + n[1] * (p[1] - a[1]) + n[2] * (p[2] - a[2]);
  const double dq = n[0] * (q[0] - a[0]) + n[1] * (q[1] - a[1]) + n[2] * (q[2] - a[2]);
  double s = 0.5;  // degenerate (coplanar) configurations: the perturbation decided, use the middle
  if (dp != dq) s = dp / (dp - dq);
  if (!(s >= 0.0)) s = 0.0;
  if (s > 1.0) s = 1.0;
  return {p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]), p[2] + s * (q[2] - p[2])};
}

namespace {

// update_crossings finds a mesh's own pairs by parts (retested among themselves, retested with the
// rest) when at least 1 / kWholeMeshShare of the mesh's triangles are retested.
constexpr std::size_t kWholeMeshShare = 4;

// The broad phase: `visit(part, t, u, sides)` for every candidate pair (t, u) (t < u) whose closed
// boxes overlap and that share at most one vertex, each pair once, t or u a triangle of a tested
// (not skipped) mesh, with the sides `prune` (surely_apart) found exactly. The descents of the
// hierarchies are split into independent parts run in parallel, descent and tests together;
// `visit` receives the part's index so results can be kept per part and joined in order
// (deterministic: the parts depend only on the trees).
template <class Visit>
void for_each_candidate(const SceneTopology& topo, const DetectSettings& settings, bool prune,
                        const Visit& visit) {
  const std::size_t meshes = topo.mesh_tri_begin.size() - 1;
  const bool skipping = !settings.skip_among.empty();
  auto skipped = [&](std::size_t m) { return skipping && settings.skip_among[m]; };
  std::vector<std::unique_ptr<TriangleBvh>> per_mesh(meshes);
  // A mesh whose own pairs are not tested needs only the triangles that can meet another mesh:
  // culled first by a linear pass (cull_triangles), so that its hierarchy is built over those.
  std::vector<bool> cull(meshes);
  for (std::size_t m = 0; m < meshes; ++m)
    cull[m] = (!settings.self_pairs || skipped(m)) && !(skipped(m) && settings.skipped_bvh != nullptr);
  const std::vector<std::vector<std::uint32_t>> kept = cull_triangles(topo, cull, settings.threads);
  // One hierarchy per mesh, built in parallel (each into its own slot: the same trees for every
  // thread count); meanwhile, for pruning, the TriPlane of each triangle in them, in chunks (a
  // flat sheet's triangle is in a dozen pairs). The shared hierarchy of skipped meshes has none.
  auto own_tree = [&](std::size_t m) { return !(skipped(m) && settings.skipped_bvh != nullptr); };
  std::unique_ptr<TriPlane[]> planes(prune ? new TriPlane[topo.tris.size()] : nullptr);
  constexpr std::size_t kChunk = 4096;
  struct Chunk {
    std::uint32_t mesh;
    std::size_t begin, end;  // in kept[mesh]
  };
  std::vector<Chunk> chunks;
  for (std::size_t m = 0; m < meshes && prune; ++m)
    if (own_tree(m))
      for (std::size_t i = 0; i < kept[m].size(); i += kChunk)
        chunks.push_back({static_cast<std::uint32_t>(m), i, std::min(kept[m].size(), i + kChunk)});
  run_parallel(settings.threads, meshes + chunks.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      if (k < meshes) {
        if (own_tree(k)) {
          per_mesh[k] = std::make_unique<TriangleBvh>(topo, kept[k]);
          // Detection of the mesh's own pairs skips those inside flat patches (no crossing there).
          if (prune && settings.self_pairs && !skipped(k)) per_mesh[k]->mark_flat_patches(topo);
        }
        continue;
      }
      const Chunk& c = chunks[k - meshes];
      for (std::size_t i = c.begin; i < c.end; ++i) {
        const std::uint32_t t = kept[c.mesh][i];
        planes[t] = tri_plane(topo.points, topo.tris[t]);
      }
    }
  });
  auto plane_of = [&](std::uint32_t t) {
    if (own_tree(topo.tri_mesh[t])) return planes[t];
    return settings.skipped_planes ? (*settings.skipped_planes)[t] : tri_plane(topo.points, topo.tris[t]);
  };
  // Pairs inside a mesh that share one vertex: apart without a test around a flat fan.
  std::vector<std::uint8_t> fan;
  if (prune && settings.self_pairs) {
    std::vector<bool> fans_of(meshes);
    for (std::size_t m = 0; m < meshes; ++m) fans_of[m] = own_tree(m) && !skipped(m);
    fan = flat_fans(topo, planes.get(), fans_of, settings.threads);
  }
  // The descents to make: each tested mesh with itself (self pairs) and with every later mesh,
  // and with the skipped meshes' shared hierarchy when there is one.
  struct Descent {
    const TriangleBvh* a;
    const TriangleBvh* b;
    bool self;
  };
  std::vector<Descent> descents;
  for (std::size_t a = 0; a < meshes; ++a) {
    if (skipped(a)) continue;
    if (settings.self_pairs) descents.push_back({per_mesh[a].get(), per_mesh[a].get(), true});
    for (std::size_t b = a + 1; b < meshes; ++b) {
      if (skipped(b) && settings.skipped_bvh != nullptr) continue;  // below, all at once
      descents.push_back({per_mesh[a].get(), per_mesh[b].get(), false});
    }
    if (skipping && settings.skipped_bvh != nullptr)
      descents.push_back({per_mesh[a].get(), settings.skipped_bvh, false});
  }
  // Skipped meshes before a tested one were visited from the tested side above (b > a only covers
  // later meshes): pair earlier skipped meshes too.
  if (!(skipping && settings.skipped_bvh != nullptr)) {
    for (std::size_t a = 0; a < meshes; ++a) {
      if (!skipped(a)) continue;
      for (std::size_t b = a + 1; b < meshes; ++b)
        if (!skipped(b)) descents.push_back({per_mesh[a].get(), per_mesh[b].get(), false});
    }
  }
  struct Job {
    std::uint32_t descent;
    TriangleBvh::Part part;
  };
  std::vector<Job> jobs;
  for (std::size_t d = 0; d < descents.size(); ++d)
    for (const TriangleBvh::Part& part : descents[d].a->split(*descents[d].b, descents[d].self, kParts))
      jobs.push_back({static_cast<std::uint32_t>(d), part});
  visit.start(jobs.size());
  // Corners as detection sees them: a position shared across meshes is one point (DESIGN §2). One
  // mesh's own vertices never share a position, so within a mesh these are its welded corners.
  const auto& tris = topo.detect_tris();
  run_parallel(settings.threads, jobs.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const Descent& d = descents[jobs[k].descent];
      d.a->each_pair_in(*d.b, jobs[k].part, d.self, [&](std::uint32_t x, std::uint32_t y) {
        const std::uint32_t t = std::min(x, y), u = std::max(x, y);
        const auto &a = tris[t], &b = tris[u];
        int shared = 0, count = 0;
        for (int i = 0; i < 3; ++i)
          if (a[i] == b[0] || a[i] == b[1] || a[i] == b[2]) shared = i, ++count;
        if (count >= 2) return;
        // A flat fan is one mesh's, around its own welded vertex: across meshes it says nothing.
        if (count == 1 && !fan.empty() && fan[topo.tris[t][shared]] && topo.tri_mesh[t] == topo.tri_mesh[u])
          return;
        PairSides sides;
        if (prune && surely_apart_at(topo.points, a, b, plane_of(t), plane_of(u), sides))
          return;
        visit(k, t, u, sides);
      });
    }
  });
}

// Results kept per part of the descents (or block of pairs) and joined in order.
template <class T, class Body>
struct BlockSink {
  std::vector<std::vector<T>>& found;
  Body body;
  void start(std::size_t blocks) const { found.assign(blocks, {}); }
  void operator()(std::size_t block, std::uint32_t t, std::uint32_t u, const PairSides& sides) const {
    body(found[block], t, u, sides);
  }
};
template <class T, class Body>
BlockSink<T, Body> sink(std::vector<std::vector<T>>& found, Body body) {
  return {found, body};
}

}  // namespace

std::vector<std::array<std::uint32_t, 2>> candidate_pairs(const SceneTopology& topo,
                                                          const DetectSettings& settings) {
  std::vector<std::vector<std::array<std::uint32_t, 2>>> found;
  for_each_candidate(topo, settings, false,
                     sink(found, [](auto& out, std::uint32_t t, std::uint32_t u, const PairSides&) {
                       out.push_back({t, u});
                     }));
  std::vector<std::array<std::uint32_t, 2>> pairs;
  for (auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

CrossingSet detect_crossings(const SceneTopology& topo, const DetectSettings& settings) {
  std::vector<std::vector<RawCrossing>> found;
  // Exactly coplanar pairs of two meshes, per part (contacts, DESIGN §2): found where the pruning
  // test met them, so they cost nothing elsewhere.
  std::vector<std::vector<std::array<std::uint32_t, 2>>> coplanar;
  struct Sink {
    const SceneTopology& topo;
    std::vector<std::vector<RawCrossing>>& found;
    std::vector<std::vector<std::array<std::uint32_t, 2>>>& coplanar;
    void start(std::size_t blocks) const {
      found.assign(blocks, {});
      coplanar.assign(blocks, {});
    }
    void operator()(std::size_t block, std::uint32_t t, std::uint32_t u, const PairSides& sides) const {
      test_owned_edges(topo, t, u, sides.of_t, found[block]);
      test_owned_edges(topo, u, t, sides.of_u, found[block]);
      if (sides.coplanar && topo.tri_mesh[t] != topo.tri_mesh[u]) coplanar[block].push_back({t, u});
    }
  };
  for_each_candidate(topo, settings, true, Sink{topo, found, coplanar});
  CrossingSet set;
  for (auto& block : found) set.items.insert(set.items.end(), block.begin(), block.end());
  for (auto& block : coplanar)
    set.coplanar_pairs.insert(set.coplanar_pairs.end(), block.begin(), block.end());
  std::sort(set.coplanar_pairs.begin(), set.coplanar_pairs.end());
  std::sort(set.items.begin(), set.items.end(), [](const RawCrossing& a, const RawCrossing& b) {
    return a.edge != b.edge ? a.edge < b.edge : a.face < b.face;
  });
  return set;
}

SceneHierarchy::SceneHierarchy(const SceneTopology& topo, const DetectSettings& settings) {
  const std::size_t meshes = topo.mesh_tri_begin.size() - 1;
  auto skipped = [&](std::size_t m) { return m < settings.skip_among.size() && settings.skip_among[m]; };
  per_mesh_.resize(meshes);
  moved_since_build_.assign(meshes, 0);
  run_parallel(settings.threads, meshes, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t m = begin; m < end; ++m) {
      if (skipped(m) && settings.skipped_bvh != nullptr) continue;  // queried through that one
      std::vector<bool> only(meshes, false);
      only[m] = true;
      per_mesh_[m] = std::make_unique<TriangleBvh>(topo, only);
    }
  });
}

void SceneHierarchy::update(const SceneTopology& topo, const std::vector<std::uint8_t>& moved) {
  const std::size_t meshes = per_mesh_.size();
  std::vector<std::size_t> count(meshes, 0);
  for (std::uint32_t v = 0; v < moved.size(); ++v)
    if (moved[v]) ++count[topo.vertex_mesh[v]];
  for (std::size_t m = 0; m < meshes; ++m) {
    if (count[m] == 0 || !per_mesh_[m]) continue;
    moved_since_build_[m] += count[m];
    const std::size_t size = topo.mesh_vertex_begin[m + 1] - topo.mesh_vertex_begin[m];
    if (4 * moved_since_build_[m] > size) {
      std::vector<bool> only(meshes, false);
      only[m] = true;
      per_mesh_[m] = std::make_unique<TriangleBvh>(topo, only);
      moved_since_build_[m] = 0;
    } else {
      per_mesh_[m]->refit(topo);
    }
  }
}

// update_steps.h
void test_pair(const SceneTopology& topo, std::uint32_t t, std::uint32_t u, const TriPlane& plane_t,
               const TriPlane& plane_u, std::vector<RawCrossing>& out) {
  const auto& tris = topo.detect_tris();
  PairSides sides;
  if (surely_apart_at(topo.points, tris[t], tris[u], plane_t, plane_u, sides)) return;
  test_owned_edges(topo, t, u, sides.of_t, out);
  test_owned_edges(topo, u, t, sides.of_u, out);
}

// update_steps.h
CrossingSet merge_update(const SceneTopology& topo, const CrossingSet& previous,
                         const std::vector<std::uint8_t>& moved,
                         const std::vector<std::vector<RawCrossing>>& found) {
  CrossingSet set;
  auto unmoved = [&](const RawCrossing& c) {
    for (std::uint32_t v : topo.edges[c.edge])
      if (moved[v]) return false;
    for (std::uint32_t v : topo.tris[c.face])
      if (moved[v]) return false;
    return true;
  };
  for (const RawCrossing& c : previous.items)
    if (unmoved(c)) set.items.push_back(c);
  for (const auto& block : found) set.items.insert(set.items.end(), block.begin(), block.end());
  auto key_less = [](const RawCrossing& a, const RawCrossing& b) {
    return a.edge != b.edge ? a.edge < b.edge : a.face < b.face;
  };
  std::sort(set.items.begin(), set.items.end(), key_less);
  // An unmoved crossing is found again when its edge's owner triangle has another corner that
  // moved: keep one copy (both were computed from the same positions).
  set.items.erase(std::unique(set.items.begin(), set.items.end(),
                              [](const RawCrossing& a, const RawCrossing& b) {
                                return a.edge == b.edge && a.face == b.face;
                              }),
                  set.items.end());
  return set;
}

CrossingSet update_crossings(const SceneTopology& topo, const DetectSettings& settings,
                             const SceneHierarchy& hierarchy, const CrossingSet& previous,
                             const std::vector<std::uint8_t>& moved) {
  // Triangles with a moved corner, found through the moved vertices' edges.
  std::vector<std::uint8_t> affected(topo.tris.size(), 0);
  std::vector<std::uint32_t> retest;
  for (std::uint32_t v = 0; v < moved.size(); ++v) {
    if (!moved[v]) continue;
    for (std::uint32_t i = topo.vertex_edge_begin[v]; i < topo.vertex_edge_begin[v + 1]; ++i) {
      const std::uint32_t e = topo.vertex_edges[i];
      for (std::uint32_t k = topo.edge_face_begin[e]; k < topo.edge_face_begin[e + 1]; ++k) {
        const std::uint32_t t = topo.edge_faces[k];
        if (!affected[t]) {
          affected[t] = 1;
          retest.push_back(t);
        }
      }
    }
  }
  std::sort(retest.begin(), retest.end());

  // The retested triangles in a hierarchy of their own, descended together with each mesh's
  // (and the skipped meshes' shared one): the same overlapping pairs as a query per triangle, at
  // a fraction of the box tests.
  const std::size_t meshes = topo.mesh_tri_begin.size() - 1;
  auto skipped = [&](std::size_t m) { return m < settings.skip_among.size() && settings.skip_among[m]; };
  std::vector<std::vector<RawCrossing>> found;
  if (!retest.empty()) {
    const TriangleBvh moved_tree(topo, retest);
    // The TriPlane of each retested triangle, found once (a moved triangle is in several pairs,
    // and one of every pair is moved); only their slots are written and read.
    const auto& tris = topo.detect_tris();
    std::unique_ptr<TriPlane[]> planes(new TriPlane[topo.tris.size()]);
    run_parallel(settings.threads, retest.size(), 1024, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) planes[retest[i]] = tri_plane(topo.points, tris[retest[i]]);
    });
    auto plane_of = [&](std::uint32_t t) {
      if (affected[t]) return planes[t];
      if (settings.skipped_planes && settings.skipped_bvh && skipped(topo.tri_mesh[t]))
        return (*settings.skipped_planes)[t];
      return tri_plane(topo.points, tris[t]);
    };
    // Where many of a mesh's triangles are retested (a relaxation's sweep moves a third of a
    // garment), the pairs among them cost the most, and the retested tree against the mesh's own
    // finds each of them twice (once from either triangle). There the mesh's pairs are found as
    // the retested triangles' own pairs, once each (a descent of their tree with itself), and
    // their pairs with the mesh's other triangles (a tree over those); the other meshes' trees
    // are descended with a tree of the retested triangles of other meshes. The same pairs either
    // way (a pair is found when its triangles' boxes overlap), so the same crossings.
    std::vector<std::vector<std::uint32_t>> retest_of(meshes);
    for (const std::uint32_t t : retest) retest_of[topo.tri_mesh[t]].push_back(t);
    std::vector<std::uint8_t> by_parts(meshes, 0);
    for (std::size_t m = 0; m < meshes; ++m) {
      const std::size_t size = topo.mesh_tri_begin[m + 1] - topo.mesh_tri_begin[m];
      by_parts[m] = hierarchy.mesh(m) != nullptr && settings.self_pairs && !skipped(m) &&
                    kWholeMeshShare * retest_of[m].size() >= size;
    }
    std::vector<std::unique_ptr<TriangleBvh>> trees;  // built here for this update
    struct Descent {
      const TriangleBvh* a;
      const TriangleBvh* b;
      bool self;         // b is a: each pair once
      bool from_shared;  // b is the skipped meshes' shared tree
    };
    std::vector<Descent> descents;
    const bool shared_tree = settings.skipped_bvh != nullptr;
    for (std::size_t m = 0; m < meshes; ++m) {
      const TriangleBvh* tree = hierarchy.mesh(m);
      if (tree == nullptr) continue;
      if (!by_parts[m]) {
        descents.push_back({&moved_tree, tree, false, false});
        continue;
      }
      trees.push_back(std::make_unique<TriangleBvh>(topo, retest_of[m]));
      const TriangleBvh* own = trees.back().get();
      descents.push_back({own, own, true, false});
      std::vector<std::uint32_t> rest, others;
      for (std::uint32_t t = topo.mesh_tri_begin[m]; t < topo.mesh_tri_begin[m + 1]; ++t)
        if (!affected[t]) rest.push_back(t);
      for (const std::uint32_t t : retest)
        if (topo.tri_mesh[t] != m) others.push_back(t);
      for (std::vector<std::uint32_t>* list : {&rest, &others}) {
        if (list->empty()) continue;
        trees.push_back(std::make_unique<TriangleBvh>(topo, *list));
        descents.push_back(list == &rest ? Descent{own, trees.back().get(), false, false}
                                         : Descent{trees.back().get(), tree, false, false});
      }
    }
    if (shared_tree) descents.push_back({&moved_tree, settings.skipped_bvh, false, true});
    struct Job {
      std::uint32_t descent;
      TriangleBvh::Part part;
    };
    std::vector<Job> jobs;
    for (std::size_t k = 0; k < descents.size(); ++k)
      for (const TriangleBvh::Part& part :
           descents[k].a->split(*descents[k].b, descents[k].self, kParts))
        jobs.push_back({static_cast<std::uint32_t>(k), part});
    found.resize(jobs.size());
    run_parallel(settings.threads, jobs.size(), 1, [&](std::size_t begin, std::size_t end) {
      for (std::size_t j = begin; j < end; ++j) {
        const Descent& d = descents[jobs[j].descent];
        d.a->each_pair_in(*d.b, jobs[j].part, d.self, [&](std::uint32_t x, std::uint32_t y) {
          // t is the retested triangle (the lower of two in a descent with itself).
          const std::uint32_t t = d.self ? std::min(x, y) : x, u = d.self ? std::max(x, y) : y;
          const std::uint32_t tm = topo.tri_mesh[t], um = topo.tri_mesh[u];
          if (d.from_shared) {
            if (skipped(tm)) return;
          } else {
            if (um == tm && !settings.self_pairs) return;
            if (skipped(um) && skipped(tm)) return;
          }
          // A pair of two retested triangles is tested once, from the lower one.
          if (u == t || (affected[u] && u < t)) return;
          if (shared_vertices(tris[t], tris[u]) >= 2) return;
          test_pair(topo, t, u, plane_of(t), plane_of(u), found[j]);
        });
      }
    });
  }

  return merge_update(topo, previous, moved, found);
}

std::vector<std::array<std::uint32_t, 2>> intersecting_pairs(const SceneTopology& topo,
                                                             const CrossingSet& crossings) {
  // Sorted as one 64-bit key per pair (lexicographic order of (t, u)): comparing arrays element by
  // element cost several times more.
  std::vector<std::uint64_t> keys;
  keys.reserve(2 * crossings.items.size());
  for (const RawCrossing& c : crossings.items) {
    for (std::uint32_t i = topo.edge_face_begin[c.edge]; i < topo.edge_face_begin[c.edge + 1]; ++i) {
      const std::uint32_t t = topo.edge_faces[i];
      keys.push_back(std::uint64_t{std::min(t, c.face)} << 32 | std::max(t, c.face));
    }
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<std::array<std::uint32_t, 2>> pairs(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i)
    pairs[i] = {static_cast<std::uint32_t>(keys[i] >> 32), static_cast<std::uint32_t>(keys[i])};
  return pairs;
}

}  // namespace untangle
