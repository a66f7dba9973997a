// cull_triangles: bounding boxes of the meshes, then an occupancy grid over where they overlap.
#include "detect/cull_triangles.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "detect/triangle_bvh.h"

namespace untangle {
namespace {

// Cells along the longest axis of the grid (the other axes in proportion, at least one).
constexpr int kCells = 64;  // < 256: cells are bytes
// Marking is abandoned (nothing culled) when the triangles' boxes cover more cells than this many
// per triangle on average: huge overlapping triangles would make the grid cost more than it saves.
constexpr std::size_t kCellsPerTriangle = 64;

// Maps coordinates to cells by one monotone function per axis: x <= y gives cell(x) <= cell(y),
// as the rounding of a subtraction and of a product by a positive number are monotone. So the
// cells of a triangle's box are those between the cells of its corners (no box is built), and two
// closed boxes that share a point p both cover the cell of p.
struct Grid {
  Box3 region;
  std::array<int, 3> dims{1, 1, 1};
  std::array<double, 3> scale{0.0, 0.0, 0.0};
  // Clamped to the grid; branch-free (min and max of doubles), as vertices come in no spatial
  // order. Coordinates are finite.
  int cell(double x, int k) const {
    const double v = (x - region.lo[k]) * scale[k];
    return static_cast<int>(std::min(std::max(v, 0.0), static_cast<double>(dims[k] - 1)));
  }
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * dims[1] + y) * dims[0] + x;
  }
};

// A vertex seen from the grid, packed in 32 bits: its cell (clamped to the grid) in bytes 0 to 2,
// and in byte 3 on which sides of the region it lies (bit 2k: below on axis k, bit 2k + 1: above).
// A triangle's box misses the region iff all three corners lie beyond one same side.
std::uint32_t vertex_cell(const Grid& grid, const Vec3& p) {
  std::uint32_t packed = 0;
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t outside = static_cast<std::uint32_t>(p[k] < grid.region.lo[k]) |
                                  static_cast<std::uint32_t>(p[k] > grid.region.hi[k]) << 1;
    packed |= static_cast<std::uint32_t>(grid.cell(p[k], k)) << (8 * k) | outside << (24 + 2 * k);
  }
  return packed;
}

// Where a triangle's box lies, from its corners' packed cells.
struct TriangleCells {
  bool outside = false;  // misses the region
  bool single = false;   // covers one cell, lo (most triangles are smaller than a cell)
  std::array<int, 3> lo{}, hi{};
};

TriangleCells triangle_cells(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  TriangleCells out;
  if ((a & b & c) >> 24) {
    out.outside = true;
    return out;
  }
  out.single = (((a ^ b) | (a ^ c)) & 0xffffffu) == 0;
  for (int k = 0; k < 3; ++k) {
    const int x = static_cast<int>(a >> (8 * k) & 0xffu), y = static_cast<int>(b >> (8 * k) & 0xffu),
              z = static_cast<int>(c >> (8 * k) & 0xffu);
    out.lo[k] = std::min(x, std::min(y, z));
    out.hi[k] = std::max(x, std::max(y, z));
  }
  return out;
}

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
    Box3& box = bounds[m];
    box.lo = box.hi = topo.points[first];
    double zero = 0.0;  // stays 0 iff every coordinate is finite (inf * 0 and NaN give NaN)
    for (std::uint32_t v = first; v < last; ++v) {
      const Vec3& p = topo.points[v];
      for (int k = 0; k < 3; ++k) {
        zero += p[k] * 0.0;
        box.lo[k] = std::min(box.lo[k], p[k]);
        box.hi[k] = std::max(box.hi[k], p[k]);
      }
    }
    if (zero != 0.0) {
      for (std::size_t c = 0; c < meshes; ++c) keep_all(c);
      return kept;
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
  std::vector<std::uint32_t> vertex(topo.points.size());
  for (std::size_t m = 0; m < meshes; ++m) {
    near[m] = has[m] && bounds[m].overlaps(grid.region);
    if (!near[m]) continue;
    for (std::uint32_t v = topo.mesh_vertex_begin[m]; v < topo.mesh_vertex_begin[m + 1]; ++v)
      vertex[v] = vertex_cell(grid, topo.points[v]);
  }
  auto cells_of = [&](std::uint32_t t) {
    const auto& tri = topo.tris[t];
    return triangle_cells(vertex[tri[0]], vertex[tri[1]], vertex[tri[2]]);
  };
  // First the region alone: culled meshes keep the triangles whose box reaches it.
  std::size_t largest = meshes;  // the culled mesh with the most triangles left
  for (std::size_t m = 0; m < meshes; ++m) {
    if (!cull[m] || !near[m]) continue;
    for (std::uint32_t t = topo.mesh_tri_begin[m]; t < topo.mesh_tri_begin[m + 1]; ++t)
      if (!cells_of(t).outside) kept[m].push_back(t);
    if (largest == meshes || kept[m].size() > kept[largest].size()) largest = m;
  }
  if (largest == meshes || kept[largest].empty()) return kept;
  // Then the grid, for the culled mesh with the most triangles left: mark the cells that the
  // boxes of every other mesh's triangles in the region cover; keep its triangles that cover a
  // marked cell. (Marking with the large mesh to cull the small ones would cost more than it
  // saves: they keep their triangles in the region.)
  std::vector<std::uint8_t> marked(static_cast<std::size_t>(grid.dims[0]) * grid.dims[1] * grid.dims[2], 0);
  std::size_t budget = kCellsPerTriangle * topo.tris.size();
  for (std::size_t m = 0; m < meshes; ++m) {
    if (m == largest || !near[m]) continue;
    auto mark = [&](std::uint32_t t) {
      const TriangleCells box = cells_of(t);
      if (box.outside) return true;
      if (box.single) {
        marked[grid.index(box.lo[0], box.lo[1], box.lo[2])] = 1;
        return true;
      }
      const std::size_t covered = static_cast<std::size_t>(box.hi[0] - box.lo[0] + 1) *
                                  (box.hi[1] - box.lo[1] + 1) * (box.hi[2] - box.lo[2] + 1);
      if (covered > budget) return false;
      budget -= covered;
      for (int z = box.lo[2]; z <= box.hi[2]; ++z)
        for (int y = box.lo[1]; y <= box.hi[1]; ++y)
          for (int x = box.lo[0]; x <= box.hi[0]; ++x) marked[grid.index(x, y, z)] = 1;
      return true;
    };
    bool within = true;
    if (cull[m]) {
      for (std::uint32_t t : kept[m]) within = within && mark(t);
    } else {
      for (std::uint32_t t = topo.mesh_tri_begin[m]; t < topo.mesh_tri_begin[m + 1] && within; ++t)
        within = mark(t);
    }
    if (!within) return kept;  // huge triangles: the region alone decides
  }
  std::vector<std::uint32_t>& list = kept[largest];
  std::size_t out = 0;
  for (std::uint32_t t : list) {
    const TriangleCells box = cells_of(t);
    bool meets = marked[grid.index(box.lo[0], box.lo[1], box.lo[2])] != 0;
    if (!box.single) {
      for (int z = box.lo[2]; z <= box.hi[2] && !meets; ++z)
        for (int y = box.lo[1]; y <= box.hi[1] && !meets; ++y)
          for (int x = box.lo[0]; x <= box.hi[0] && !meets; ++x) meets = marked[grid.index(x, y, z)] != 0;
    }
    if (meets) list[out++] = t;
  }
  list.resize(out);
  return kept;
}

}  // namespace untangle
