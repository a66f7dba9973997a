// The repair loop: detect -> contours -> regions -> moves -> apply, until clean, capped or stalled.
#pragma once

#include <vector>

#include "resolve/moves.h"
#include "untangle/fix.h"
#include "untangle/mesh.h"

namespace untangle {

// fix_meshes on meshes already in canonical order (canonical_order.h): moves the movable
// meshes' positions in place and returns what the loop computed (`after` counts the state left in
// `meshes`, as the loop detected it; nothing is detected again).
FixResult run_repair(std::vector<Mesh>& meshes, const FixOptions& options, const PinMask& pins,
                     const Rounding& round, const FixProgress& progress);

}  // namespace untangle
