// The software z-buffer rasterizer: shaded triangles, contours over them, the legend.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "detect/run_parallel.h"
#include "geometry/vec3.h"
#include "render/legend.h"
#include "untangle/render.h"

#include <stb/stb_easy_font.h>

namespace untangle {

namespace {

using Rgb = std::array<std::uint8_t, 3>;
using Colour = std::array<double, 3>;  // 0..255

constexpr Rgb kBackground{236, 239, 243};
constexpr Rgb kObstacle{188, 186, 180};
constexpr std::array<Rgb, 6> kPalette{{{84, 136, 208},
                                       {96, 176, 96},
                                       {226, 168, 56},
                                       {64, 176, 182},
                                       {150, 110, 200},
                                       {168, 166, 76}}};
constexpr Rgb kContour{222, 16, 16};
constexpr Rgb kTint{214, 58, 214};         // tint 1: faces that cross
constexpr Rgb kIllegalTint{240, 165, 40};  // tint 2: illegal regions
constexpr double kAmbient = 0.32;
constexpr double kDiffuse = 0.68;
constexpr double kBackFace = 0.78;  // back faces are lit like front faces, a little darker
constexpr int kBandRows = 16;       // rows per band: the unit of parallel work

// v / |v| by division (not vec3.h's unit(), which multiplies by 1 / |v|: the golden pictures were
// made with this rounding).
Vec3 normalized(const Vec3& v) {
  const double n = std::sqrt(dot(v, v));
  if (!(n > 0.0)) return {0, 0, 0};
  return {v[0] / n, v[1] / n, v[2] / n};
}

std::uint8_t to_byte(double v) {
  if (!(v > 0.0)) return 0;
  if (v >= 255.0) return 255;
  return static_cast<std::uint8_t>(v + 0.5);
}

// Pale blue (0, unmoved) -> teal -> yellow -> orange (1): unlike the obstacles' grey, and no red,
// which is the contours'.
Colour heat_colour(double t) {
  constexpr std::array<Colour, 4> kStops{{{196, 212, 240}, {40, 168, 176}, {236, 214, 56},
                                          {246, 128, 24}}};
  if (!(t > 0.0)) t = 0.0;
  if (t > 1.0) t = 1.0;
  const double x = t * 3.0;
  const int k = std::min(2, static_cast<int>(x));
  const double f = x - k;
  Colour c;
  for (int i = 0; i < 3; ++i) c[i] = kStops[k][i] * (1.0 - f) + kStops[k + 1][i] * f;
  return c;
}

// A triangle ready to rasterize: picture coordinates, depth, per-corner colour (already lit).
struct ScreenTriangle {
  std::array<double, 3> x, y, depth;
  std::array<Colour, 3> colour;
  int row_min = 0, row_max = -1;  // rows whose pixel centres it may cover
};

struct Frame {
  int width = 0, height = 0;
  std::vector<double> depth;
  std::vector<std::uint8_t> pixels;
  void put(int x, int y, const Rgb& c) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    std::uint8_t* p = &pixels[3 * (static_cast<std::size_t>(y) * width + x)];
    p[0] = c[0];
    p[1] = c[1];
    p[2] = c[2];
  }
};

// Per mesh, the normal at each vertex index: the sum of the (area-weighted) normals of the
// triangles around it, normalized; zero where they cancel.
std::vector<Vec3> vertex_normals(const Mesh& mesh) {
  std::vector<Vec3> normals(mesh.positions.size(), Vec3{0, 0, 0});
  const std::size_t n = mesh.positions.size();
  for (const Triangle& t : mesh.triangles) {
    if (t[0] >= n || t[1] >= n || t[2] >= n) continue;
    const Vec3& a = mesh.positions[t[0]];
    const Vec3 face = cross(sub(mesh.positions[t[1]], a), sub(mesh.positions[t[2]], a));
    for (std::uint32_t v : t)
      for (int c = 0; c < 3; ++c) normals[v][c] += face[c];
  }
  for (Vec3& v : normals) v = normalized(v);
  return normals;
}

std::vector<ScreenTriangle> project(const std::vector<Mesh>& meshes, const RenderCamera& camera,
                                    const RenderMarks& marks) {
  const Vec3 light = normalized({0.8 * camera.toward_viewer[0] + 0.45 * camera.up[0] -
                                     0.35 * camera.right[0],
                                 0.8 * camera.toward_viewer[1] + 0.45 * camera.up[1] -
                                     0.35 * camera.right[1],
                                 0.8 * camera.toward_viewer[2] + 0.45 * camera.up[2] -
                                     0.35 * camera.right[2]});
  const double half_w = camera.width / 2.0, half_h = camera.height / 2.0;
  std::vector<ScreenTriangle> out;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = meshes[m];
    const std::size_t n = mesh.positions.size();
    const std::vector<Vec3> normals = vertex_normals(mesh);
    const Rgb base = mesh_colour(meshes, m);
    const std::vector<double>* heat =
        m < marks.heat.size() && marks.heat[m].size() == n ? &marks.heat[m] : nullptr;
    const std::vector<std::uint8_t>* tint =
        m < marks.tinted_triangles.size() && marks.tinted_triangles[m].size() == mesh.triangles.size()
            ? &marks.tinted_triangles[m]
            : nullptr;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      if (tri[0] >= n || tri[1] >= n || tri[2] >= n) continue;
      const Vec3& a = mesh.positions[tri[0]];
      const Vec3 face = cross(sub(mesh.positions[tri[1]], a), sub(mesh.positions[tri[2]], a));
      const double facing = dot(face, camera.toward_viewer) >= 0.0 ? 1.0 : -1.0;
      const Vec3 face_normal = normalized(face);
      ScreenTriangle s;
      for (int k = 0; k < 3; ++k) {
        const Vec3 d = sub(mesh.positions[tri[k]], camera.centre);
        s.x[k] = dot(d, camera.right) / camera.scale + half_w;
        s.y[k] = half_h - dot(d, camera.up) / camera.scale;
        s.depth[k] = dot(d, camera.toward_viewer);
        Vec3 normal = normals[tri[k]];
        if (dot(normal, normal) == 0.0) normal = face_normal;
        const double lambert = std::max(0.0, facing * dot(normal, light));
        const double light_level = (kAmbient + kDiffuse * lambert) * (facing > 0 ? 1.0 : kBackFace);
        Colour c{double(base[0]), double(base[1]), double(base[2])};
        if (heat != nullptr) c = heat_colour((*heat)[tri[k]]);
        if (tint != nullptr && (*tint)[t] != 0) {
          const Rgb& to = (*tint)[t] == 1 ? kTint : kIllegalTint;
          for (int i = 0; i < 3; ++i) c[i] = 0.3 * c[i] + 0.7 * to[i];
        }
        for (int i = 0; i < 3; ++i) s.colour[k][i] = c[i] * light_level;
      }
      const double y_lo = std::min({s.y[0], s.y[1], s.y[2]});
      const double y_hi = std::max({s.y[0], s.y[1], s.y[2]});
      // Off the picture (or not a number): skipped before any conversion to int.
      if (!(y_hi >= 0.0) || !(y_lo <= camera.height)) continue;
      const double x_lo = std::min({s.x[0], s.x[1], s.x[2]});
      const double x_hi = std::max({s.x[0], s.x[1], s.x[2]});
      if (!(x_hi >= 0.0) || !(x_lo <= camera.width)) continue;
      // Pixel row r has its centre at r + 0.5.
      s.row_min = static_cast<int>(std::max(0.0, std::ceil(y_lo - 0.5)));
      s.row_max = static_cast<int>(std::min(camera.height - 1.0, std::floor(y_hi - 0.5)));
      if (s.row_min > s.row_max) continue;
      out.push_back(s);
    }
  }
  return out;
}

