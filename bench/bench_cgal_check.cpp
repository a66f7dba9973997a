// The CGAL side of the whole-process comparison with `untangle check` (docs/PERFORMANCE.md,
// "The whole check process against CGAL"): a small program that does check's job with CGAL 5.5.1
// alone. It reads every file given (OBJ or OFF, through CGAL's own readers into a polygon soup,
// vertices welded by CGAL's repair like check welds them), then for each mesh the intersecting
// pairs of its own triangles (PMP::self_intersections) and for each pair of meshes the
// intersection polylines (PMP::surface_intersection), and prints the counts.
//
// Usage: untangle_bench_cgal_check FILE...   (exit 0 after printing; 1 on an unreadable file)
// `--timed` adds the in-process milliseconds of the work after reading (the job of
// `untangle check --timings`' detect + contours figures).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Face = SurfaceMesh::Face_index;
namespace PMP = CGAL::Polygon_mesh_processing;

}  // namespace

int main(int argc, char** argv) {
  bool timed = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--timed") == 0) {
      timed = true;
    } else if (std::strcmp(argv[i], "-h") == 0 || std::strcmp(argv[i], "--help") == 0) {
      std::printf("usage: %s [--timed] FILE...\n", argv[0]);
      return 0;
    } else {
      files.push_back(argv[i]);
    }
  }
  std::vector<SurfaceMesh> meshes(files.size());
  for (std::size_t m = 0; m < files.size(); ++m) {
    std::vector<Point> points;
    std::vector<std::vector<std::size_t>> polygons;
    if (!CGAL::IO::read_polygon_soup(files[m], points, polygons)) {
      std::fprintf(stderr, "error: %s: not readable\n", files[m].c_str());
      return 1;
    }
    PMP::repair_polygon_soup(points, polygons);  // welds duplicate points, drops degenerate faces
    PMP::orient_polygon_soup(points, polygons);
    PMP::polygon_soup_to_polygon_mesh(points, polygons, meshes[m]);
    PMP::triangulate_faces(meshes[m]);
  }
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    std::vector<std::pair<Face, Face>> pairs;
    PMP::self_intersections(meshes[m], std::back_inserter(pairs));
    std::printf("%s: %zu self-intersecting pairs\n", files[m].c_str(), pairs.size());
  }
  for (std::size_t a = 0; a < meshes.size(); ++a)
    for (std::size_t b = a + 1; b < meshes.size(); ++b) {
      std::vector<std::vector<Point>> polylines;
      PMP::surface_intersection(meshes[a], meshes[b], std::back_inserter(polylines));
      std::size_t points = 0;
      for (const auto& polyline : polylines) points += polyline.size();
      std::printf("%s / %s: %zu polylines, %zu points\n", files[a].c_str(), files[b].c_str(),
                  polylines.size(), points);
    }
  if (timed)
    std::printf("work ms %.3f\n",
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  return 0;
}
