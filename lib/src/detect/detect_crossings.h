// Broad and narrow phase: every edge-through-face crossing of a scene, decided exactly.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "detect/triangle_bvh.h"
#include "topology/scene_topology.h"

namespace untangle {

// A crossing in global topology ids: edge `edge` passes through the interior of triangle `face`.
struct RawCrossing {
  std::uint32_t edge = 0;
  std::uint32_t face = 0;
  Vec3 point{};
};

// Crossings sorted by (edge, face), unique.
struct CrossingSet {
  std::vector<RawCrossing> items;
  // Triangle pairs (t < u) of two different meshes lying exactly in one plane and not surely apart
  // there (contacts, DESIGN §2), sorted; found by detect_crossings only (update_crossings leaves it
  // empty).
  std::vector<std::array<std::uint32_t, 2>> coplanar_pairs;
  // Index of the crossing (edge, face), or kNone.
  std::uint32_t find(std::uint32_t edge, std::uint32_t face) const;
};

// What the pruning test (triangles_surely_apart) needs of one triangle alone: found once per
// triangle by a caller that meets a triangle in many pairs.
struct TriPlane {
  std::int8_t axis;       // the corners share this coordinate bit for bit (the lowest such), or -1
  std::int8_t axis_turn;  // AxisPlane's turn when axis >= 0
  std::int8_t drop;       // the dominant axis of the rounded normal: coplanar tests project along it
  std::int8_t turn;       // orient_2d of the corners along drop (0: degenerate there)
};
TriPlane triangle_plane(const std::vector<Vec3>& points, const std::array<std::uint32_t, 3>& tri);

struct DetectSettings {
  int threads = 0;
  // Pairs of triangles that both belong to meshes flagged here are not tested (obstacles that
  // never move need no re-detection among themselves). Empty = test every pair.
  std::vector<bool> skip_among;
  // Optional: a hierarchy over exactly the triangles of the skip_among meshes at their current
  // positions (they never move, so it is built once and reused every iteration).
  const TriangleBvh* skipped_bvh = nullptr;
  // Optional, with skipped_bvh: per triangle of the scene, its TriPlane where the triangle is one
  // of the skip_among meshes' (at the same positions; other entries are not read).
  const std::vector<TriPlane>* skipped_planes = nullptr;
  // Whether pairs of triangles of the same mesh are tested (self-intersections).
  bool self_pairs = true;
};

// Whether edge (p, q) passes through triangle (a, b, c) under the symbolic perturbation; ids are
// global welded vertex ids into `points`. The edge must share no vertex with the triangle.
bool edge_crosses_triangle(const std::vector<Vec3>& points, std::uint32_t p, std::uint32_t q,
                           std::uint32_t a, std::uint32_t b, std::uint32_t c);

// Whether triangles a and b (corner ids into `points`, sharing at most one vertex) provably yield
// no crossing under every infinitesimal perturbation, so the exact tests can be skipped: the
// non-shared corners of one lie strictly on one side of the other's plane, or the two are coplanar
// and a line through an edge of one strictly separates them (with a shared vertex: a line through
// it and an edge). Flat sheets make most neighbouring pairs coplanar, where the perturbed tests
// would otherwise do all the work.
bool triangles_surely_apart(const std::vector<Vec3>& points, const std::array<std::uint32_t, 3>& a,
                            const std::array<std::uint32_t, 3>& b);
// The same with the triangles' planes known (triangle_plane of a and b).
bool triangles_surely_apart(const std::vector<Vec3>& points, const std::array<std::uint32_t, 3>& a,
                            const std::array<std::uint32_t, 3>& b, const TriPlane& plane_a,
                            const TriPlane& plane_b);

// The crossing point constructed in double (within the segment; steering only).
Vec3 crossing_point(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

// Candidate triangle pairs (t < u) whose closed bounding boxes overlap and that share no edge,
// sorted. The broad phase is a bounding-volume hierarchy (TriangleBvh) queried per triangle.
std::vector<std::array<std::uint32_t, 2>> candidate_pairs(const SceneTopology& topology,
                                                          const DetectSettings& settings);

// Every crossing. Each edge is tested against a face only from its lowest incident triangle.
CrossingSet detect_crossings(const SceneTopology& topology, const DetectSettings& settings);

// The hierarchies of a scene's tested meshes, kept across iterations of fix. After vertices move,
// the trees of the meshes that hold them are refitted (the same tree, new boxes), or rebuilt once
// a quarter of a mesh's vertices have moved since it was built (refitted boxes grow loose).
class SceneHierarchy {
 public:
  SceneHierarchy(const SceneTopology& topology, const DetectSettings& settings);
  void update(const SceneTopology& topology, const std::vector<std::uint8_t>& moved);
  // The tree of mesh m; nullptr for the meshes of settings.skip_among when settings.skipped_bvh
  // holds them.
  const TriangleBvh* mesh(std::size_t m) const { return per_mesh_[m].get(); }

 private:
  std::vector<std::unique_ptr<TriangleBvh>> per_mesh_;
  std::vector<std::size_t> moved_since_build_;
};

// The crossings after the welded vertices flagged in `moved` changed position, given the crossings
// before (`previous`, same topology) and the hierarchy already updated to the new positions. Only
// triangles with a moved corner are tested again, against every triangle their boxes overlap;
// crossings between unmoved edges and faces are kept. The result equals detect_crossings on the
// new positions (tests/test_incremental_detection.cpp), at a cost that follows the moved part.
CrossingSet update_crossings(const SceneTopology& topology, const DetectSettings& settings,
                             const SceneHierarchy& hierarchy, const CrossingSet& previous,
                             const std::vector<std::uint8_t>& moved);

// Distinct intersecting triangle pairs (t < u), sorted: a pair intersects iff an edge of one
// crosses the other.
std::vector<std::array<std::uint32_t, 2>> intersecting_pairs(const SceneTopology& topology,
                                                             const CrossingSet& crossings);

}  // namespace untangle
