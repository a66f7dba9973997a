// Pictures: the golden PNG, contours where they project, the same bytes at any thread count, the
// views, and `untangle render` / `fix --preview` end to end.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "scene_files.h"
#include "scenes/scenes.h"
#include "test_support.h"
#include "untangle/intersections.h"
#include "untangle/read_meshes.h"
#include "untangle/render.h"
#include "geometry/vec3.h"
#include "resolve/illegal_vertices.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;
using testing::write_text;

constexpr std::array<std::uint8_t, 3> kRed{222, 16, 16};  // the contours' colour

std::array<std::uint8_t, 3> pixel(const RgbImage& image, int x, int y) {
  const std::uint8_t* p = &image.pixels[3 * (static_cast<std::size_t>(y) * image.width + x)];
  return {p[0], p[1], p[2]};
}

fs::path golden_path(const std::string& name) {
  return fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "render" / (name + ".png");
}

// The golden picture: sheet_through_sphere at 320 x 320, auto view, contours and the faces that
// cross tinted, legend on. Compared byte for byte with testdata/render/; the rasterizer is
// deterministic (doubles without contraction, a fixed triangle order per pixel) and the PNG
// encoder is compiled in. UNTANGLE_REWRITE_RENDER_GOLDEN=1 rewrites the file for review
// (then `git diff --stat testdata/render` and look at it).
TEST(RenderGolden, SheetThroughSphereMatchesTestdata) {
  const std::vector<Mesh> meshes = scenes::scene_meshes(scenes::sheet_through_sphere());
  RenderOptions options;
  options.width = 320;
  options.height = 320;
  options.contours = true;
  options.inside = true;
  options.threads = 2;
  RenderSummary summary;
  const std::string png = encode_png(render_scene(meshes, options, &summary));
  EXPECT_EQ(summary.view, RenderView::kFront);  // the sheet lies in z = const: front shows it all
  EXPECT_EQ(summary.counts.contours, 1u);
  const fs::path path = golden_path("sheet_through_sphere");
  const char* rewrite = std::getenv("UNTANGLE_REWRITE_RENDER_GOLDEN");
  if (rewrite != nullptr && std::string(rewrite) == "1") {
    write_text(path.string(), png);
    GTEST_SKIP() << "rewrote " << path;
  }
  ASSERT_TRUE(fs::exists(path)) << path << " is missing; UNTANGLE_REWRITE_RENDER_GOLDEN=1 writes it";
  const std::string golden = read_text(path.string());
  EXPECT_EQ(png.size(), golden.size());
  EXPECT_TRUE(png == golden) << "the picture differs from " << path
                             << "; if the change is intended, rewrite it with "
                                "UNTANGLE_REWRITE_RENDER_GOLDEN=1 and look at it";
}

// Every point of the contour lands on a red pixel, and every red pixel lies on the drawn line
// (within its radius of a projected segment).
TEST(Render, ContourPixelsLandWhereTheContourProjects) {
  const std::vector<Mesh> meshes = scenes::scene_meshes(scenes::sheet_through_sphere());
  const Intersections found = find_intersections(meshes);
  ASSERT_EQ(found.contours.size(), 1u);
  for (RenderView view : {RenderView::kFront, RenderView::kTop, RenderView::kLeft}) {
    const RenderCamera camera = fit_camera({&meshes}, view, 300, 240);
    RenderMarks marks;
    std::vector<std::array<double, 2>> projected;
    for (const Contour& c : found.contours) {
      marks.contours.push_back({c.polyline, c.closed});
      for (const Vec3& p : c.polyline) {
        const Vec3 d{p[0] - camera.centre[0], p[1] - camera.centre[1], p[2] - camera.centre[2]};
        const double x = (d[0] * camera.right[0] + d[1] * camera.right[1] + d[2] * camera.right[2]) /
                             camera.scale + camera.width / 2.0;
        const double y = camera.height / 2.0 -
                         (d[0] * camera.up[0] + d[1] * camera.up[1] + d[2] * camera.up[2]) / camera.scale;
        projected.push_back({x, y});
      }
    }
    const RgbImage image = render_meshes(meshes, camera, marks, 1);
    ASSERT_EQ(image.width, 300);
    ASSERT_EQ(image.height, 240);
    for (const auto& p : projected) {
      EXPECT_EQ(pixel(image, static_cast<int>(p[0]), static_cast<int>(p[1])), kRed)
          << to_string(view) << " at " << p[0] << ", " << p[1];
    }
    const double radius = 1.0 + 1.5;  // the line's radius at this size, and a pixel's diagonal
    std::size_t red = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        if (pixel(image, x, y) != kRed) continue;
        ++red;
        double nearest = 1e9;
        const std::size_t n = projected.size();
        for (std::size_t k = 0; k < n; ++k) {
          const auto& a = projected[k];
          const auto& b = projected[(k + 1) % n];  // the contour is closed
          const double dx = b[0] - a[0], dy = b[1] - a[1];
          const double len2 = dx * dx + dy * dy;
          double t = len2 > 0 ? ((x + 0.5 - a[0]) * dx + (y + 0.5 - a[1]) * dy) / len2 : 0.0;
          t = std::min(1.0, std::max(0.0, t));
          nearest = std::min(nearest, std::hypot(a[0] + t * dx - x - 0.5, a[1] + t * dy - y - 0.5));
        }
        EXPECT_LE(nearest, radius) << to_string(view) << ": red pixel " << x << ", " << y;
      }
    }
    EXPECT_GT(red, 100u) << to_string(view);
  }
}

