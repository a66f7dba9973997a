// Canonical renumbering of a mesh, so that the repair's result does not depend on the order of
// vertices and faces in the file.
#include "resolve/canonical_order.h"

#include <algorithm>

namespace untangle {

CanonicalMesh canonical(const Mesh& input) {
  CanonicalMesh out;
  const std::size_t nv = input.positions.size();
  out.vertex_order.resize(nv);
  for (std::uint32_t i = 0; i < nv; ++i) out.vertex_order[i] = i;
  std::sort(out.vertex_order.begin(), out.vertex_order.end(),
            [&](std::uint32_t a, std::uint32_t b) {
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
