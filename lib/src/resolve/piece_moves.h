// Pieces moved whole (DESIGN §5, "Pieces moved whole"): where the repair left small pieces
// interlocked with others (a ring through a tube's wall, a torus through a sheet, two links of a
// chain), no local move frees them: "the small side is illegal" has no small side on a ring's
// tube, and the contour on the other piece bounds a disk that any deformation still spans. Such a
// piece is moved as a whole, by the shortest of a set of translations that leaves it clear of
// every other piece and obstacle, before the repair runs again from there.
#pragma once

#include <vector>

#include "resolve/moves.h"
#include "untangle/fix.h"
#include "untangle/mesh.h"

namespace untangle {

class ObstacleWinding;

// A piece of at most this many triangles, tangled only with pieces and obstacles (each closed
// component; a mesh a vertex lies inside, whole) of at most as many, may be moved whole: rings,
// chain links, props interlocked with one another. Not a garment piece on a body (MakeHuman tops
// and trousers have 1,500 to 1,800 triangles, their bodies over 40,000), which a clear
// translation carries off the body.
constexpr std::size_t kMaxPieceTriangles = 2048;
// Translations tried: the piece's bounding-box diagonal times k / kPieceSteps for k = 1 to
// kPieceLongest (1/16 to half the diagonal), each along 26 directions of the piece's principal
// axes. Half its size at most: the move unhooks a piece, it does not carry it away; what is
// interlocked with a piece of its own size comes off in less (random tangles: of the 84 scenes
// the moves resolved with lengths up to the whole diagonal, 83 still are).
constexpr int kPieceSteps = 16;
constexpr int kPieceLongest = 8;

// On `meshes` (the input, canonical order, as run_repair takes them; moved in place): the pieces
// (edge-connected parts of the movable meshes) that cross another piece or an obstacle in `kept`
// (the attempt kept so far, the same meshes vertex for vertex), or have a vertex inside an
// obstacle there, are each moved whole, smallest first, by the shortest translation (the first of
// the 26 directions on a tie) that leaves it crossing no other piece or obstacle and with no
// vertex inside an obstacle, against the other pieces where they are by then; one with no such
// translation stays. Nothing moves (ran false) unless every such piece, every piece or obstacle
// component it crosses and every obstacle mesh it lies inside has at most kMaxPieceTriangles
// triangles, and no such piece has a pinned vertex or one shared with an obstacle. Exact
// predicates decide every crossing; the winding numbers decide inside. `round` (when given) is
// applied to every moved position. The record's pieces name the meshes by their index in
// `meshes` and the vertices by input_vertex (per mesh, per vertex of `meshes`: its index in the
// file), the lowest of the piece. `earlier`: the obstacles' winding numbers the repair built,
// shared (ObstacleWinding's `earlier`) rather than built again.
PieceMoveRecord move_pieces_whole(std::vector<Mesh>& meshes, const std::vector<Mesh>& kept,
                                  const FixOptions& options, const PinMask& pins,
                                  const Rounding& round,
                                  const std::vector<std::vector<std::uint32_t>>& input_vertex,
                                  const ObstacleWinding* earlier = nullptr);

}  // namespace untangle
