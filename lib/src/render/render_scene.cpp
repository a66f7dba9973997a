// The pictures of the CLI: `render` (a scene with its contours) and `fix --preview` (before,
// after, displacement), composed from render_meshes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "resolve/illegal_vertices.h"
#include "render/legend.h"
#include "untangle/render.h"

namespace untangle {

namespace {

std::vector<RenderPolyline> polylines_of(const Intersections& found) {
  std::vector<RenderPolyline> lines;
  for (const Contour& contour : found.contours) lines.push_back({contour.polyline, contour.closed});
  return lines;
}

// A mesh's name in the legend: its file name without the folder, so that the picture does not
// depend on where the files lie; ":name" when its file holds several meshes.
std::string legend_label(const std::vector<Mesh>& meshes, std::size_t index) {
  const Mesh& mesh = meshes[index];
  std::size_t same_file = 0;
  for (const Mesh& other : meshes) same_file += other.path == mesh.path ? 1 : 0;
  std::string label = mesh.path.empty() ? mesh.name
                                        : std::filesystem::path(mesh.path).filename().string();
  if (!mesh.path.empty() && same_file > 1 && !mesh.name.empty()) label += ":" + mesh.name;
  return label;
}

std::string mesh_line(const std::vector<Mesh>& meshes, std::size_t m) {
  return legend_label(meshes, m) + " (" + to_string(meshes[m].role) + "), " +
         std::to_string(meshes[m].positions.size()) + " vertices, " +
         std::to_string(meshes[m].triangles.size()) + " triangles";
}

std::string counts_line(const char* what, const IntersectionCounts& counts) {
  return std::string(what) + std::to_string(counts.crossings) + " crossings, " +
         std::to_string(counts.contours) + " contours";
}

void add_mesh_lines(const std::vector<Mesh>& meshes, RenderMarks& marks) {
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    marks.legend.push_back(mesh_line(meshes, m));
    marks.legend_mesh.push_back(static_cast<int>(m));
  }
}

void add_line(RenderMarks& marks, std::string line) {
  marks.legend.push_back(std::move(line));
  marks.legend_mesh.push_back(-1);
}

// "%.3g" of a length, the same text on every machine for the same double.
std::string short_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

}  // namespace

RgbImage render_scene(const std::vector<Mesh>& meshes, const RenderOptions& options,
                      RenderSummary* summary) {
  Intersections found;
  const bool detect = options.contours || options.inside || options.view == RenderView::kAuto;
  if (detect) {
    DetectOptions detect_options;
    detect_options.threads = options.threads;
    found = find_intersections(meshes, detect_options);
  }
  const std::vector<RenderPolyline> contours = polylines_of(found);
  const RenderView view = options.view == RenderView::kAuto ? best_view(contours) : options.view;

  RenderMarks marks;
  if (options.contours) marks.contours = contours;
  if (options.inside) {
    // Amber (2): a triangle with a corner in an illegal region or inside an obstacle; magenta
    // (1, drawn over amber): a triangle of an intersecting pair.
    const std::vector<std::vector<std::uint8_t>> illegal =
        illegal_vertices(meshes, true, options.threads);
    marks.tinted_triangles.resize(meshes.size());
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      marks.tinted_triangles[m].assign(meshes[m].triangles.size(), 0);
      for (std::size_t t = 0; t < meshes[m].triangles.size(); ++t)
        for (std::uint32_t v : meshes[m].triangles[t])
          if (v < illegal[m].size() && illegal[m][v]) marks.tinted_triangles[m][t] = 2;
    }
    for (const auto& pair : found.triangle_pairs) {
      for (int side = 0; side < 2; ++side) {
        const std::uint32_t mesh = pair[2 * side], triangle = pair[2 * side + 1];
        if (mesh < meshes.size() && triangle < meshes[mesh].triangles.size())
          marks.tinted_triangles[mesh][triangle] = 1;
      }
    }
  }
  if (options.legend) {
    add_mesh_lines(meshes, marks);
    std::string last = detect ? counts_line("", found.counts) + ", " : std::string();
    last += std::string("view ") + to_string(view);
    add_line(marks, last);
    if (options.contours) add_line(marks, "red: contours");
    if (options.inside) add_line(marks, "magenta: faces that cross; amber: illegal regions");
  }
  if (summary != nullptr) {
    summary->view = view;
    summary->counts = found.counts;
  }
  const RenderCamera camera =
      fit_camera({&meshes}, view, options.width, options.height,
                 render::legend_bottom(marks.legend.size(), options.width, options.height));
  return render_meshes(meshes, camera, marks, options.threads);
}

RgbImage render_before_after(const std::vector<Mesh>& before, const std::vector<Mesh>& after,
                             const Intersections& found_before, const Intersections& found_after,
                             const RenderOptions& options) {
  const std::vector<RenderPolyline> contours_before = polylines_of(found_before);
  const std::vector<RenderPolyline> contours_after = polylines_of(found_after);
  const RenderView view =
      options.view == RenderView::kAuto ? best_view(contours_before) : options.view;
  RenderMarks marks_before;
  marks_before.contours = contours_before;
  RenderMarks marks_after;
  marks_after.contours = contours_after;
  RenderMarks marks_heat;
  marks_heat.contours = contours_after;

  // Displacement per vertex of each movable mesh, scaled by the largest of the scene.
  double largest = 0.0;
  marks_heat.heat.resize(after.size());
  for (std::size_t m = 0; m < after.size() && m < before.size(); ++m) {
    const Mesh& a = after[m];
    const Mesh& b = before[m];
    if (a.role != Role::kMovable || a.positions.size() != b.positions.size()) continue;
    std::vector<double>& heat = marks_heat.heat[m];
    heat.resize(a.positions.size());
    for (std::size_t v = 0; v < a.positions.size(); ++v) {
      const double dx = a.positions[v][0] - b.positions[v][0];
      const double dy = a.positions[v][1] - b.positions[v][1];
      const double dz = a.positions[v][2] - b.positions[v][2];
      heat[v] = std::sqrt(dx * dx + dy * dy + dz * dz);
      largest = std::max(largest, heat[v]);
    }
  }
  for (std::vector<double>& heat : marks_heat.heat)
    for (double& h : heat) h = largest > 0.0 ? h / largest : 0.0;

  if (options.legend) {
    add_line(marks_before, "before");
    add_mesh_lines(before, marks_before);
    add_line(marks_before, counts_line("", found_before.counts) + ", view " + to_string(view));
    add_line(marks_after, "after");
    add_mesh_lines(after, marks_after);
    add_line(marks_after, counts_line("", found_after.counts) + " remain");
    add_line(marks_heat, "after: displacement");
    add_line(marks_heat, "pale blue 0 .. orange " + short_number(largest) + " (scene units)");
    add_line(marks_heat, counts_line("", found_after.counts) + " remain");
  }
  const std::size_t lines = std::max(marks_before.legend.size(),
                                     std::max(marks_after.legend.size(), marks_heat.legend.size()));
  const RenderCamera camera =
      fit_camera({&before, &after}, view, options.width, options.height,
                 render::legend_bottom(lines, options.width, options.height));
  const RgbImage left = render_meshes(before, camera, marks_before, options.threads);
  const RgbImage middle = render_meshes(after, camera, marks_after, options.threads);
  const RgbImage right = render_meshes(after, camera, marks_heat, options.threads);
  return side_by_side(side_by_side(left, middle), right);
}

}  // namespace untangle
