// cull_triangles: bounding boxes of the meshes, then an occupancy grid over where they overlap.
#include "detect/cull_triangles.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "detect/triangle_bvh.h"

namespace untangle {
namespace {

// Cells along the longest axis of the grid (the other axes in proportion, at least one).
constexpr int kCells = 32;  // < 256: cells are bytes
// Marking is abandoned (nothing culled) when the triangles' boxes cover more cells than this many
// per triangle on average: huge overlapping triangles would make the grid cost more than it saves.
constexpr std::size_t kCellsPerTriangle = 64;

constexpr std::uint32_t kEmpty = 0xffffffffu;
constexpr std::uint32_t kShared = 0xfffffffeu;  // marked by two or more meshes

// Maps coordinates to cells by one monotone function per axis: x <= y gives cell(x) <= cell(y),
// as the rounding of a subtraction and of a product by a positive number are monotone. So the
// cells of a triangle's box are those between the cells of its corners (no box is built), and two
// closed boxes that share a point p both cover the cell of p.
struct Grid {
  Box3 region;
  std::array<int, 3> dims{1, 1, 1};
  std::array<double, 3> scale{0.0, 0.0, 0.0};
  int cell(double x, int k) const {
    const double v = (x - region.lo[k]) * scale[k];
    if (!(v > 0.0)) return 0;
    if (v >= dims[k]) return dims[k] - 1;
    return static_cast<int>(v);
  }
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * dims[1] + y) * dims[0] + x;
  }
};

// A vertex seen from the grid: its cell (clamped to the grid) and on which sides of the region it
// lies (bit 2k: below on axis k, bit 2k + 1: above). A triangle's box misses the region iff all
// three corners lie beyond one same side.
struct VertexCell {
  std::uint8_t outside = 0;
  std::array<std::uint8_t, 3> cell{};
};

// A triangle of a culled mesh whose box reaches the region, with its cell range.
struct Pending {
  std::uint32_t triangle = 0;
  std::array<std::uint8_t, 3> lo{}, hi{};
};

}  // namespace

