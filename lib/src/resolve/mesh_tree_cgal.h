// The CGAL part of a MeshTree (resolve/surface_queries.h): its entries' triangles, which closest
// points are projected onto, and the AABB tree over them that rays are cast into, built at the
// first ray.
#pragma once

#include <memory>
#include <mutex>

#include "resolve/triangle_tree.h"

namespace untangle {

struct MeshTreeCgal {
  TreeTriangleList triangles;  // one per MeshTree entry
  const TriangleTree& ray_tree() const;

 private:
  mutable std::once_flag rays_built_;
  mutable std::unique_ptr<TriangleTree> rays_;
};

}  // namespace untangle
