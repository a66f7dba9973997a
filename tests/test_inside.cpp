// Inside by generalized winding number (issue 20, DESIGN §4): movable vertices inside an
// obstacle are illegal, closed or open obstacle alike, even where nothing crosses. Judged
// independently of untangle by a signed ray cast (the sum of +1 exits and -1 entries along a ray,
// which is the winding number of a closed mesh) and CGAL's Side_of_triangle_mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <string>
#include <cstdlib>
#include <cstdio>
#include <utility>
#include <vector>

#include "cgal_reference.h"
#include "detect/detect_crossings.h"
#include "geometry/vec3.h"
#include "resolve/inside_vertices.h"
#include "scenes/random_tangles.h"
#include "scenes/scenes.h"
#include "scenes/self_scenes.h"
#include "topology/scene_topology.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"
#include "untangle/read_meshes.h"

namespace untangle {
namespace {


// The winding number of a closed mesh at p by a ray: +1 for each face the ray leaves through
// (outward normal along the ray), -1 for each it enters through (Moller-Trumbore).
int ray_winding(const Mesh& mesh, const Vec3& p) {
  const Vec3 d{0.8731, 0.3217, 0.2411};  // no special direction of the generated meshes
  int w = 0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3& a = mesh.positions[t[0]];
    const Vec3 e1 = sub(mesh.positions[t[1]], a), e2 = sub(mesh.positions[t[2]], a);
    const Vec3 q = cross(d, e2);
    const double det = dot(e1, q);
    if (det == 0.0) continue;
    const Vec3 s = sub(p, a);
    const double u = dot(s, q) / det;
    if (u < 0.0 || u > 1.0) continue;
    const Vec3 r = cross(s, e1);
    const double v = dot(d, r) / det;
    if (v < 0.0 || u + v > 1.0) continue;
    if (dot(e2, r) / det <= 0.0) continue;
    w += dot(cross(e1, e2), d) > 0.0 ? 1 : -1;
  }
  return w;
}

std::size_t ray_inside(const Mesh& movable, const Mesh& closed_body) {
  std::size_t n = 0;
  for (const Vec3& p : movable.positions) n += ray_winding(closed_body, p) > 0 ? 1 : 0;
  return n;
}

// `mesh` without the triangles whose centroid lies within `radius` of one of `centres` (holes).
Mesh with_holes(Mesh mesh, const std::vector<Vec3>& centres, double radius) {
  std::vector<Triangle> kept;
  for (const Triangle& t : mesh.triangles) {
    Vec3 c{0, 0, 0};
    for (std::uint32_t v : t)
      for (int k = 0; k < 3; ++k) c[k] += mesh.positions[v][k] / 3.0;
    bool drop = false;
    for (const Vec3& h : centres) drop = drop || std::sqrt(dot(sub(c, h), sub(c, h))) < radius;
    if (!drop) kept.push_back(t);
  }
  mesh.triangles = kept;
  mesh.polygon.resize(kept.size());
  for (std::uint32_t t = 0; t < kept.size(); ++t) mesh.polygon[t] = t;
  mesh.source_faces = kept.size();
  return mesh;
}

// The winding number agrees with the ray cast and with CGAL on the vertices of a sheet sweeping
// through a closed sphere and a closed capsule, and with the ray cast on a self-intersecting
// body where two capsules overlap (winding 2 there; parity would call it outside).
TEST(Inside, WindingNumberAgreesWithRayCastAndCgal) {
  const Mesh sheet =
      scenes::grid_sheet(41, 41, {-1.5013, -1.4987, 0.0137}, {3.0, 0, 0}, {0, 3.0, 0}, "sheet");
  std::vector<Mesh> bodies;
  bodies.push_back(scenes::uv_sphere({0.0, 0.0, 0.0}, 1.0, 48, 24, "sphere"));
  bodies.push_back(scenes::capsule({0.1, 0.0, 0.0}, 0.6, 1.5, 32, 6, "capsule"));
  bodies.push_back(scenes::self_intersecting_obstacle(32));
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    Mesh body = bodies[b];
    body.role = Role::kObstacle;
    const Intersections found = find_intersections({sheet, body});
    const std::size_t by_ray = ray_inside(sheet, body);
    EXPECT_GT(by_ray, 100u) << body.name;
    EXPECT_EQ(found.counts.inside_vertices, by_ray) << body.name;
    ASSERT_EQ(found.counts.inside_by_mesh.size(), 2u);
    EXPECT_EQ(found.counts.inside_by_mesh[0], by_ray);
    EXPECT_EQ(found.counts.inside_by_mesh[1], 0u);
    if (b < 2) {
      EXPECT_EQ(cgal_reference::inside_count(sheet, body), by_ray) << body.name;
    }
  }
}