// Rasterizes the triangles listed for one band of rows, in list order: a pixel keeps the nearest
// fragment, the first one on a tie, so that every band decides alone what the serial loop would.
void rasterize_band(const std::vector<ScreenTriangle>& triangles,
                    const std::vector<std::uint32_t>& list, int row_begin, int row_end,
                    Frame& frame) {
  for (std::uint32_t index : list) {
    const ScreenTriangle& s = triangles[index];
    const double area = (s.x[1] - s.x[0]) * (s.y[2] - s.y[0]) - (s.x[2] - s.x[0]) * (s.y[1] - s.y[0]);
    if (area == 0.0) continue;
    const double x_lo = std::min({s.x[0], s.x[1], s.x[2]});
    const double x_hi = std::max({s.x[0], s.x[1], s.x[2]});
    const int col_min = static_cast<int>(std::max(0.0, std::ceil(x_lo - 0.5)));
    const int col_max = static_cast<int>(std::min(frame.width - 1.0, std::floor(x_hi - 0.5)));
    const int r0 = std::max(row_begin, s.row_min), r1 = std::min(row_end - 1, s.row_max);
    for (int row = r0; row <= r1; ++row) {
      const double py = row + 0.5;
      for (int col = col_min; col <= col_max; ++col) {
        const double px = col + 0.5;
        // Edge functions, each the doubled signed area of the pixel centre with one edge.
        double w0 = (s.x[2] - s.x[1]) * (py - s.y[1]) - (s.y[2] - s.y[1]) * (px - s.x[1]);
        double w1 = (s.x[0] - s.x[2]) * (py - s.y[2]) - (s.y[0] - s.y[2]) * (px - s.x[2]);
        double w2 = (s.x[1] - s.x[0]) * (py - s.y[0]) - (s.y[1] - s.y[0]) * (px - s.x[0]);
        if (area < 0.0) {
          w0 = -w0;
          w1 = -w1;
          w2 = -w2;
        }
        if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
        const double a = std::fabs(area);
        const double l0 = w0 / a, l1 = w1 / a, l2 = w2 / a;
        const double z = l0 * s.depth[0] + l1 * s.depth[1] + l2 * s.depth[2];
        const std::size_t pixel = static_cast<std::size_t>(row) * frame.width + col;
        if (!(z > frame.depth[pixel])) continue;
        frame.depth[pixel] = z;
        std::uint8_t* p = &frame.pixels[3 * pixel];
        for (int i = 0; i < 3; ++i)
          p[i] = to_byte(l0 * s.colour[0][i] + l1 * s.colour[1][i] + l2 * s.colour[2][i]);
      }
    }
  }
}

