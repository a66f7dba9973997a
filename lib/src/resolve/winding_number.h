// The generalized winding number of a triangle soup (Jacobson, Kavan and Sorkine-Hornung 2013),
// evaluated on a hierarchy with the far-field dipole approximation of Barill et al. 2018.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

// w(p) = (1/4π) Σ Ω_t(p), the solid angles of the triangles seen from p, signed by their winding:
// 1 inside a closed outward surface, 0 outside, 2 where two parts of it overlap; holes, open
// boundaries, self-intersection and duplicated faces change it only near them. A node of the
// hierarchy farther from p than kFarField times its radius is summed as one dipole (its
// area-weighted normal at its area-weighted centre); nearer ones triangle by triangle. Doubles:
// the result steers moves and labels, never decides a crossing. Immutable after construction, so
// concurrent queries are safe; the value depends only on the triangles and p.
class WindingNumber {
 public:
  static constexpr double kFarField = 2.0;

  // The triangles `tris` of `points` (corners as indices), in the given order. The hierarchy is
  // built on `threads` threads (0: all cores), the same bits for every count.
  WindingNumber(const std::vector<Vec3>& points,
                const std::vector<std::array<std::uint32_t, 3>>& tris, int threads = 1);
  double operator()(const Vec3& p) const;
  // The same, and sets `in_plane` when p lies in the plane of a triangle summed one by one, up to
  // rounding (on the surface, or so near that the value may be that of either side).
  double evaluate(const Vec3& p, bool& in_plane) const;
  // The signed volume the triangles enclose (negative for an inward surface).
  double signed_volume() const { return volume_; }
  bool empty() const { return tri_.empty(); }
  // Whether this hierarchy was built from the triangles `tris` of `points`: as many, in the same
  // order, every corner equal bit for bit. The constructor would then build it again, the same.
  bool built_from(const std::vector<Vec3>& points,
                  const std::vector<std::array<std::uint32_t, 3>>& tris) const;

 private:
  struct Node {
    Vec3 centre{}, dipole{};  // area-weighted centroid, sum of the area vectors
    double radius = 0.0;      // a leaf: farthest corner; above: a ball holding the children's
    std::uint32_t begin = 0, end = 0;   // range of tri_
    std::uint32_t left = 0, right = 0;  // children (0: a leaf)
  };
  // A triangle while the hierarchy is built: what every node above it sums, computed once.
  struct Item {
    std::array<Vec3, 3> tri;
    Vec3 area_vector{}, centroid{}, weighted{};  // weighted: the centroid times the area
    double area = 0.0;
  };
  // A subtree of triangles [begin, end) still to build, its root at node `id`.
  struct Pending {
    std::uint32_t begin, end, id;
  };
  // An entry of the order being split: an index into the items with its centroid beside it, so
  // that the splits read and move the keys in place rather than through the index.
  struct Keyed {
    Vec3 centroid{};
    std::uint32_t item = 0;
  };
  // Splits node `id` over order[begin, end) and, below `depth` levels, its subtree: ranges and
  // children only, the sums are taken afterwards. The subtrees left at `depth` are appended to
  // `pending` (depth < 0: none left). Node ids are those of a pre-order numbering (node_count), so
  // the parts can be split in any order.
  void split(const std::vector<Item>& items, std::vector<Keyed>& order, std::uint32_t begin,
             std::uint32_t end, std::uint32_t id, int depth, std::vector<Pending>& pending);

  std::vector<std::array<Vec3, 3>> tri_;
  std::vector<std::uint32_t> input_of_;  // per entry of tri_: its index in the constructor's tris
  std::vector<Node> nodes_;
  double volume_ = 0.0;
};

}  // namespace untangle
