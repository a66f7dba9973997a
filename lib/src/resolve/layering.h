// Layering (DESIGN §5, "Layers"): garments worn one over another. Repaired together, two garments
// that lie a fraction of an edge apart over a whole body cross in thousands of places, and "the
// small side is illegal" has no small side to find. One at a time the job is shallow: each garment
// alone on the body, then each laid over the ones inside it while they grow back from the body's
// surface to their places.
#pragma once

#include <vector>

#include "resolve/moves.h"
#include "untangle/fix.h"
#include "untangle/mesh.h"

namespace untangle {

// The layers are the edge-connected pieces of the movable meshes (welded by position): a top and
// the trousers in one garment file are two layers, as two garments are.

// Whether the layering can change the result of `input` whose attempt kept is `kept` (the same
// meshes at the positions of that attempt): an obstacle and two or more layers, and with a
// single movable mesh, two of its pieces crossing in `kept` (its repair alone is that attempt,
// so with none crossing every piece would lie where it is: measured on the MakeHuman garments on
// their bodies scaled 1.05, the layering doubled the time and wrote the same).
bool worth_layering(const std::vector<Mesh>& input, const std::vector<Mesh>& kept, int threads);

// Runs the layering on `meshes` (the canonical scene at its input positions in, the result out;
// obstacles are never moved):
//  1. each movable mesh is repaired alone with the obstacles (fix_meshes, without the layering);
//  2. the layers are ordered by the median distance of their vertices to the obstacles, nearest
//     first (ties by canonical order of meshes, then pieces: the listing order does not matter);
//  3. from the second on, each is laid over those before it: if it crosses them, they stand as
//     obstacles, flattened onto the obstacles' surface (each vertex to its closest point there)
//     and grown back to their places in the continuation's steps, the layer repaired and relaxed
//     toward the shape it had alone after each (run_continuation, stage 5);
//  4. where the whole scene then ends unresolved or beyond `options.bounds`, step 3 runs again
//     from the meshes of step 1 in the order where the layers overlap (layer_order in
//     layering.cpp), when it differs, and the better of the two is kept (a tie keeps the first).
// The result is judged on the whole scene: `clean`, `after`, `quality` and `displacement` against
// the input; `history` every repair's iterations in order (stage 5), of both orders when two
// ran. `record.orders` lists the orders tried, `record.layers` the kept one's layers innermost
// first, their meshes in canonical indices, each piece named by its ordinal among its mesh's
// pieces by lowest vertex in the input's numbering (`input_vertex`: per mesh, canonical vertex
// -> input vertex; a mesh without one is numbered as it is).
FixResult run_layering(std::vector<Mesh>& meshes, const FixOptions& options, const PinMask& pins,
                       const Rounding& round, const FixProgress& progress,
                       const std::vector<std::vector<std::uint32_t>>& input_vertex,
                       LayeringRecord& record);

}  // namespace untangle
