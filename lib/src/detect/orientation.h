// The one orientation predicate of detection: exact, with one consistent symbolic perturbation.
#pragma once

#include <cstdint>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

// Sign (+1 or -1, never 0) of the orientation of the points with global ids a, b, c, d, in the
// convention of CGAL::orientation: +1 when d lies on the positive side of the plane (a, b, c).
// Decided by CGAL's filtered exact predicate; an exact zero is resolved by Simulation of
// Simplicity (Edelsbrunner & Mücke 1990): coordinate j of the point with id i is perturbed by
// eps^(2^(3i - j)), so the result depends only on the coordinates and on the order of the ids.
// Every predicate made from it therefore describes one and the same perturbed, generic scene.
int orient_sos(const std::vector<Vec3>& points, std::uint32_t a, std::uint32_t b,
               std::uint32_t c, std::uint32_t d);

// The perturbed sign alone (exact arithmetic throughout): exposed for tests.
int orient_symbolic(const Vec3& pa, const Vec3& pb, const Vec3& pc, const Vec3& pd,
                    std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d);

}  // namespace untangle