std::vector<std::vector<std::uint32_t>> cull_triangles(const SceneTopology& topo,
                                                       const std::vector<bool>& cull) {
  const std::size_t meshes = topo.mesh_tri_begin.size() - 1;
  std::vector<std::vector<std::uint32_t>> kept(meshes);
  auto keep_all = [&](std::size_t m) {
    kept[m].resize(topo.mesh_tri_begin[m + 1] - topo.mesh_tri_begin[m]);
    for (std::size_t i = 0; i < kept[m].size(); ++i) kept[m][i] = topo.mesh_tri_begin[m] + static_cast<std::uint32_t>(i);
  };
  if (std::find(cull.begin(), cull.end(), true) == cull.end()) {
    for (std::size_t m = 0; m < meshes; ++m) keep_all(m);
    return kept;
  }
  // Each mesh's box, from its vertices (a superset of its triangles' corners). Non-finite
  // coordinates defeat the grid's rounding: then nothing is culled.
  std::vector<Box3> bounds(meshes);
  std::vector<bool> has(meshes, false);
  for (std::size_t m = 0; m < meshes; ++m) {
    const std::uint32_t first = topo.mesh_vertex_begin[m], last = topo.mesh_vertex_begin[m + 1];
    if (first == last || topo.mesh_tri_begin[m] == topo.mesh_tri_begin[m + 1]) continue;
    has[m] = true;
    bounds[m].lo = bounds[m].hi = topo.points[first];
    for (std::uint32_t v = first; v < last; ++v) {
      const Vec3& p = topo.points[v];
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(p[k])) {
          for (std::size_t c = 0; c < meshes; ++c) keep_all(c);
          return kept;
        }
        bounds[m].lo[k] = std::min(bounds[m].lo[k], p[k]);
        bounds[m].hi[k] = std::max(bounds[m].hi[k], p[k]);
      }
    }
  }
  for (std::size_t m = 0; m < meshes; ++m)
    if (!cull[m]) keep_all(m);
  // The region: the box around every overlap of a culled mesh's box with another mesh's box. Two
  // triangle boxes of different meshes, one of them culled, can only meet inside it.
  Grid grid;
  bool any = false;
  for (std::size_t a = 0; a < meshes; ++a) {
    for (std::size_t b = a + 1; b < meshes; ++b) {
      if (!has[a] || !has[b] || !(cull[a] || cull[b]) || !bounds[a].overlaps(bounds[b])) continue;
      Box3 overlap;
      for (int k = 0; k < 3; ++k) {
        overlap.lo[k] = std::max(bounds[a].lo[k], bounds[b].lo[k]);
        overlap.hi[k] = std::min(bounds[a].hi[k], bounds[b].hi[k]);
      }
      grid.region = any ? merged(grid.region, overlap) : overlap;
      any = true;
    }
  }
  if (!any) return kept;  // culled meshes meet no other mesh's box: nothing of them is kept
  double longest = 0.0;
  for (int k = 0; k < 3; ++k) longest = std::max(longest, grid.region.hi[k] - grid.region.lo[k]);
  for (int k = 0; k < 3; ++k) {
    const double extent = grid.region.hi[k] - grid.region.lo[k];
    if (longest > 0.0 && extent > 0.0) {
      grid.dims[k] = std::clamp(static_cast<int>(kCells * (extent / longest)) + 1, 1, kCells);
      grid.scale[k] = grid.dims[k] / extent;
    }
  }
  // The cell of every vertex of a mesh that reaches the region.
  std::vector<bool> near(meshes, false);
  std::vector<VertexCell> vertex(topo.points.size());
  for (std::size_t m = 0; m < meshes; ++m) {
    near[m] = has[m] && bounds[m].overlaps(grid.region);
    if (!near[m]) continue;
    for (std::uint32_t v = topo.mesh_vertex_begin[m]; v < topo.mesh_vertex_begin[m + 1]; ++v) {
      const Vec3& p = topo.points[v];
      VertexCell& out = vertex[v];
      for (int k = 0; k < 3; ++k) {
        out.outside |= static_cast<std::uint8_t>((p[k] < grid.region.lo[k]) << (2 * k) |
                                                 (p[k] > grid.region.hi[k]) << (2 * k + 1));
        out.cell[k] = static_cast<std::uint8_t>(grid.cell(p[k], k));
      }
    }
  }
  // Mark every cell a triangle's box covers with its mesh (kShared once two meshes meet there).
  std::vector<std::uint32_t> owner(static_cast<std::size_t>(grid.dims[0]) * grid.dims[1] * grid.dims[2],
                                   kEmpty);
  std::vector<Pending> pending;
  std::size_t budget = kCellsPerTriangle * topo.tris.size();
  for (std::size_t m = 0; m < meshes; ++m) {
    if (!near[m]) continue;
    const auto mesh = static_cast<std::uint32_t>(m);
    for (std::uint32_t t = topo.mesh_tri_begin[m]; t < topo.mesh_tri_begin[m + 1]; ++t) {
      const VertexCell& a = vertex[topo.tris[t][0]];
      const VertexCell& b = vertex[topo.tris[t][1]];
      const VertexCell& c = vertex[topo.tris[t][2]];
      if (a.outside & b.outside & c.outside) continue;
      Pending range;
      range.triangle = t;
      for (int k = 0; k < 3; ++k) {
        range.lo[k] = std::min({a.cell[k], b.cell[k], c.cell[k]});
        range.hi[k] = std::max({a.cell[k], b.cell[k], c.cell[k]});
      }
      const std::size_t covered = static_cast<std::size_t>(range.hi[0] - range.lo[0] + 1) *
                                  (range.hi[1] - range.lo[1] + 1) * (range.hi[2] - range.lo[2] + 1);
      if (covered > budget) {
        for (std::size_t c = 0; c < meshes; ++c)
          if (cull[c]) keep_all(c);
        return kept;
      }
      budget -= covered;
      for (int z = range.lo[2]; z <= range.hi[2]; ++z)
        for (int y = range.lo[1]; y <= range.hi[1]; ++y)
          for (int x = range.lo[0]; x <= range.hi[0]; ++x) {
            std::uint32_t& o = owner[grid.index(x, y, z)];
            if (o == kEmpty) o = mesh;
            else if (o != mesh) o = kShared;
          }
      if (cull[m]) pending.push_back(range);
    }
  }
  // Keep the triangles of culled meshes that cover a cell some other mesh covers too.
  for (const Pending& range : pending) {
    const std::uint32_t t = range.triangle;
    const std::uint32_t mesh = topo.tri_mesh[t];
    bool meets = false;
    for (int z = range.lo[2]; z <= range.hi[2] && !meets; ++z)
      for (int y = range.lo[1]; y <= range.hi[1] && !meets; ++y)
        for (int x = range.lo[0]; x <= range.hi[0] && !meets; ++x) {
          const std::uint32_t o = owner[grid.index(x, y, z)];
          meets = o != kEmpty && o != mesh;
        }
    if (meets) kept[mesh].push_back(t);
  }
  return kept;
}

}  // namespace untangle
