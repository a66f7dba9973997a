// A bounding-volume hierarchy over triangles of meshes that do not move (obstacles): built once,
// queried with the boxes of the moving triangles every iteration.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "topology/scene_topology.h"

namespace untangle {

struct Box3 {
  std::array<double, 3> lo{}, hi{};
  bool overlaps(const Box3& o) const {  // closed boxes: touching counts
    for (int k = 0; k < 3; ++k)
      if (hi[k] < o.lo[k] || o.hi[k] < lo[k]) return false;
    return true;
  }
};

Box3 triangle_box(const SceneTopology& topology, std::uint32_t t);

class TriangleBvh {
 public:
  // Over the triangles whose mesh is flagged in `include`.
  TriangleBvh(const SceneTopology& topology, const std::vector<bool>& include);

  // Appends every indexed triangle whose box overlaps `box` (in no particular order).
  void query(const Box3& box, std::vector<std::uint32_t>& out) const;
  bool empty() const { return triangles_.empty(); }

 private:
  struct Node {
    Box3 box;
    std::uint32_t first = 0, count = 0;  // leaf: range in triangles_
    std::uint32_t left = 0, right = 0;   // inner: children
  };
  struct Item {
    Box3 box;
    std::array<double, 3> centre{};  // twice the box centre
    std::uint32_t tri = 0;
  };
  std::uint32_t build(std::uint32_t first, std::uint32_t count, std::vector<Item>& items);

  std::vector<Node> nodes_;
  std::vector<std::uint32_t> triangles_;
  std::vector<Box3> leaf_boxes_;  // per entry of triangles_
};

}  // namespace untangle
