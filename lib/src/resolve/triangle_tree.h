// The CGAL AABB tree over a list of triangles that the resolve stage queries for closest points,
// ray exits and winding numbers (doubles: it only steers moves).
#pragma once

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <vector>

namespace untangle {

using TreeKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using TreeTriangleList = std::vector<TreeKernel::Triangle_3>;
using TreePrimitive = CGAL::AABB_triangle_primitive<TreeKernel, TreeTriangleList::const_iterator>;
using TriangleTree = CGAL::AABB_tree<CGAL::AABB_traits<TreeKernel, TreePrimitive>>;

}  // namespace untangle