// Obstacles are left out among themselves (the self-intersecting body crosses itself).
Intersections detect(const std::vector<Mesh>& meshes) {
  DetectOptions options;
  options.skip_obstacle_pairs = true;
  return find_intersections(meshes, options);
}

// An obstacle stored inside out (every face wound the other way) has the same inside, and the
// count is the same at any thread count.
TEST(Inside, InsideOutObstacleIsReadTurned) {
  const Mesh sheet =
      scenes::grid_sheet(41, 41, {-1.5013, -1.4987, 0.0137}, {3.0, 0, 0}, {0, 3.0, 0}, "sheet");
  Mesh body = scenes::uv_sphere({0.0, 0.0, 0.0}, 1.0, 48, 24, "sphere");
  body.role = Role::kObstacle;
  Mesh flipped = body;
  for (Triangle& t : flipped.triangles) std::swap(t[1], t[2]);
  DetectOptions one;
  one.threads = 1;
  const std::size_t expected = ray_inside(sheet, body);
  EXPECT_GT(expected, 100u);
  EXPECT_EQ(find_intersections({sheet, body}, one).counts.inside_vertices, expected);
  DetectOptions two;
  two.threads = 2;
  EXPECT_EQ(find_intersections({sheet, flipped}, two).counts.inside_vertices, expected);
}

// Required of every repair here: the result detected again has no crossing, no vertex inside by
// winding number, and none inside by the independent check on `closed_body`.
void expect_clean(const FixResult& result, const std::vector<Mesh>& meshes,
                  const Mesh& closed_body) {
  EXPECT_TRUE(result.clean);
  EXPECT_EQ(result.after.inside_vertices, 0u);
  const Intersections again = detect(meshes);
  EXPECT_EQ(again.counts.crossings, 0u);
  EXPECT_EQ(again.counts.inside_vertices, 0u);
  EXPECT_EQ(ray_inside(meshes[0], closed_body), 0u);
}

// A sheet sunk wholly under the surface of a closed body: no crossing at all, so detection alone
// calls it clean; every vertex is inside. The repair brings it out.
TEST(Inside, GarmentWhollyInsideClosedBody) {
  std::vector<Mesh> meshes;
  meshes.push_back(
      scenes::grid_sheet(13, 13, {-0.3013, -0.2987, 0.8}, {0.6, 0, 0}, {0, 0.6, 0}, "sheet"));
  meshes.push_back(scenes::uv_sphere({0.0, 0.0, 0.0}, 1.0, 48, 24, "body"));
  meshes[1].role = Role::kObstacle;
  const Mesh body = meshes[1];
  const Intersections before = detect(meshes);
  EXPECT_EQ(before.counts.crossings, 0u);
  EXPECT_EQ(before.counts.inside_vertices, meshes[0].positions.size());
  EXPECT_EQ(cgal_reference::inside_count(meshes[0], body), meshes[0].positions.size());

  const FixResult result = fix_meshes(meshes, FixOptions{});
  EXPECT_EQ(result.before.inside_vertices, meshes[0].positions.size());
  expect_clean(result, meshes, body);
  EXPECT_EQ(cgal_reference::inside_count(meshes[0], body), 0u);
}

// The panel mostly inside a body (panel_in_body), the body open: a hole cut at its bottom pole, so
// the
// inside rule of closed obstacles does not apply and "the smaller side is illegal" would push the
// panel's corners in. The winding number still says where inside is.
TEST(Inside, PanelThroughOpenBody) {
  const scenes::Scene scene = scenes::panel_in_body();
  std::vector<Mesh> meshes = scenes::scene_meshes(scene);
  const Mesh closed_body = meshes[1];
  meshes[1] = with_holes(meshes[1], {{0.0, 0.0, -1.0}}, 0.15);
  ASSERT_LT(meshes[1].triangles.size(), closed_body.triangles.size());
  const Intersections before = detect(meshes);
  EXPECT_GT(before.counts.crossings, 0u);
  EXPECT_GT(before.counts.inside_vertices, meshes[0].positions.size() / 2);
  EXPECT_EQ(before.counts.inside_vertices, ray_inside(meshes[0], closed_body));

  const FixResult result = fix_meshes(meshes, FixOptions{});
  expect_clean(result, meshes, closed_body);
  EXPECT_GT(result.illegal_regions_by_inside, 0u);
}

