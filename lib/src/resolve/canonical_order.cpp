// Canonical renumbering of a mesh, and canonical order of a scene's meshes, so that the repair's
// result depends neither on the order of vertices and faces in the file nor on the order in which
// the meshes are listed.
#include "resolve/canonical_order.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <tuple>
#include <utility>

#include "geometry/vec3.h"

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

namespace {

// Steps 2 to 4 of the canonical mesh order (canonical_order.h), computed once per mesh.
struct MeshKey {
  int role = 0;
  std::size_t vertices = 0, triangles = 0;
  std::vector<std::size_t> valence_counts;  // [v] = how many vertices have v neighbours
  float area = 0.0f;

  auto tied() const { return std::tie(role, vertices, triangles, valence_counts, area); }
};

MeshKey key_of(const Mesh& mesh) {
  MeshKey key;
  key.role = static_cast<int>(mesh.role);
  key.vertices = mesh.positions.size();
  key.triangles = mesh.triangles.size();
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(3 * mesh.triangles.size());
  std::vector<double> areas;
  areas.reserve(mesh.triangles.size());
  for (const Triangle& t : mesh.triangles) {
    if (t[0] >= key.vertices || t[1] >= key.vertices || t[2] >= key.vertices) continue;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      if (a != b) edges.emplace_back(std::min(a, b), std::max(a, b));
    }
    areas.push_back(triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<std::size_t> valence(key.vertices, 0);
  for (const auto& [a, b] : edges) {
    ++valence[a];
    ++valence[b];
  }
  for (std::size_t v : valence) {
    if (v >= key.valence_counts.size()) key.valence_counts.resize(v + 1, 0);
    ++key.valence_counts[v];
  }
  std::sort(areas.begin(), areas.end());
  key.area = static_cast<float>(std::accumulate(areas.begin(), areas.end(), 0.0));
  if (std::isnan(key.area)) key.area = INFINITY;  // keeps the order strict (readers refuse NaN)
  return key;
}

// Step 5: positions bit for bit (a strict order even for -0.0 and NaN), then triangles.
int compare_geometry(const Mesh& a, const Mesh& b) {
  for (std::size_t i = 0; i < a.positions.size() && i < b.positions.size(); ++i) {
    const int c = std::memcmp(a.positions[i].data(), b.positions[i].data(), sizeof(Vec3));
    if (c != 0) return c;
  }
  if (a.triangles != b.triangles) return a.triangles < b.triangles ? -1 : 1;
  return 0;
}

}  // namespace

CanonicalScene canonical_scene(const std::vector<Mesh>& input,
                               const std::vector<std::vector<std::uint8_t>>& pins) {
  const std::size_t n = input.size();
  std::vector<CanonicalMesh> renumbered;
  std::vector<MeshKey> keys;
  std::vector<std::vector<std::uint8_t>> canonical_pins(n);
  renumbered.reserve(n);
  keys.reserve(n);
  for (std::size_t m = 0; m < n; ++m) {
    renumbered.push_back(canonical(input[m]));
    keys.push_back(key_of(renumbered[m].mesh));
    if (m < pins.size() && !pins[m].empty()) {
      const auto& order = renumbered[m].vertex_order;
      canonical_pins[m].assign(order.size(), 0);
      for (std::size_t k = 0; k < order.size(); ++k)
        if (order[k] < pins[m].size()) canonical_pins[m][k] = pins[m][order[k]];
    }
  }
  CanonicalScene scene;
  scene.mesh_order.resize(n);
  std::iota(scene.mesh_order.begin(), scene.mesh_order.end(), 0u);
  std::sort(scene.mesh_order.begin(), scene.mesh_order.end(), [&](std::uint32_t a, std::uint32_t b) {
    if (keys[a].tied() != keys[b].tied()) return keys[a].tied() < keys[b].tied();
    const int geometry = compare_geometry(renumbered[a].mesh, renumbered[b].mesh);
    if (geometry != 0) return geometry < 0;
    if (canonical_pins[a] != canonical_pins[b]) return canonical_pins[a] < canonical_pins[b];
    return a < b;
  });
  scene.mesh_rank.resize(n);
  for (std::uint32_t c = 0; c < n; ++c) scene.mesh_rank[scene.mesh_order[c]] = c;
  for (std::uint32_t m : scene.mesh_order) {
    scene.meshes.push_back(std::move(renumbered[m].mesh));
    renumbered[m].mesh = Mesh{};
    scene.renumbering.push_back(std::move(renumbered[m]));
    scene.pins.push_back(std::move(canonical_pins[m]));
  }
  return scene;
}

void counts_in_input_order(const CanonicalScene& scene, IntersectionCounts& counts) {
  counts.inside_by_mesh = in_input_order(scene, counts.inside_by_mesh);
  for (MeshContact& c : counts.contacts) {
    const std::uint32_t a = scene.mesh_order[c.mesh_a], b = scene.mesh_order[c.mesh_b];
    c.mesh_a = std::min(a, b);
    c.mesh_b = std::max(a, b);
  }
  std::sort(counts.contacts.begin(), counts.contacts.end(),
            [](const MeshContact& x, const MeshContact& y) {
              return std::tie(x.mesh_a, x.mesh_b) < std::tie(y.mesh_a, y.mesh_b);
            });
}

}  // namespace untangle
