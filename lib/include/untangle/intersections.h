// Finding intersections: crossings (edge through face), contours and their track types.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "untangle/mesh.h"
#include "untangle/mesh_info.h"

namespace untangle {

// Track types of the paper (§II): closed; both ends on this track's mesh boundary; one end on the
// boundary and one inside; both ends inside.
enum class TrackType { kCL, kBB, kBI, kII };
const char* to_string(TrackType type);

// An edge of mesh `edge_mesh` passing through the interior of triangle `face` of mesh `face_mesh`
// (possibly the same mesh), the two sharing no vertex. Decided with exact predicates under one
// symbolic perturbation, so degenerate input (vertex on face, edge through edge, coplanar or
// duplicated geometry) still yields 0 or 2 crossings per pair of triangles sharing no vertex.
struct Crossing {
  std::uint32_t edge_mesh = 0;
  std::uint32_t edge_v0 = 0, edge_v1 = 0;  // the edge, as input vertex indices of edge_mesh
  std::uint32_t face_mesh = 0;
  std::uint32_t face = 0;  // triangle index in face_mesh
  Vec3 point{};            // e ∩ f, constructed in double (steers, never decides)
};

// A contour seen on one surface.
struct Track {
  std::uint32_t mesh = 0;
  TrackType type = TrackType::kCL;
  std::size_t boundary_ends = 0;
  std::size_t cut_edges = 0;  // edges of this mesh crossed an odd number of times by the contour
  // For CL and BB tracks (unless DetectOptions::separation is off, when they keep these defaults):
  // whether cutting those edges splits the mesh component the track lies on
  // (flood fill, DESIGN §4), and the area of the smaller side (triangle areas shared equally among
  // their corners). The two sides are grown in lock step from the first cut edge, so the side
  // found is the one with fewer vertices and the cost is that side's size, not the mesh's. A track
  // that cuts no edge encloses no vertex: it separates (a disc inside faces) with area 0.
  bool separates = false;
  double smaller_area = 0.0;
};

// An intersection curve: a maximal chain of crossings linked through intersecting triangle pairs.
struct Contour {
  std::array<Track, 2> tracks;  // tracks[0] holds the edge of the first crossing
  bool closed = false;
  bool self = false;                // both tracks on the same mesh
  std::size_t loop_vertices = 0;    // ends at a vertex shared by the two intersecting triangles
  std::size_t branch_points = 0;    // crossings on non-manifold edges (3+ faces)
  std::vector<std::uint32_t> crossings;  // indices into Intersections::crossings, in walk order
  std::vector<Vec3> polyline;  // the crossing points (and loop vertices) in walk order
  double length = 0.0;          // polyline length, closing segment included when closed
};

// Exact contact between two meshes, or within one (DESIGN §2, "Contact is not penetration"):
// coincidences decided on the coordinates as given, bit for bit, never by a tolerance. They are
// not crossings: a position that is a vertex of an obstacle and of other meshes is one point for
// detection (edges and faces through it share a vertex, as within one mesh), a face repeated with
// either winding is left out of detection, and fix pins the movable vertices at such positions.
// Positions shared by movable meshes alone stay two points (fix can part them).
struct MeshContact {
  std::uint32_t mesh_a = 0, mesh_b = 0;  // mesh_a <= mesh_b, input order; equal: within one mesh
  // Positions that are a vertex of both meshes and of an obstacle (garment seams sewn onto body
  // vertices); 0 when mesh_a == mesh_b (a mesh's own equal positions are welded).
  std::size_t seam_vertices = 0;
  // Faces with the same three positions as another face, either winding: across the two meshes,
  // the distinct repeated faces whose corners are all seam vertices; within one mesh, the later copies, which detection leaves out
  // (kept in the output).
  std::size_t repeated_faces = 0;
  // Triangle pairs, one of each mesh, that lie exactly in one plane and touch or overlap there
  // (sharing at most one position). Counted, and decided by the symbolic perturbation like every
  // other exact zero (DESIGN §2: leaving them out would break the 0-or-2 property).
  std::size_t coplanar_pairs = 0;
};

// Counts of one detection (the report's `before` / `after` objects).
struct IntersectionCounts {
  std::size_t crossings = 0;
  std::size_t triangle_pairs = 0;  // distinct intersecting triangle pairs (sharing no edge)
  std::size_t contours = 0;
  double contour_length = 0.0;
  std::array<std::size_t, 4> tracks{};  // by TrackType
  std::size_t pairs_cl_cl = 0, pairs_bb_ii = 0, pairs_bi_bi = 0, pairs_self = 0, pairs_other = 0;
  std::size_t loop_vertices = 0;
  std::size_t non_separating = 0;  // CL or BB tracks that separate nothing (0 without separation)
  std::size_t branch_points = 0;
  // Contours whose walk failed (a crossing link without partner). Always 0 unless the 0-or-2
  // crossings property is violated, i.e. a bug; the property tests assert it.
  std::size_t broken = 0;
  // Welded vertices of movable meshes inside an obstacle mesh: where its generalized winding
  // number (Jacobson et al. 2013) exceeds 1/2, for closed and open obstacles alike (DESIGN §4).
  // They are illegal even where nothing crosses (a garment wholly inside a body). In total and per
  // mesh, in input order (0 for obstacles); all 0 in a scene without obstacles.
  std::size_t inside_vertices = 0;
  std::vector<std::size_t> inside_by_mesh;
  // Exact contacts, one entry per pair of meshes that has any, sorted by (mesh_a, mesh_b).
  std::vector<MeshContact> contacts;
};

struct Intersections {
  std::vector<Crossing> crossings;  // sorted by (edge mesh, edge, face mesh, face)
  std::vector<Contour> contours;    // in the order of their lowest crossing
  IntersectionCounts counts;
  // Intersecting triangle pairs as (mesh, triangle) pairs, each pair ordered, sorted.
  std::vector<std::array<std::uint32_t, 4>> triangle_pairs;
};

struct DetectOptions {
  int threads = 0;  // 0 = all cores; the result is identical for every value
  // Leave out pairs of triangles that both belong to obstacles (obstacles never move, so `fix`
  // neither needs nor can change what happens among them).
  bool skip_obstacle_pairs = false;
  // Whether each mesh is also tested against itself (self-intersections). Off: only pairs of
  // different meshes, the job of CGAL's surface_intersection.
  bool self_intersections = true;
  // Whether CL and BB tracks are tested for separation: Track::separates and Track::smaller_area,
  // found by flood fills of the mesh (region analysis, DESIGN §4), and the count non_separating.
  // Off: those keep their defaults (false, 0.0, 0) and the floods are skipped; crossings, pairs,
  // contours, track types and cut edges are the same either way. Detection and contours alone
  // are what CGAL's surface_intersection computes (its intersection polylines).
  bool separation = true;
};

struct DetectTimings {
  double detect_ms = 0.0;    // topology, broad and narrow phase
  double topology_ms = 0.0;  // of which welding and edge topology (the input preparation)
  double contours_ms = 0.0;  // linking, classification, flood fills (DetectOptions::separation)
};

// Finds every crossing between every pair of meshes and within each mesh, builds contours and
// classifies their tracks. Deterministic. Never prints. Thread-safe for distinct inputs.
// `infos`, when given, receives describe_mesh of every mesh, made from the topology detection
// builds anyway (check describes its inputs: one welding per run instead of two).
Intersections find_intersections(const std::vector<Mesh>& meshes, const DetectOptions& options = {},
                                 DetectTimings* timings = nullptr, std::vector<MeshInfo>* infos = nullptr);

}  // namespace untangle
