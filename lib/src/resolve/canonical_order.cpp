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

#include "geometry/order_free_sum.h"

namespace untangle {

namespace {

// The mean of the vertices of `meshes`: the same whatever their order, and exactly turned with
// them by a half turn about an axis (which negates two coordinates) and scaled with them by a power
// of two (OrderFreeSum).
Vec3 order_free_mean(const std::vector<const std::vector<Vec3>*>& meshes) {
  Vec3 mean{0, 0, 0};
  std::size_t count = 0;
  for (const auto* positions : meshes) count += positions->size();
  if (count == 0) return mean;
  for (int axis = 0; axis < 3; ++axis) {
    OrderFreeSum sum;
    for (const auto* positions : meshes)
      for (const Vec3& p : *positions) sum.add(p[axis]);
    mean[axis] = sum.value() / static_cast<double>(count);
  }
  return mean;
}

// The squared distance of `p` from `centre`, its three terms added smallest first so that a
// permutation of the axes gives the same bits.
double squared_distance(const Vec3& p, const Vec3& centre) {
  std::array<double, 3> terms;
  for (int k = 0; k < 3; ++k) terms[k] = (p[k] - centre[k]) * (p[k] - centre[k]);
  std::sort(terms.begin(), terms.end());
  return (terms[0] + terms[1]) + terms[2];
}

}  // namespace

CanonicalMesh canonical(const Mesh& input) { return canonical(input, nullptr); }

CanonicalMesh canonical(const Mesh& input, const Vec3* scene_mean) {
  CanonicalMesh out;
  const std::size_t nv = input.positions.size();
  // Vertices by their distance from the mean of the mesh's vertices, then from the mean of the
  // scene's (order_free_mean); equal in both (a symmetric mesh, mirrored in the scene too) by
  // position, x, then y, then z; equal positions by index. Positions are compared on integer keys
  // that order as the doubles do (readers refuse NaN; -0.0 is keyed as 0.0, which it equals).
  struct VertexKey {
    double distance, scene_distance;
    std::array<std::uint64_t, 3> position;
    std::uint32_t index;
  };
  auto key_of = [](double x) {
    if (x == 0.0) x = 0.0;
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    return bits >> 63 ? ~bits : bits | (std::uint64_t(1) << 63);
  };
  const Vec3 centre = order_free_mean({&input.positions});
  std::vector<VertexKey> vertex_keys(nv);
  for (std::uint32_t i = 0; i < nv; ++i) {
    const Vec3& p = input.positions[i];
    const double distance = squared_distance(p, centre);
    vertex_keys[i] = {distance,
                      scene_mean != nullptr ? squared_distance(p, *scene_mean) : distance,
                      {key_of(p[0]), key_of(p[1]), key_of(p[2])},
                      i};
  }
  std::sort(vertex_keys.begin(), vertex_keys.end(), [](const VertexKey& a, const VertexKey& b) {
    if (a.distance != b.distance) return a.distance < b.distance;
    if (a.scene_distance != b.scene_distance) return a.scene_distance < b.scene_distance;
    if (a.position[0] != b.position[0]) return a.position[0] < b.position[0];
    if (a.position[1] != b.position[1]) return a.position[1] < b.position[1];
    if (a.position[2] != b.position[2]) return a.position[2] < b.position[2];
    return a.index < b.index;
  });
  out.vertex_order.resize(nv);
  for (std::uint32_t k = 0; k < nv; ++k) out.vertex_order[k] = vertex_keys[k].index;
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
  // Triangles by their rotated corners, equal ones by index: one 64-bit key of the first two
  // corners, then the third, then the index.
  struct TriangleKey {
    std::uint64_t first_two;
    std::uint32_t third, index;
  };
  auto less = [](const TriangleKey& a, const TriangleKey& b) {
    if (a.first_two != b.first_two) return a.first_two < b.first_two;
    if (a.third != b.third) return a.third < b.third;
    return a.index < b.index;
  };
  // The keys are distinct (the index breaks ties), so any sort gives this one order. Bucketed by
  // the first corner (a counting pass, indices ascending in each bucket), then each bucket of
  // about two triangles sorted alone: the comparison sort of the whole took 2.2% of `check` on
  // the shipped MakeHuman pair, the buckets' sorts take 0.3% (issue 24). A first corner out of
  // range sorts the whole at once.
  std::vector<TriangleKey> triangle_keys(nt);
  bool in_range = true;
  for (std::uint32_t t = 0; t < nt; ++t) in_range = in_range && rotated[t][0] < nv;
  if (in_range) {
    std::vector<std::uint32_t> bucket(nv + 1, 0);
    for (std::uint32_t t = 0; t < nt; ++t) ++bucket[rotated[t][0] + 1];
    for (std::size_t v = 0; v < nv; ++v) bucket[v + 1] += bucket[v];
    std::vector<std::uint32_t> fill(bucket.begin(), bucket.end() - 1);
    for (std::uint32_t t = 0; t < nt; ++t)
      triangle_keys[fill[rotated[t][0]]++] = {std::uint64_t(rotated[t][0]) << 32 | rotated[t][1],
                                              rotated[t][2], t};
    for (std::size_t v = 0; v < nv; ++v)
      if (bucket[v + 1] - bucket[v] > 1)
        std::sort(triangle_keys.begin() + bucket[v], triangle_keys.begin() + bucket[v + 1], less);
  } else {
    for (std::uint32_t t = 0; t < nt; ++t)
      triangle_keys[t] = {std::uint64_t(rotated[t][0]) << 32 | rotated[t][1], rotated[t][2], t};
    std::sort(triangle_keys.begin(), triangle_keys.end(), less);
  }
  std::vector<std::uint32_t>& tri_order = out.triangle_order;
  tri_order.resize(nt);
  for (std::uint32_t t = 0; t < nt; ++t) tri_order[t] = triangle_keys[t].index;

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

// Steps 1 to 3 of the canonical mesh order (canonical_order.h), computed once per mesh: what the
// repair leaves as it was (it moves positions only), so the written meshes take the same order.
struct MeshKey {
  int role = 0;
  std::size_t vertices = 0, triangles = 0;
  std::vector<std::size_t> valence_counts;  // [v] = how many vertices have v neighbours
  std::size_t pinned = 0;

  auto tied() const { return std::tie(role, vertices, triangles, valence_counts, pinned); }
};

MeshKey key_of(const Mesh& mesh, const std::vector<std::uint8_t>& pins) {
  MeshKey key;
  key.role = static_cast<int>(mesh.role);
  key.vertices = mesh.positions.size();
  key.triangles = mesh.triangles.size();
  // Each vertex's distinct neighbours: its neighbours through triangle edges listed per vertex
  // (CSR), repeats told apart by a stamp.
  const std::size_t nv = key.vertices;
  std::vector<std::uint32_t> begin(nv + 1, 0);
  auto valid = [nv](const Triangle& t) { return t[0] < nv && t[1] < nv && t[2] < nv; };
  for (const Triangle& t : mesh.triangles)
    if (valid(t))
      for (int k = 0; k < 3; ++k)
        if (t[k] != t[(k + 1) % 3]) {
          ++begin[t[k] + 1];
          ++begin[t[(k + 1) % 3] + 1];
        }
  for (std::size_t v = 0; v < nv; ++v) begin[v + 1] += begin[v];
  std::vector<std::uint32_t> neighbours(begin[nv]), fill(begin.begin(), begin.end() - 1);
  for (const Triangle& t : mesh.triangles)
    if (valid(t))
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = t[k], b = t[(k + 1) % 3];
        if (a == b) continue;
        neighbours[fill[a]++] = b;
        neighbours[fill[b]++] = a;
      }
  std::vector<std::size_t> valence(nv, 0);
  std::vector<std::uint32_t> stamp(nv, static_cast<std::uint32_t>(-1));
  for (std::uint32_t v = 0; v < nv; ++v)
    for (std::uint32_t i = begin[v]; i < begin[v + 1]; ++i)
      if (stamp[neighbours[i]] != v) {
        stamp[neighbours[i]] = v;
        ++valence[v];
      }
  for (std::size_t v : valence) {
    if (v >= key.valence_counts.size()) key.valence_counts.resize(v + 1, 0);
    ++key.valence_counts[v];
  }
  for (const std::uint8_t pin : pins) key.pinned += pin != 0 ? 1 : 0;
  return key;
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
  std::vector<const std::vector<Vec3>*> all;
  for (const Mesh& mesh : input) all.push_back(&mesh.positions);
  const Vec3 scene_mean = order_free_mean(all);
  for (std::size_t m = 0; m < n; ++m) {
    renumbered.push_back(canonical(input[m], &scene_mean));
    if (m < pins.size() && !pins[m].empty()) {
      const auto& order = renumbered[m].vertex_order;
      canonical_pins[m].assign(order.size(), 0);
      for (std::size_t k = 0; k < order.size(); ++k)
        if (order[k] < pins[m].size()) canonical_pins[m][k] = pins[m][order[k]];
    }
    keys.push_back(key_of(renumbered[m].mesh, canonical_pins[m]));
  }
  CanonicalScene scene;
  scene.mesh_order.resize(n);
  std::iota(scene.mesh_order.begin(), scene.mesh_order.end(), 0u);
  std::sort(scene.mesh_order.begin(), scene.mesh_order.end(), [&](std::uint32_t a, std::uint32_t b) {
    if (keys[a].tied() != keys[b].tied()) return keys[a].tied() < keys[b].tied();
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
