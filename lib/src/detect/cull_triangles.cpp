// cull_triangles: bounding boxes of the meshes, then an occupancy grid over where they overlap.
#include "detect/cull_triangles.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "detect/run_parallel.h"
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

// On which sides of the region a point lies: bit 2k below it on axis k, bit 2k + 1 above. A
// triangle's box misses the region iff all three corners lie beyond one same side.
std::uint8_t outside_bits(const Grid& grid, const Vec3& p) {
  unsigned bits = 0;
  for (int k = 0; k < 3; ++k)
    bits |= static_cast<unsigned>(p[k] < grid.region.lo[k]) << (2 * k) |
            static_cast<unsigned>(p[k] > grid.region.hi[k]) << (2 * k + 1);
  return static_cast<std::uint8_t>(bits);
}

// The cell of a point (clamped to the grid), packed in bytes 0 to 2.
std::uint32_t grid_cell(const Grid& grid, const Vec3& p) {
  std::uint32_t packed = 0;
  for (int k = 0; k < 3; ++k) packed |= static_cast<std::uint32_t>(grid.cell(p[k], k)) << (8 * k);
  return packed;
}

// Which cells a triangle's box covers, from its corners' packed cells.
struct TriangleCells {
  bool single = false;  // covers one cell, lo (most triangles are smaller than a cell)
  std::array<int, 3> lo{}, hi{};
};