// A sheet through a body that passes through itself (two capsules overlapping as one mesh).
TEST(Inside, SheetThroughSelfIntersectingBody) {
  std::vector<Mesh> meshes;
  meshes.push_back(
      scenes::grid_sheet(33, 33, {-1.6137, -1.5929, 0.3637}, {3.2, 0, 0}, {0, 3.2, 0}, "sheet"));
  meshes.push_back(scenes::self_intersecting_obstacle(24));
  meshes[1].role = Role::kObstacle;
  const Mesh body = meshes[1];
  const Intersections before = detect(meshes);
  EXPECT_GT(before.counts.crossings, 0u);
  EXPECT_EQ(before.counts.inside_vertices, ray_inside(meshes[0], body));

  const FixResult result = fix_meshes(meshes, FixOptions{});
  expect_clean(result, meshes, body);
}

// A figure of capsules: a torso (z up), two legs overlapping the torso and each other at the
// crotch, two arms overlapping the torso at the shoulders. Irrational-looking offsets keep the
// capsules' vertices off each other's faces.
std::vector<Mesh> figure_parts() {
  std::vector<Mesh> parts;
  parts.push_back(scenes::capsule({0.0013, -0.0021, 0.0}, 0.5, 1.2, 40, 13, "torso"));
  parts.push_back(scenes::capsule({0.1837, 0.0031, -1.2}, 0.2, 1.0, 24, 11, "left_leg"));
  parts.push_back(scenes::capsule({-0.1849, -0.0027, -1.2}, 0.2, 1.0, 24, 11, "right_leg"));
  // Arms along x at shoulder height, from inside the torso outwards.
  parts.push_back(scenes::rotated(scenes::capsule({0, 0, 0}, 0.14, 0.9, 20, 9, "left_arm"), 1,
                                  0.5 * 3.14159265358979, {0.7013, 0.0041, 0.46}));
  parts.push_back(scenes::rotated(scenes::capsule({0, 0, 0}, 0.14, 0.9, 20, 9, "right_arm"), 1,
                                  0.5 * 3.14159265358979, {-0.7029, -0.0037, 0.46}));
  return parts;
}

// A shirt (an open tube around the torso, shifted so that one side sinks into it) and a skirt (an
// open tube around the hips, narrower than the legs are apart: the legs pass through it).
std::vector<Mesh> shirt_and_skirt() {
  std::vector<Mesh> garments;
  garments.push_back(scenes::open_tube({0.0537, 0.0113, -0.05}, 0.52, 0.7, 48, 15, "shirt"));
  garments.push_back(scenes::open_tube({0.0021, 0.0017, -1.02}, 0.37, 0.36, 48, 9, "skirt"));
  return garments;
}

// The winding number of the closed figure (the parts' sum) at p, by the ray cast.
int figure_winding(const std::vector<Mesh>& parts, const Vec3& p) {
  int w = 0;
  for (const Mesh& part : parts) w += ray_winding(part, p);
  return w;
}

std::size_t inside_figure(const Mesh& garment, const std::vector<Mesh>& parts) {
  std::size_t n = 0;
  for (const Vec3& p : garment.positions) n += figure_winding(parts, p) > 0 ? 1 : 0;
  return n;
}

// Prints a scene's figures (never asserted), and with UNTANGLE_INSIDE_KEEP=DIR writes the meshes
// before and after into DIR (NAME_<mesh>_before.obj, NAME_<mesh>_after.obj) for a look.
void report_figure_scene(const std::string& name, const std::vector<Mesh>& input,
                         const std::vector<Mesh>& output, const FixResult& result) {
  std::printf("[ %s ] before: %zu crossings, %zu inside; after %d iterations: %zu crossings, %zu "
              "inside; moved %zu vertices, max %.3f mean edges\n",
              name.c_str(), result.before.crossings, result.before.inside_vertices,
              result.iterations, result.after.crossings, result.after.inside_vertices,
              result.displacement.moved_vertices, result.displacement.max_over_mean_edge);
  const std::vector<QualityStats> quality = measure_quality(input, output);
  for (std::size_t m = 0; m < output.size(); ++m)
    if (output[m].role == Role::kMovable)
      std::printf("[ %s ] %s: largest edge-length ratio %.3f, p95 change %.4f, %zu flipped\n",
                  name.c_str(), output[m].name.c_str(), quality[m].max_stretch,
                  quality[m].edge_change_p95, quality[m].flipped_faces);
  const char* keep = std::getenv("UNTANGLE_INSIDE_KEEP");
  if (keep == nullptr || *keep == '\0') return;
  for (std::size_t m = 0; m < output.size(); ++m) {
    const std::string stem = std::string(keep) + "/" + name + "_" + output[m].name;
    scenes::write_obj(input[m], stem + "_before.obj");
    scenes::write_obj(output[m], stem + "_after.obj");
  }
}

