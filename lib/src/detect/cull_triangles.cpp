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

// Consecutive ids [begin, end) of one mesh: the passes below run on such parts in parallel (each
// mesh cut into parts of at most kPart ids), each part writing its own slots or its own list,
// joined in part order, so the result is the same for every thread count.
struct Part {
  std::uint32_t mesh, begin, end;
};
constexpr std::uint32_t kPart = 4096;

// Parts covering the ids [first[m], first[m + 1]) of every mesh m with wanted(m), in mesh order.
template <class Wanted>
std::vector<Part> parts_of(const std::vector<std::uint32_t>& first, const Wanted& wanted) {
  std::vector<Part> parts;
  for (std::uint32_t m = 0; m + 1 < first.size(); ++m) {
    if (!wanted(m)) continue;
    for (std::uint32_t b = first[m]; b < first[m + 1]; b += std::min(kPart, first[m + 1] - b))
      parts.push_back({m, b, b + std::min(kPart, first[m + 1] - b)});
  }
  return parts;
}

}  // namespace

std::vector<std::vector<std::uint32_t>> cull_triangles(const SceneTopology& topo,
                                                       const std::vector<bool>& cull, int threads) {
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
  // coordinates defeat the grid's rounding: then nothing is culled. The parts' boxes are merged in
  // order with the same min and max as one pass, so the box is that pass's bit for bit (of equal
  // values, a signed zero included, the first is kept).
  std::vector<Box3> bounds(meshes);
  std::vector<std::uint8_t> has(meshes, 0), finite(meshes, 1);
  for (std::size_t m = 0; m < meshes; ++m)
    has[m] = topo.mesh_vertex_begin[m] < topo.mesh_vertex_begin[m + 1] &&
             topo.mesh_tri_begin[m] < topo.mesh_tri_begin[m + 1];
  const std::vector<Part> vertex_parts =
      parts_of(topo.mesh_vertex_begin, [&](std::uint32_t m) { return has[m] != 0; });
  std::vector<Box3> part_box(vertex_parts.size());
  std::vector<std::uint8_t> part_finite(vertex_parts.size());
  run_parallel(threads, vertex_parts.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Part& part = vertex_parts[i];
      Box3& box = part_box[i];
      box.lo = box.hi = topo.points[part.begin];
      bool all_finite = true;  // a comparison, not a sum: no chain of additions to wait for
      for (std::uint32_t v = part.begin; v < part.end; ++v) {
        const Vec3& p = topo.points[v];
        for (int k = 0; k < 3; ++k) {
          all_finite &= std::abs(p[k]) <= std::numeric_limits<double>::max();  // false for inf, NaN
          box.lo[k] = std::min(box.lo[k], p[k]);
          box.hi[k] = std::max(box.hi[k], p[k]);
        }
      }
      part_finite[i] = all_finite;
    }
  });
  for (std::size_t i = 0; i < vertex_parts.size(); ++i) {
    const std::uint32_t m = vertex_parts[i].mesh;
    finite[m] &= part_finite[i];
    Box3& box = bounds[m];
    if (vertex_parts[i].begin == topo.mesh_vertex_begin[m]) {
      box = part_box[i];
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      box.lo[k] = std::min(box.lo[k], part_box[i].lo[k]);
      box.hi[k] = std::max(box.hi[k], part_box[i].hi[k]);
    }
  }
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
  for (std::size_t m = 0; m < meshes; ++m) near[m] = has[m] && bounds[m].overlaps(grid.region);
  const std::vector<Part> near_parts =
      parts_of(topo.mesh_vertex_begin, [&](std::uint32_t m) { return near[m] != 0; });
  std::vector<std::size_t> part_inside(near_parts.size());
  run_parallel(threads, near_parts.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      std::size_t count = 0;
      for (std::uint32_t v = near_parts[i].begin; v < near_parts[i].end; ++v) {
        outside[v] = outside_bits(grid, topo.points[v]);
        count += outside[v] == 0;
      }
      part_inside[i] = count;
    }
  });
  std::vector<std::size_t> inside(meshes, 0);
  for (std::size_t i = 0; i < near_parts.size(); ++i) inside[near_parts[i].mesh] += part_inside[i];
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
  // Appends to kept[m], for every mesh m with wanted(m), its triangles t with keep(t), ascending.
  auto keep_where = [&](const auto& wanted, const auto& keep) {
    const std::vector<Part> parts = parts_of(topo.mesh_tri_begin, wanted);
    std::vector<std::vector<std::uint32_t>> lists(parts.size());
    run_parallel(threads, parts.size(), 1, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        lists[i].reserve(parts[i].end - parts[i].begin);
        for (std::uint32_t t = parts[i].begin; t < parts[i].end; ++t)
          if (keep(t)) lists[i].push_back(t);
      }
    });
    for (std::size_t i = 0; i < parts.size(); ++i)
      kept[parts[i].mesh].insert(kept[parts[i].mesh].end(), lists[i].begin(), lists[i].end());
  };
  keep_where([&](std::uint32_t m) { return near[m] && cull[m] && m != largest; }, in_region);
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
      keep_where([&](std::uint32_t k) { return k == largest; }, in_region);
      return kept;
    }
  }
  std::vector<std::uint8_t> corner_near(topo.points.size());
  const std::vector<Part> largest_parts =
      parts_of(topo.mesh_vertex_begin, [&](std::uint32_t m) { return m == largest; });
  run_parallel(threads, largest_parts.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      for (std::uint32_t v = largest_parts[i].begin; v < largest_parts[i].end; ++v) {
        const std::uint32_t c = grid_cell(grid, topo.points[v]);
        cell[v] = c;
        corner_near[v] = near_marked[grid.index(c & 0xff, c >> 8 & 0xff, c >> 16 & 0xff)];
      }
    }
  });
  auto meets_marked = [&](std::uint32_t t) {
    const auto& tri = topo.tris[t];
    if (!in_region(t)) return false;
    const bool near_all = (corner_near[tri[0]] & corner_near[tri[1]] & corner_near[tri[2]]) != 0;
    const TriangleCells box = cells_of(t, true);
    bool meets = false;
    if (box.hi[0] - box.lo[0] <= 1 && box.hi[1] - box.lo[1] <= 1 && box.hi[2] - box.lo[2] <= 1) {
      if (!near_all) return false;
      // At most two cells per axis (most triangles): the box's cells are the combinations of lo
      // and hi, read without branches.
      for (int k = 0; k < 8; ++k)
        meets |= marked[grid.index(k & 1 ? box.hi[0] : box.lo[0], k & 2 ? box.hi[1] : box.lo[1],
                                   k & 4 ? box.hi[2] : box.lo[2])] != 0;
    } else {
      for (int z = box.lo[2]; z <= box.hi[2] && !meets; ++z)
        for (int y = box.lo[1]; y <= box.hi[1] && !meets; ++y)
          for (int x = box.lo[0]; x <= box.hi[0] && !meets; ++x)
            meets = marked[grid.index(x, y, z)] != 0;
    }
    return meets;
  };
  keep_where([&](std::uint32_t m) { return m == largest; }, meets_marked);
  return kept;
}

}  // namespace untangle