TEST(Render, SameBytesAtOneAndTwoThreads) {
  const fs::path folder = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman";
  std::vector<Mesh> meshes = read_meshes((folder / "male_casualsuit04.obj").string(), Role::kMovable);
  for (Mesh& m : read_meshes((folder / "male_generic.obj").string(), Role::kObstacle))
    meshes.push_back(std::move(m));
  RenderOptions options;
  options.contours = true;
  options.inside = true;
  options.threads = 1;
  const std::string one = encode_png(render_scene(meshes, options));
  options.threads = 2;
  const std::string two = encode_png(render_scene(meshes, options));
  EXPECT_FALSE(one.empty());
  EXPECT_TRUE(one == two);

  // The time the issue asks about: a MakeHuman garment on its body at 800 x 800 (printed for the
  // log; speed is measured, never asserted).
  const RenderCamera camera = fit_camera({&meshes}, RenderView::kFront, 800, 800);
  for (int threads : {1, 2}) {
    const auto start = std::chrono::steady_clock::now();
    const RgbImage image = render_meshes(meshes, camera, {}, threads);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const auto png_start = std::chrono::steady_clock::now();
    const std::string png = encode_png(image);
    const double png_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - png_start).count();
    std::printf("render makehuman 800x800, %d thread(s): %.1f ms raster, %.1f ms PNG (%zu bytes)\n",
                threads, ms, png_ms, png.size());
  }
}

// A contour in a plane is seen whole from the view along that plane's normal.
TEST(Render, AutoViewShowsTheMostContourLength) {
  auto circle = [](int axis) {
    RenderPolyline line;
    line.closed = true;
    for (int k = 0; k < 16; ++k) {
      Vec3 p{0, 0, 0};
      p[(axis + 1) % 3] = std::cos(k * 0.3926990817);
      p[(axis + 2) % 3] = std::sin(k * 0.3926990817);
      line.points.push_back(p);
    }
    return line;
  };
  EXPECT_EQ(best_view({circle(2)}), RenderView::kFront);  // in z = 0
  EXPECT_EQ(best_view({circle(0)}), RenderView::kLeft);   // in x = 0
  EXPECT_EQ(best_view({circle(1)}), RenderView::kTop);    // in y = 0
  EXPECT_EQ(best_view({}), RenderView::kFront);
}

// The same camera for both states, each movable mesh its own colour, obstacles grey.
TEST(Render, ColoursAndSideBySide) {
  std::vector<Mesh> meshes = scenes::scene_meshes(scenes::sheet_through_sphere());
  meshes.insert(meshes.begin(), meshes.front());
  EXPECT_NE(mesh_colour(meshes, 0), mesh_colour(meshes, 1));
  EXPECT_NE(mesh_colour(meshes, 2), mesh_colour(meshes, 0));
  EXPECT_NE(mesh_colour(meshes, 0), kRed);
  RgbImage a, b;
  a.width = 2;
  a.height = 1;
  a.pixels = {1, 1, 1, 2, 2, 2};
  b.width = 1;
  b.height = 2;
  b.pixels = {3, 3, 3, 4, 4, 4};
  const RgbImage both = side_by_side(a, b);
  EXPECT_EQ(both.width, 3);
  EXPECT_EQ(both.height, 2);
  EXPECT_EQ(pixel(both, 2, 1), (std::array<std::uint8_t, 3>{4, 4, 4}));
  EXPECT_EQ(pixel(both, 0, 1), (std::array<std::uint8_t, 3>{255, 255, 255}));
}