// Issue 20's open body: one mesh that passes through itself where the limbs meet the torso and
// the legs each other, open at a neck hole, an eye hole and a hole under one foot, with a shirt
// and a skirt on it. The winding number says where inside is despite the holes and the overlaps;
// the repair ends with no crossing and no garment vertex inside, judged again by the ray cast on
// the closed parts.
TEST(Inside, ShirtAndSkirtOnOpenSelfIntersectingBody) {
  const std::vector<Mesh> parts = figure_parts();
  Mesh body = parts[0];
  for (std::size_t i = 1; i < parts.size(); ++i) body = scenes::merged(body, parts[i], "body");
  body = with_holes(body, {{0.0013, -0.0021, 1.1}, {0.17, 0.47, 0.75}, {0.1837, 0.0031, -1.9}},
                    0.09);
  body.role = Role::kObstacle;
  std::vector<Mesh> meshes = shirt_and_skirt();
  meshes.push_back(body);
  const Intersections before = detect(meshes);
  ASSERT_GT(before.counts.crossings, 0u);
  EXPECT_EQ(before.counts.inside_vertices,
            inside_figure(meshes[0], parts) + inside_figure(meshes[1], parts));
  EXPECT_GT(inside_figure(meshes[0], parts), 0u);
  EXPECT_GT(inside_figure(meshes[1], parts), 0u);

  const std::vector<Mesh> input = meshes;
  const FixResult result = fix_meshes(meshes, FixOptions{});
  report_figure_scene("open_body", input, meshes, result);
  EXPECT_TRUE(result.clean);
  const Intersections again = detect(meshes);
  EXPECT_EQ(again.counts.crossings, 0u);
  EXPECT_EQ(again.counts.inside_vertices, 0u);
  EXPECT_EQ(inside_figure(meshes[0], parts), 0u);
  EXPECT_EQ(inside_figure(meshes[1], parts), 0u);
  const std::vector<QualityStats> quality = measure_quality(input, meshes);
  for (std::size_t m = 0; m < 2; ++m) {
    EXPECT_EQ(quality[m].flipped_faces, 0u) << meshes[m].name;
    EXPECT_LE(quality[m].max_stretch, QualityBounds{}.max_stretch) << meshes[m].name;
  }
}

// Issue 20's articulated figure: the same parts as separate closed meshes (rigid segments that
// overlap at the joints), a shirt over the torso segment. Each segment is its own obstacle.
TEST(Inside, ShirtOnArticulatedFigure) {
  const std::vector<Mesh> parts = figure_parts();
  std::vector<Mesh> meshes = {shirt_and_skirt()[0]};
  for (Mesh part : parts) {
    part.role = Role::kObstacle;
    meshes.push_back(part);
  }
  const Intersections before = detect(meshes);
  ASSERT_GT(before.counts.crossings, 0u);
  EXPECT_EQ(before.counts.inside_vertices, inside_figure(meshes[0], parts));
  EXPECT_GT(before.counts.inside_vertices, 0u);

  const std::vector<Mesh> input = meshes;
  const FixResult result = fix_meshes(meshes, FixOptions{});
  report_figure_scene("articulated", input, meshes, result);
  EXPECT_TRUE(result.clean);
  const Intersections again = detect(meshes);
  EXPECT_EQ(again.counts.crossings, 0u);
  EXPECT_EQ(again.counts.inside_vertices, 0u);
  EXPECT_EQ(inside_figure(meshes[0], parts), 0u);
  const QualityStats quality = measure_quality(input, meshes)[0];
  EXPECT_EQ(quality.flipped_faces, 0u);
  EXPECT_LE(quality.max_stretch, QualityBounds{}.max_stretch);
}

// How the inside test by parts (one winding number per part of the movable meshes cut by the
// crossings and by the holes' reach) compares with the winding number at every vertex.
struct PartsAgreement {
  std::size_t compared = 0;  // movable vertices whose own winding numbers are clear
  std::size_t unclear = 0;   // movable vertices on or at rounding distance from a surface
  std::size_t inside = 0;    // by parts
  std::size_t disagree = 0;  // among the compared
  std::size_t holes = 0;
};

