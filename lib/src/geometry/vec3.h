// Small vector helpers on Vec3 (double[3]) shared by every stage: plain arithmetic in a fixed
// order, no fused multiply-add (the build sets -ffp-contract=off), so results are bit-stable.
#pragma once

#include <cmath>

#include "untangle/mesh.h"

namespace untangle {

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
// a / |a|, or the zero vector for a zero vector.
inline Vec3 unit(const Vec3& a) {
  const double n = norm(a);
  return n > 0.0 ? scale(a, 1.0 / n) : Vec3{0.0, 0.0, 0.0};
}
// Area of triangle (a, b, c): half the length of (b - a) x (c - a).
inline double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * norm(cross(sub(b, a), sub(c, a)));
}
// Six times the signed volume of the tetrahedron (r, a, b, c). Summed over the triangles of a
// closed surface it is six times the volume the surface encloses, for any r; take r on the
// surface, not the origin: far from the origin (a scene moved by 1e5) the terms about it are
// some |p|^3 and their sum is rounding noise, of either sign.
inline double volume6(const Vec3& r, const Vec3& a, const Vec3& b, const Vec3& c) {
  return dot(sub(a, r), cross(sub(b, r), sub(c, r)));
}

}  // namespace untangle