std::size_t line_count(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

TEST(RenderCli, WritesAPngAndTheSameBytesAtAnyThreadCount) {
  TempDir dir;
  const testing::SceneFiles files = testing::write_scene(scenes::sheet_through_sphere(), dir);
  const std::string one = dir.file("one.png"), two = dir.file("two.png");
  const auto r1 = run_cli("render" + files.inputs_args() + " -o " + quote(one) +
                          " --contours --inside --size 200x150 --threads 1");
  ASSERT_EQ(r1.exit_code, 0) << r1.err;
  EXPECT_NE(r1.out.find("wrote " + one), std::string::npos) << r1.out;
  const auto r2 = run_cli("render" + files.inputs_args() + " -o " + quote(two) +
                          " --contours --inside --size 200x150 --threads 2");
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  const std::string a = read_text(one), b = read_text(two);
  ASSERT_GT(a.size(), 8u);
  EXPECT_EQ(a.substr(1, 3), "PNG");
  EXPECT_TRUE(a == b);
  // Width and height, big-endian in the IHDR chunk.
  auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(a[at]) << 24) | (static_cast<unsigned char>(a[at + 1]) << 16) |
           (static_cast<unsigned char>(a[at + 2]) << 8) | static_cast<unsigned char>(a[at + 3]);
  };
  EXPECT_EQ(be32(16), 200);
  EXPECT_EQ(be32(20), 150);
}

// The legend names files without their folder: the same scene in two folders, the same bytes.
TEST(RenderCli, SamePictureWhereverTheFilesLie) {
  TempDir a, b;
  const testing::SceneFiles in_a = testing::write_scene(scenes::sheet_through_sphere(), a);
  fs::create_directories(b.path() / "deeper" / "folder");
  const testing::SceneFiles in_b =
      testing::write_scene(scenes::sheet_through_sphere(), (b.path() / "deeper" / "folder").string());
  const auto ra = run_cli("render" + in_a.inputs_args() + " -o " + quote(a.file("x.png")) + " --size 120x90");
  const auto rb = run_cli("render" + in_b.inputs_args() + " -o " + quote(b.file("x.png")) + " --size 120x90");
  ASSERT_EQ(ra.exit_code, 0) << ra.err;
  ASSERT_EQ(rb.exit_code, 0) << rb.err;
  EXPECT_TRUE(read_text(a.file("x.png")) == read_text(b.file("x.png")));
}

TEST(RenderCli, BadInputGivesExitThreeAndOneLineNamingTheFile) {
  TempDir dir;
  const std::string bad = dir.file("broken.obj");
  write_text(bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n");
  for (const std::string& args : {quote(bad), quote(dir.file("missing.obj"))}) {
    const auto r = run_cli("render " + args + " -o " + quote(dir.file("out.png")));
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_EQ(r.err.rfind("error: " + args.substr(1, args.size() - 2), 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists(dir.file("out.png")));
  }
}

TEST(RenderCli, RefusesInputsExistingFilesAndBadOptions) {
  TempDir dir;
  const testing::SceneFiles files = testing::write_scene(scenes::sheet_through_sphere(), dir);
  const std::string out = dir.file("out.png");
  write_text(out, "keep");
  auto r = run_cli("render" + files.inputs_args() + " -o " + quote(out));
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("--overwrite"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(out), "keep");
  r = run_cli("render" + files.inputs_args() + " -o " + quote(out) + " --overwrite -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(read_text(out), "keep");
  r = run_cli("render" + files.inputs_args() + " -o " + quote(files.movable[0]) + " --overwrite");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  r = run_cli("render" + files.inputs_args() + " -o " + quote(dir.file("out.jpg")));
  EXPECT_EQ(r.exit_code, 4) << r.err;
  r = run_cli("render" + files.inputs_args() + " -o " + quote(dir.file("a.png")) + " --size 10x10");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  r = run_cli("render" + files.inputs_args() + " -o " + quote(dir.file("a.png")) + " --view side");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_FALSE(fs::exists(dir.file("a.png")));
  for (const auto& entry : fs::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().filename().string().find(".untangle-tmp"), std::string::npos);
}

TEST(RenderCli, FixPreviewWritesBeforeAfterAndHeat) {
  TempDir dir;
  const testing::SceneFiles files = testing::write_scene(scenes::sheet_through_sphere(), dir);
  const fs::path previews = dir.path() / "previews";
  fs::create_directory(previews);
  const auto r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("fixed.obj")) +
                         " --preview " + quote(previews.string()) + " --threads 2");
  ASSERT_TRUE(testing::intersection_free(r.exit_code)) << r.err;
  const fs::path png = previews / "movable_0_before_after.png";
  ASSERT_TRUE(fs::exists(png));
  const std::string bytes = read_text(png.string());
  auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(bytes[at]) << 24) |
           (static_cast<unsigned char>(bytes[at + 1]) << 16) |
           (static_cast<unsigned char>(bytes[at + 2]) << 8) | static_cast<unsigned char>(bytes[at + 3]);
  };
  EXPECT_EQ(be32(16), 3 * RenderOptions{}.width);  // before | after | displacement
  EXPECT_EQ(be32(20), RenderOptions{}.height);
  // The same bytes with one thread.
  const fs::path single = dir.path() / "single";
  fs::create_directory(single);
  const auto r1 = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("fixed1.obj")) +
                          " --preview " + quote(single.string()) + " --threads 1");
  ASSERT_EQ(r1.exit_code, r.exit_code) << r1.err;
  EXPECT_TRUE(read_text((single / "movable_0_before_after.png").string()) == bytes);
  // A second run refuses the existing preview before any work.
  const auto again = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("fixed2.obj")) +
                             " --preview " + quote(previews.string()));
  EXPECT_EQ(again.exit_code, 4) << again.err;
  EXPECT_FALSE(fs::exists(dir.file("fixed2.obj")));
  const auto missing = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("fixed3.obj")) +
                               " --preview " + quote(dir.file("nowhere")));
  EXPECT_EQ(missing.exit_code, 4) << missing.err;
}