// A disc of radius `radius` pixels around picture point (x, y).
void stamp(Frame& frame, double x, double y, double radius, const Rgb& colour) {
  // Off the picture (or not a number): nothing to draw, and no conversion to int.
  if (!(x >= -radius - 1 && x <= frame.width + radius + 1 && y >= -radius - 1 &&
        y <= frame.height + radius + 1))
    return;
  const int c0 = static_cast<int>(std::floor(x - radius)), c1 = static_cast<int>(std::ceil(x + radius));
  const int r0 = static_cast<int>(std::floor(y - radius)), r1 = static_cast<int>(std::ceil(y + radius));
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      const double dx = c + 0.5 - x, dy = r + 0.5 - y;
      if (dx * dx + dy * dy <= radius * radius) frame.put(c, r, colour);
    }
  }
}

void draw_contours(const std::vector<RenderPolyline>& contours, const RenderCamera& camera,
                   Frame& frame) {
  const double radius = std::max(1.0, std::min(camera.width, camera.height) / 320.0);
  auto to_picture = [&](const Vec3& p, double& x, double& y) {
    const Vec3 d = sub(p, camera.centre);
    x = dot(d, camera.right) / camera.scale + camera.width / 2.0;
    y = camera.height / 2.0 - dot(d, camera.up) / camera.scale;
  };
  for (const RenderPolyline& line : contours) {
    const std::size_t n = line.points.size();
    if (n == 0) continue;
    const std::size_t segments = line.closed ? n : n - 1;
    double x0 = 0, y0 = 0;
    to_picture(line.points[0], x0, y0);
    stamp(frame, x0, y0, radius, kContour);
    for (std::size_t k = 0; k < segments; ++k) {
      double xa = 0, ya = 0, xb = 0, yb = 0;
      to_picture(line.points[k], xa, ya);
      to_picture(line.points[(k + 1) % n], xb, yb);
      const double length = std::hypot(xb - xa, yb - ya);
      if (!(length < 1e6)) continue;  // a point far outside the picture
      const int steps = std::max(1, static_cast<int>(std::ceil(length * 2.0)));
      for (int s = 1; s <= steps; ++s) {
        const double f = static_cast<double>(s) / steps;
        stamp(frame, xa + (xb - xa) * f, ya + (yb - ya) * f, radius, kContour);
      }
    }
  }
}