TriangleCells triangle_cells(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  TriangleCells out;
  out.single = ((a ^ b) | (a ^ c)) == 0;
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
                                                       const std::vector<bool>& cull, int threads) {
  const std::size_t meshes = topo.mesh_tri_begin.size() - 1;
  std::vector<std::vector<std::uint32_t>> kept(meshes);
  auto mesh_triangles = [&](std::size_t m) -> std::size_t {
    return topo.mesh_tri_begin[m + 1] - topo.mesh_tri_begin[m];
  };
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
  // The per-mesh passes run on the meshes in parallel, each writing its own slots.
  std::vector<Box3> bounds(meshes);
  std::vector<std::uint8_t> has(meshes, 0), finite(meshes, 1);
  run_parallel(threads, meshes, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t m = begin; m < end; ++m) {
      const std::uint32_t first = topo.mesh_vertex_begin[m], last = topo.mesh_vertex_begin[m + 1];
      if (first == last || topo.mesh_tri_begin[m] == topo.mesh_tri_begin[m + 1]) continue;
      has[m] = 1;
      Box3& box = bounds[m];
      box.lo = box.hi = topo.points[first];
      bool all_finite = true;  // a comparison, not a sum: no chain of additions to wait for
      for (std::uint32_t v = first; v < last; ++v) {
        const Vec3& p = topo.points[v];
        for (int k = 0; k < 3; ++k) {
          all_finite &= std::abs(p[k]) <= std::numeric_limits<double>::max();  // false for inf, NaN
          box.lo[k] = std::min(box.lo[k], p[k]);
          box.hi[k] = std::max(box.hi[k], p[k]);
        }
      }
      finite[m] = all_finite;
    }
  });
  if (std::find(finite.begin(), finite.end(), 0) != finite.end()) {
    for (std::size_t c = 0; c < meshes; ++c) keep_all(c);
    return kept;
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
  // Which sides of the region every vertex of a mesh that reaches it lies beyond (six
  // comparisons); the region test of a triangle needs nothing more.
  std::vector<std::uint8_t> near(meshes, 0);
  std::vector<std::uint8_t> outside(topo.points.size());
  auto in_region = [&](std::uint32_t t) {
    const auto& tri = topo.tris[t];
    return (outside[tri[0]] & outside[tri[1]] & outside[tri[2]]) == 0;
  };
  // Those sides for the meshes that reach the region, and how many of their vertices lie inside.
  std::vector<std::size_t> inside(meshes, 0);
  run_parallel(threads, meshes, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t m = begin; m < end; ++m) {
      near[m] = has[m] && bounds[m].overlaps(grid.region);
      if (!near[m]) continue;
      std::size_t count = 0;
      for (std::uint32_t v = topo.mesh_vertex_begin[m]; v < topo.mesh_vertex_begin[m + 1]; ++v) {
        outside[v] = outside_bits(grid, topo.points[v]);
        count += outside[v] == 0;
      }
      inside[m] = count;
    }
  });
  // The grid serves the culled mesh with the most vertices in the region (`largest`): the cells
  // that the boxes of every other mesh's triangles in the region cover are marked, and it keeps
  // its triangles in the region that cover a marked cell. (Marking with the large mesh to cull the
  // small ones would cost more than it saves.) Its region test is made in the same pass as the
  // grid's; the other culled meshes keep the triangles whose box reaches the region.
  std::size_t largest = meshes;
  for (std::size_t m = 0; m < meshes; ++m) {
    if (!cull[m] || !near[m]) continue;
    if (largest == meshes || inside[m] > inside[largest]) largest = m;
  }
  if (largest == meshes) return kept;
  auto region_pass = [&](std::size_t m) {
    kept[m].reserve(mesh_triangles(m));
    for (std::uint32_t t = topo.mesh_tri_begin[m]; t < topo.mesh_tri_begin[m + 1]; ++t)
      if (in_region(t)) kept[m].push_back(t);
  };
  run_parallel(threads, meshes, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t m = begin; m < end; ++m)
      if (near[m] && cull[m] && m != largest) region_pass(m);
  });
  // Cells are computed per corner where a mesh has few triangles to visit, else once per vertex.
  std::vector<std::uint32_t> cell(topo.points.size());
  auto cells_of = [&](std::uint32_t t, bool stored) {
    const auto& tri = topo.tris[t];
    if (stored) return triangle_cells(cell[tri[0]], cell[tri[1]], cell[tri[2]]);
    return triangle_cells(grid_cell(grid, topo.points[tri[0]]), grid_cell(grid, topo.points[tri[1]]),
                          grid_cell(grid, topo.points[tri[2]]));
  };
  auto store_cells = [&](std::size_t m) {
    for (std::uint32_t v = topo.mesh_vertex_begin[m]; v < topo.mesh_vertex_begin[m + 1]; ++v)
      cell[v] = grid_cell(grid, topo.points[v]);
  };
  // `near_marked`: the marked cells grown by one cell on every side. A triangle whose box spans
  // at most two cells per axis can only meet a marked cell when each of its corners lies in a
  // cell near one, so a byte per corner rules out most triangles before their boxes are formed.
  const std::size_t cells = static_cast<std::size_t>(grid.dims[0]) * grid.dims[1] * grid.dims[2];
  std::vector<std::uint8_t> marked(cells, 0), near_marked(cells, 0);
  std::size_t budget = kCellsPerTriangle * topo.tris.size();
  auto fill = [&](std::vector<std::uint8_t>& grid_cells, const std::array<int, 3>& lo, const std::array<int, 3>& hi) {
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) grid_cells[grid.index(x, y, z)] = 1;
  };
  for (std::size_t m = 0; m < meshes; ++m) {
    if (m == largest || !near[m]) continue;
    const std::size_t vertices = topo.mesh_vertex_begin[m + 1] - topo.mesh_vertex_begin[m];
    const std::size_t visits = cull[m] ? kept[m].size() : topo.mesh_tri_begin[m + 1] - topo.mesh_tri_begin[m];
    const bool stored = 3 * visits > vertices;
    if (stored) store_cells(m);
    auto mark = [&](std::uint32_t t) {
      if (!in_region(t)) return true;
      const TriangleCells box = cells_of(t, stored);
      std::array<int, 3> lo, hi;
      std::size_t covered = 1;
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::max(box.lo[k] - 1, 0);
        hi[k] = std::min(box.hi[k] + 1, grid.dims[k] - 1);
        covered *= static_cast<std::size_t>(hi[k] - lo[k] + 1);
      }
      if (covered > budget) return false;
      budget -= covered;
      fill(marked, box.lo, box.hi);
      fill(near_marked, lo, hi);
      return true;
    };
    bool within = true;
    if (cull[m]) {
      for (std::uint32_t t : kept[m]) within = within && mark(t);
    } else {
      for (std::uint32_t t = topo.mesh_tri_begin[m]; t < topo.mesh_tri_begin[m + 1] && within; ++t)
        within = mark(t);
    }
    if (!within) {  // huge triangles: the region alone decides
      region_pass(largest);
      return kept;
    }
  }
  std::vector<std::uint8_t> corner_near(topo.points.size());
  for (std::uint32_t v = topo.mesh_vertex_begin[largest]; v < topo.mesh_vertex_begin[largest + 1]; ++v) {
    const std::uint32_t c = grid_cell(grid, topo.points[v]);
    cell[v] = c;
    corner_near[v] = near_marked[grid.index(c & 0xff, c >> 8 & 0xff, c >> 16 & 0xff)];
  }
  std::vector<std::uint32_t>& list = kept[largest];
  for (std::uint32_t t = topo.mesh_tri_begin[largest]; t < topo.mesh_tri_begin[largest + 1]; ++t) {
    const auto& tri = topo.tris[t];
    if (!in_region(t)) continue;
    const bool near_all = (corner_near[tri[0]] & corner_near[tri[1]] & corner_near[tri[2]]) != 0;
    const TriangleCells box = cells_of(t, true);
    bool meets = false;
    if (box.hi[0] - box.lo[0] <= 1 && box.hi[1] - box.lo[1] <= 1 && box.hi[2] - box.lo[2] <= 1) {
      if (!near_all) continue;
      // At most two cells per axis (most triangles): the box's cells are the combinations of lo
      // and hi, read without branches.
      for (int k = 0; k < 8; ++k)
        meets |= marked[grid.index(k & 1 ? box.hi[0] : box.lo[0], k & 2 ? box.hi[1] : box.lo[1],
                                   k & 4 ? box.hi[2] : box.lo[2])] != 0;
    } else {
      for (int z = box.lo[2]; z <= box.hi[2] && !meets; ++z)
        for (int y = box.lo[1]; y <= box.hi[1] && !meets; ++y)
          for (int x = box.lo[0]; x <= box.hi[0] && !meets; ++x) meets = marked[grid.index(x, y, z)] != 0;
    }
    if (meets) list.push_back(t);
  }
  return kept;
}

}  // namespace untangle
