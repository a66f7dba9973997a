// Pictures of a scene: a deterministic software z-buffer rasterizer and its PNG encoding.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "untangle/intersections.h"
#include "untangle/mesh.h"

namespace untangle {

// Where the camera looks from. The scene's up axis is +y (MakeHuman, glTF): front looks from +z
// toward -z, back from -z, left from -x (the left of the front view), right from +x, top from +y
// down with -z up in the picture. kAuto is resolved by best_view().
enum class RenderView { kFront, kBack, kLeft, kRight, kTop, kAuto };
const char* to_string(RenderView view);

// An RGB picture, 8 bits per channel, rows from top to bottom, no padding:
// pixels[3 * (y * width + x) + c].
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
};

// An orthographic camera: a point p lands at picture coordinates
// ((p - centre) . right / scale + width / 2, height / 2 - (p - centre) . up / scale), and
// (p - centre) . toward_viewer is its depth (larger is nearer).
struct RenderCamera {
  Vec3 centre{};
  Vec3 right{1, 0, 0};
  Vec3 up{0, 1, 0};
  Vec3 toward_viewer{0, 0, 1};
  double scale = 1.0;  // scene units per pixel
  int width = 0;
  int height = 0;
};

// A polyline drawn over the surfaces (a contour), `closed` joining its last point to its first.
struct RenderPolyline {
  std::vector<Vec3> points;
  bool closed = false;
};

// What is drawn besides the shaded surfaces. Every per-mesh vector is either empty (nothing for
// any mesh) or holds one entry per mesh, which may itself be empty (nothing for that mesh).
struct RenderMarks {
  // Drawn last in red, over everything, so that they show through the surfaces; about
  // min(width, height) / 160 pixels wide (5 px at 800).
  std::vector<RenderPolyline> contours;
  // Per mesh, per triangle: 1 tints the triangle magenta (faces that take part in crossings), 2
  // amber (a corner in an illegal region or inside an obstacle), for `render --inside`.
  std::vector<std::vector<std::uint8_t>> tinted_triangles;
  // Per mesh, per vertex: a value in [0, 1] (clamped) coloured from pale blue (0) through teal
  // and yellow to orange (1) instead of the mesh's own colour: the displacement heat map of
  // `fix --preview`.
  std::vector<std::vector<double>> heat;
  // Lines of text drawn top left, 8 px font (doubled at 800 px and more), on a white box; the
  // colour swatch before line k is the colour of mesh legend_mesh[k] (none when -1 or absent).
  std::vector<std::string> legend;
  std::vector<int> legend_mesh;
};

struct RenderOptions {
  int width = 800;   // pixels (of each panel of render_before_after), 16 to 8192
  int height = 800;  // pixels, 16 to 8192
  RenderView view = RenderView::kAuto;
  bool contours = false;  // draw the contours (render_before_after always does)
  bool inside = false;    // tint the illegal regions (amber) and the faces that cross (magenta)
  bool legend = true;     // file names and counts, top left
  int threads = 0;  // 0 = all cores; the picture is the same bytes for every value
};

// The view among front, back, left, right, top (in that order of preference on a tie) under which
// the contours' total projected length is largest; kFront when there are none.
RenderView best_view(const std::vector<RenderPolyline>& contours);

// A camera looking from `view` (not kAuto) that fits the bounding box of every mesh of every list
// given (so that two states of one scene share one camera), with a 4 % margin, into the picture
// below its top `top_margin` rows (room for a legend). Meshes without vertices are ignored; an
// empty scene gives a unit box at the origin.
RenderCamera fit_camera(const std::vector<const std::vector<Mesh>*>& scenes, RenderView view,
                        int width, int height, int top_margin = 0);

// The colour of mesh `index` in `meshes`: obstacles a neutral grey, movable meshes from a fixed
// palette in order of the movable meshes (no red: red is the contours').
std::array<std::uint8_t, 3> mesh_colour(const std::vector<Mesh>& meshes, std::size_t index);

// Draws every triangle of every mesh (Lambert + ambient with a light near the viewer, both sides
// lit, back faces slightly darker; vertex normals averaged from the faces around each vertex
// index), then the marks. Deterministic: the same bytes for the same input at any thread count.
// Never prints. Triangles with an index out of range are skipped.
RgbImage render_meshes(const std::vector<Mesh>& meshes, const RenderCamera& camera,
                       const RenderMarks& marks, int threads = 0);

// Places `right` to the right of `left` (the taller one's height, white where one is shorter).
RgbImage side_by_side(const RgbImage& left, const RgbImage& right);

// The PNG file (8-bit RGB, no metadata) of an image, as bytes. The encoder is stb_image_write's,
// compiled into the library, so the bytes depend on neither zlib's version nor the machine.
std::string encode_png(const RgbImage& image);

// What render_scene found and chose.
struct RenderSummary {
  RenderView view = RenderView::kFront;  // the view drawn (kAuto resolved)
  IntersectionCounts counts;             // of the detection (zero when none was needed)
};

// The picture of `untangle render`: every mesh shaded in its colour (mesh_colour), fitted to the
// picture from options.view; with options.contours the contours of find_intersections (default
// DetectOptions, options.threads) in red, with options.inside the illegal regions (illegal_vertices)
// tinted amber and the triangles of intersecting pairs magenta; above them (the camera leaves room) a legend with each mesh's file name (without folder; ":name" when a file holds several
// meshes), role, vertices and triangles, then the counts and the view. Detection runs only when
// contours, inside or the auto view need it. Deterministic, never prints.
RgbImage render_scene(const std::vector<Mesh>& meshes, const RenderOptions& options,
                      RenderSummary* summary = nullptr);

// The picture of `fix --preview`: three panels of options.width x options.height from one camera
// (fitted to both states; options.view, kAuto resolved on the contours before): `before` with
// the contours of `found_before` in red; `after` with those of `found_after` (the remaining
// ones); `after` again with each movable vertex coloured by its displacement from `before`
// (pale blue unmoved, orange the largest of the scene), the remaining contours over it. `before` and
// `after` hold the same meshes in the same order. Deterministic, never prints.
RgbImage render_before_after(const std::vector<Mesh>& before, const std::vector<Mesh>& after,
                             const Intersections& found_before, const Intersections& found_after,
                             const RenderOptions& options);

}  // namespace untangle