void fill_rect(Frame& frame, int x0, int y0, int x1, int y1, const Rgb& colour) {
  for (int y = std::max(0, y0); y < std::min(frame.height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(frame.width, x1); ++x) frame.put(x, y, colour);
}

// The legend: stb_easy_font's glyphs (axis-aligned quads on an integer grid), scaled by `scale`.
void draw_legend(const std::vector<Mesh>& meshes, const RenderMarks& marks, Frame& frame) {
  if (marks.legend.empty()) return;
  const int scale = render::legend_scale(frame.width, frame.height);
  const int line_height = 12 * scale, pad = 4 * scale, swatch = 8 * scale;
  int text_width = 0;
  std::vector<std::vector<char>> texts;
  for (const std::string& line : marks.legend) {
    std::vector<char> text(line.begin(), line.end());
    for (char& c : text)
      if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
    text.push_back('\0');
    text_width = std::max(text_width, stb_easy_font_width(text.data()) * scale);
    texts.push_back(std::move(text));
  }
  const int left = pad, top = pad;
  const int box_w = pad + swatch + pad + text_width + pad;
  const int box_h = pad + line_height * static_cast<int>(texts.size()) + pad;
  fill_rect(frame, left, top, left + box_w, top + box_h, {255, 255, 255});
  std::vector<char> quads(texts.empty() ? 0 : 64 * 1024);
  for (std::size_t k = 0; k < texts.size(); ++k) {
    const int y = top + pad + line_height * static_cast<int>(k);
    const int mesh = k < marks.legend_mesh.size() ? marks.legend_mesh[k] : -1;
    if (mesh >= 0 && static_cast<std::size_t>(mesh) < meshes.size()) {
      const Rgb c = mesh_colour(meshes, static_cast<std::size_t>(mesh));
      fill_rect(frame, left + pad, y, left + pad + swatch, y + swatch, c);
    }
    const int count = stb_easy_font_print(0, 0, texts[k].data(), nullptr, quads.data(),
                                          static_cast<int>(quads.size()));
    const int x = left + pad + swatch + pad;
    for (int q = 0; q < count; ++q) {
      // Each quad is four vertices of 16 bytes: x, y, z as float, then a colour.
      float corner[4][2];
      for (int v = 0; v < 4; ++v) {
        const char* vertex = quads.data() + (q * 4 + v) * 16;
        std::copy(vertex, vertex + 4, reinterpret_cast<char*>(&corner[v][0]));
        std::copy(vertex + 4, vertex + 8, reinterpret_cast<char*>(&corner[v][1]));
      }
      float qx0 = corner[0][0], qx1 = corner[0][0], qy0 = corner[0][1], qy1 = corner[0][1];
      for (int v = 1; v < 4; ++v) {
        qx0 = std::min(qx0, corner[v][0]);
        qx1 = std::max(qx1, corner[v][0]);
        qy0 = std::min(qy0, corner[v][1]);
        qy1 = std::max(qy1, corner[v][1]);
      }
      fill_rect(frame, x + static_cast<int>(std::lround(qx0 * scale)),
                y + static_cast<int>(std::lround(qy0 * scale)),
                x + static_cast<int>(std::lround(qx1 * scale)),
                y + static_cast<int>(std::lround(qy1 * scale)), {24, 24, 24});
    }
  }
}

}  // namespace

std::array<std::uint8_t, 3> mesh_colour(const std::vector<Mesh>& meshes, std::size_t index) {
  if (index >= meshes.size() || meshes[index].role == Role::kObstacle) return kObstacle;
  std::size_t movable = 0;
  for (std::size_t m = 0; m < index; ++m) movable += meshes[m].role == Role::kMovable ? 1 : 0;
  return kPalette[movable % kPalette.size()];
}

RgbImage render_meshes(const std::vector<Mesh>& meshes, const RenderCamera& camera,
                       const RenderMarks& marks, int threads) {
  RgbImage image;
  if (camera.width <= 0 || camera.height <= 0 || !(camera.scale > 0.0)) return image;
  Frame frame;
  frame.width = camera.width;
  frame.height = camera.height;
  const std::size_t pixels = static_cast<std::size_t>(frame.width) * frame.height;
  frame.depth.assign(pixels, -std::numeric_limits<double>::infinity());
  frame.pixels.resize(3 * pixels);
  for (std::size_t p = 0; p < pixels; ++p)
    for (int i = 0; i < 3; ++i) frame.pixels[3 * p + i] = kBackground[i];

  const std::vector<ScreenTriangle> triangles = project(meshes, camera, marks);
  // Each band lists, in scene order, the triangles that reach its rows.
  const int bands = (frame.height + kBandRows - 1) / kBandRows;
  std::vector<std::vector<std::uint32_t>> lists(static_cast<std::size_t>(bands));
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int b = triangles[t].row_min / kBandRows; b <= triangles[t].row_max / kBandRows; ++b)
      lists[static_cast<std::size_t>(b)].push_back(static_cast<std::uint32_t>(t));
  }
  run_parallel(threads, static_cast<std::size_t>(bands), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      const int row_begin = static_cast<int>(b) * kBandRows;
      rasterize_band(triangles, lists[b], row_begin, std::min(frame.height, row_begin + kBandRows),
                     frame);
    }
  });
  draw_contours(marks.contours, camera, frame);
  draw_legend(meshes, marks, frame);

  image.width = frame.width;
  image.height = frame.height;
  image.pixels = std::move(frame.pixels);
  return image;
}

RgbImage side_by_side(const RgbImage& left, const RgbImage& right) {
  RgbImage out;
  out.width = left.width + right.width;
  out.height = std::max(left.height, right.height);
  out.pixels.assign(static_cast<std::size_t>(out.width) * out.height * 3, 255);
  auto copy = [&](const RgbImage& from, int x0) {
    for (int y = 0; y < from.height; ++y) {
      const auto* src = &from.pixels[3 * static_cast<std::size_t>(y) * from.width];
      std::copy(src, src + 3 * from.width,
                &out.pixels[3 * (static_cast<std::size_t>(y) * out.width + x0)]);
    }
  };
  copy(left, 0);
  copy(right, left.width);
  return out;
}

}  // namespace untangle