// The illegal region of the sheet through the sphere is the disc inside the sphere: the vertices
// `render --inside` tints amber are those nearer the sphere's centre than its radius, judged here
// from the sphere's own vertices.
TEST(Render, IllegalRegionIsTheSheetInsideTheSphere) {
  const std::vector<Mesh> meshes = scenes::scene_meshes(scenes::sheet_through_sphere());
  ASSERT_EQ(meshes.size(), 2u);
  const Mesh& sheet = meshes[0];
  const Mesh& sphere = meshes[1];
  ASSERT_EQ(sphere.role, Role::kObstacle);
  Vec3 centre{0.0, 0.0, 0.0};
  for (const Vec3& p : sphere.positions)
    for (int a = 0; a < 3; ++a) centre[a] += p[a] / static_cast<double>(sphere.positions.size());
  double radius = 0.0;
  for (const Vec3& p : sphere.positions) radius += norm(sub(p, centre)) / sphere.positions.size();
  const auto illegal = illegal_vertices(meshes, true, 2);
  ASSERT_EQ(illegal.size(), 2u);
  std::size_t inside = 0;
  for (std::size_t v = 0; v < sheet.positions.size(); ++v) {
    const double d = norm(sub(sheet.positions[v], centre));
    if (d < 0.95 * radius) {
      EXPECT_EQ(illegal[0][v], 1) << "vertex " << v << " inside the sphere";
      ++inside;
    }
    if (d > 1.05 * radius) {
      EXPECT_EQ(illegal[0][v], 0) << "vertex " << v << " outside the sphere";
    }
  }
  EXPECT_GT(inside, 10u);
  for (std::uint8_t f : illegal[1]) EXPECT_EQ(f, 0);  // obstacles are never illegal

  // Drawn: amber pixels (red high, blue low) appear only with --inside. (Inside the sphere the
  // disc is hidden: a strip through a sheet shows its illegal side.)
  const std::vector<Mesh> strip = scenes::scene_meshes(scenes::strip_through_sheet());
  RenderOptions options;
  options.width = 240;
  options.height = 240;
  options.legend = false;
  options.view = RenderView::kTop;  // the strip's illegal end stands above the sheet
  auto amber = [&](bool tint) {
    options.inside = tint;
    const RgbImage image = render_scene(strip, options, nullptr);
    std::size_t n = 0;
    for (std::size_t i = 0; i + 2 < image.pixels.size(); i += 3) {
      const int r = image.pixels[i], g = image.pixels[i + 1], b = image.pixels[i + 2];
      if (r > 120 && r > g + 20 && g > b + 40) ++n;
    }
    return n;
  };
  EXPECT_EQ(amber(false), 0u);
  EXPECT_GT(amber(true), 100u);
}

}  // namespace
}  // namespace untangle

