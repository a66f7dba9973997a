// The cameras of a picture: the five fixed views, the auto view, fitting a camera to a scene.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "geometry/vec3.h"
#include "untangle/render.h"

namespace untangle {

namespace {


// The orientation of a view: right, up, toward the viewer (a right-handed frame).
struct ViewAxes {
  Vec3 right, up, toward;
};

ViewAxes axes_of(RenderView view) {
  switch (view) {
    case RenderView::kBack: return {{-1, 0, 0}, {0, 1, 0}, {0, 0, -1}};
    case RenderView::kLeft: return {{0, 0, 1}, {0, 1, 0}, {-1, 0, 0}};
    case RenderView::kRight: return {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}};
    case RenderView::kTop: return {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}};
    case RenderView::kFront:
    case RenderView::kAuto: break;
  }
  return {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
}

}  // namespace

const char* to_string(RenderView view) {
  switch (view) {
    case RenderView::kFront: return "front";
    case RenderView::kBack: return "back";
    case RenderView::kLeft: return "left";
    case RenderView::kRight: return "right";
    case RenderView::kTop: return "top";
    case RenderView::kAuto: return "auto";
  }
  return "front";
}

RenderView best_view(const std::vector<RenderPolyline>& contours) {
  constexpr std::array<RenderView, 5> kViews = {RenderView::kFront, RenderView::kBack,
                                                RenderView::kLeft, RenderView::kRight,
                                                RenderView::kTop};
  RenderView best = RenderView::kFront;
  double best_length = 0.0;
  for (RenderView view : kViews) {
    const Vec3 axis = axes_of(view).toward;
    double length = 0.0;
    for (const RenderPolyline& line : contours) {
      const std::size_t n = line.points.size();
      const std::size_t segments = line.closed ? n : (n > 0 ? n - 1 : 0);
      for (std::size_t k = 0; k < segments && n >= 2; ++k) {
        const Vec3& a = line.points[k];
        const Vec3& b = line.points[(k + 1) % n];
        const Vec3 d{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double along = dot(d, axis);
        length += std::sqrt(std::max(0.0, dot(d, d) - along * along));
      }
    }
    // Strictly longer only: a tie keeps the earlier view of kViews.
    if (length > best_length) {
      best_length = length;
      best = view;
    }
  }
  return best;
}

RenderCamera fit_camera(const std::vector<const std::vector<Mesh>*>& scenes, RenderView view,
                        int width, int height, int top_margin) {
  const ViewAxes axes = axes_of(view);
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi{-lo[0], -lo[1], -lo[2]};
  bool any = false;
  for (const std::vector<Mesh>* meshes : scenes) {
    if (meshes == nullptr) continue;
    for (const Mesh& mesh : *meshes) {
      for (const Vec3& p : mesh.positions) {
        for (int c = 0; c < 3; ++c) {
          lo[c] = std::min(lo[c], p[c]);
          hi[c] = std::max(hi[c], p[c]);
        }
        any = true;
      }
    }
  }
  if (!any) {
    lo = {-0.5, -0.5, -0.5};
    hi = {0.5, 0.5, 0.5};
  }
  RenderCamera camera;
  camera.centre = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  camera.right = axes.right;
  camera.up = axes.up;
  camera.toward_viewer = axes.toward;
  camera.width = width;
  camera.height = height;
  const Vec3 size{hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
  // The box's extent along each picture axis (the axes are coordinate axes, up to sign).
  const double across = std::fabs(dot(size, axes.right));
  const double along = std::fabs(dot(size, axes.up));
  const int margin = std::max(0, std::min(top_margin, height / 2));
  const double w = std::max(1, width), h = std::max(1, height - margin);
  double scale = std::max(across / w, along / h) * 1.08;  // 4 % margin on each side
  if (!(scale > 0.0)) scale = 1.0 / std::min(w, h);
  camera.scale = scale;
  // The box's centre at the middle of the rows below the margin: the picture's centre row is
  // margin / 2 rows above it, so the camera's centre moves that far up in the scene.
  for (int c = 0; c < 3; ++c) camera.centre[c] += axes.up[c] * (margin / 2.0) * scale;
  return camera;
}

}  // namespace untangle
