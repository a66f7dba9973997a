// Canonical renumbering of a mesh, so that the repair's result does not depend on the order of
// vertices and faces in the file.
#include "resolve/canonical_order.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace untangle {
namespace {

// The mean of the positions, to within 2^-60 of the largest coordinate: each coordinate cut
// toward zero to a multiple of 2^(e - 60), where 2^e bounds every coordinate's magnitude, and
// summed exactly as an integer. The sum is then the same in any order, and so is the mean of the
// scene scaled by a power of two (scaled), or turned a quarter about an axis or mirrored (its
// coordinates permuted and negated).
Vec3 exact_mean(const std::vector<Vec3>& positions) {
  Vec3 mean{0.0, 0.0, 0.0};
  double largest = 0.0;
  for (const Vec3& p : positions)
    for (double c : p)
      if (std::isfinite(c)) largest = std::max(largest, std::abs(c));
  if (positions.empty() || largest == 0.0) return mean;
  const int e = std::ilogb(largest) + 1;  // |c| < 2^e
  for (int k = 0; k < 3; ++k) {
    __int128 sum = 0;  // |each term| < 2^60: exact for up to 2^67 positions
    for (const Vec3& p : positions)
      if (std::isfinite(p[k])) sum += static_cast<__int128>(std::ldexp(p[k], 60 - e));
    mean[k] = std::ldexp(static_cast<double>(sum), e - 60) / static_cast<double>(positions.size());
  }
  return mean;
}

// The squared distance of p from `centre`, its three squares added smallest first: the same for
// the scene turned a quarter about an axis or mirrored.
double squared_distance(const Vec3& p, const Vec3& centre) {
  std::array<double, 3> s{};
  for (int k = 0; k < 3; ++k) {
    const double d = p[k] - centre[k];
    s[k] = d * d;
  }
  std::sort(s.begin(), s.end());
  return s[0] + s[1] + s[2];
}

}  // namespace

CanonicalMesh canonical(const Mesh& input) {
  CanonicalMesh out;
  const std::size_t nv = input.positions.size();
  // Vertices by their distance from the mesh's mean position, which turns and scales with the
  // scene (ordering by the coordinates would renumber a turned scene, and the repair's sums and
  // ties would follow); equal distances (a mirror-symmetric mesh) by position, then input index.
  const Vec3 centre = exact_mean(input.positions);
  std::vector<double> key(nv);
  for (std::uint32_t i = 0; i < nv; ++i) {
    key[i] = squared_distance(input.positions[i], centre);
    if (std::isnan(key[i])) key[i] = INFINITY;  // keeps the order strict (readers refuse NaN)
  }
  out.vertex_order.resize(nv);
  for (std::uint32_t i = 0; i < nv; ++i) out.vertex_order[i] = i;
  std::sort(out.vertex_order.begin(), out.vertex_order.end(),
            [&](std::uint32_t a, std::uint32_t b) {
              if (key[a] != key[b]) return key[a] < key[b];
              const Vec3& pa = input.positions[a];
              const Vec3& pb = input.positions[b];
              return pa != pb ? pa < pb : a < b;
            });
  std::vector<std::uint32_t> rank(nv);
  for (std::uint32_t k = 0; k < nv; ++k) rank[out.vertex_order[k]] = k;

  const std::size_t nt = input.triangles.size();
  std::vector<Triangle> rotated(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    Triangle tri{};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = input.triangles[t][k];
      tri[k] = v < nv ? rank[v] : v;  // out-of-range indices are the reader's to refuse
    }
    const int first = static_cast<int>(std::min_element(tri.begin(), tri.end()) - tri.begin());
    std::rotate(tri.begin(), tri.begin() + first, tri.end());
    rotated[t] = tri;
  }
  std::vector<std::uint32_t>& tri_order = out.triangle_order;
  tri_order.resize(nt);
  for (std::uint32_t t = 0; t < nt; ++t) tri_order[t] = t;
  std::sort(tri_order.begin(), tri_order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return rotated[a] != rotated[b] ? rotated[a] < rotated[b] : a < b;
  });

  out.mesh.path = input.path;
  out.mesh.name = input.name;
  out.mesh.role = input.role;
  out.mesh.source_faces = input.source_faces;
  out.mesh.group_names = input.group_names;
  out.mesh.positions.reserve(nv);
  for (std::uint32_t i : out.vertex_order) out.mesh.positions.push_back(input.positions[i]);
  out.mesh.triangles.reserve(nt);
  for (std::uint32_t t : tri_order) {
    out.mesh.triangles.push_back(rotated[t]);
    if (t < input.polygon.size()) out.mesh.polygon.push_back(input.polygon[t]);
    if (t < input.triangle_group.size()) out.mesh.triangle_group.push_back(input.triangle_group[t]);
  }
  return out;
}

}  // namespace untangle