PartsAgreement compare_parts(const std::vector<Mesh>& meshes, int threads = 1) {
  const SceneTopology topo = build_topology(meshes);
  std::vector<Role> role;
  DetectSettings settings;
  settings.threads = threads;
  for (const Mesh& m : meshes) {
    role.push_back(m.role);
    settings.skip_among.push_back(m.role == Role::kObstacle);
  }
  const ObstacleWinding winding(topo, role, threads);
  const CrossingSet set = detect_crossings(topo, settings);
  std::vector<std::uint32_t> by_parts;
  find_inside_by_parts(topo, role, winding, set, threads, by_parts);
  PartsAgreement a;
  a.holes = winding.holes().size();
  for (std::uint32_t v = 0; v < topo.points.size(); ++v) {
    if (role[topo.vertex_mesh[v]] != Role::kMovable) {
      EXPECT_EQ(by_parts[v], kNone);
      continue;
    }
    a.inside += by_parts[v] != kNone ? 1 : 0;
    std::uint32_t own = kNone;
    if (!winding.inside_clearly(topo.points[v], own)) {
      ++a.unclear;
      continue;
    }
    ++a.compared;
    a.disagree += own != by_parts[v] ? 1 : 0;
  }
  return a;
}

// Where a vertex's own winding numbers are clear, the part it belongs to gives the same answer:
// on every named scene, the cow, the shipped MakeHuman pair as given and with the body grown by
// 5% (hundreds of garment vertices inside), a sphere with holes cut where sheets pass (the
// holes' reach), and 300 random tangles (half of them snapped to a grid: vertices lying exactly
// on an obstacle's face are not clear and take their part's answer, which the crossings decide).
TEST(Inside, PartsAgreeWithEveryClearVertex) {
  std::vector<std::pair<std::string, std::vector<Mesh>>> cases;
  for (const scenes::Scene& s : scenes::named_scenes()) cases.push_back({s.name, scenes::scene_meshes(s)});
  cases.push_back({"cow", scenes::scene_meshes(scenes::sheet_through_cow(61))});
  const std::string mh = std::string(UNTANGLE_SOURCE_DIR) + "/testdata/makehuman/";
  std::vector<Mesh> pair = read_meshes(mh + "male_casualsuit04.obj", Role::kMovable);
  pair.push_back(read_meshes(mh + "male_generic.obj", Role::kObstacle).at(0));
  cases.push_back({"makehuman", pair});
  pair[1] = scenes::scaled_about_centre({pair[1]}, 1.05).at(0);
  pair[1].role = Role::kObstacle;
  cases.push_back({"makehuman x1.05", pair});
  {
    // Two holes of radius 0.3 in a unit sphere (at the poles), a sheet through the sphere just
    // below the upper one, one through its middle, and a strip through the lower hole.
    Mesh sphere = with_holes(scenes::uv_sphere({0, 0, 0}, 1.0, 48, 24, "sphere"),
                             {{0, 0, 1.0}, {0, 0, -1.0}}, 0.3);
    sphere.role = Role::kObstacle;
    std::vector<Mesh> holed{
        scenes::grid_sheet(31, 31, {-1.2013, -1.1987, 0.8137}, {2.4, 0, 0}, {0, 2.4, 0}, "high"),
        scenes::grid_sheet(31, 31, {-1.2013, -1.1987, 0.0137}, {2.4, 0, 0}, {0, 2.4, 0}, "middle"),
        scenes::grid_sheet(5, 31, {-0.1013, 0.0013, -1.5013}, {0.2, 0, 0}, {0, 0, 1.0}, "strip"),
        sphere};
    cases.push_back({"holed sphere", holed});
  }
  std::size_t with_holes_seen = 0, unclear = 0;
  for (const auto& [name, meshes] : cases) {
    const PartsAgreement a = compare_parts(meshes);
    EXPECT_EQ(a.disagree, 0u) << name;
    EXPECT_GT(a.compared, 0u) << name;
    with_holes_seen += a.holes;
    if (name == "makehuman x1.05" || name == "cow" || name == "holed sphere") {
      EXPECT_GT(a.inside, 100u) << name;
    }
  }
  EXPECT_EQ(with_holes_seen, 2u);
  for (std::uint64_t seed = 0; seed < 300; ++seed) {
    const scenes::RandomTangle t = scenes::random_tangle(seed);
    const PartsAgreement a = compare_parts(scenes::scene_meshes(t.scene), seed % 2 ? 2 : 1);
    EXPECT_EQ(a.disagree, 0u) << t.description;
    unclear += a.unclear;
  }
  EXPECT_GT(unclear, 0u);  // the snapped tangles put vertices on faces
}

}  // namespace
}  // namespace untangle
