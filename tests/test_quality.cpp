// The judge's quality side: the shape relaxation after a clean repair, the bounds that turn a
// clean but distorted result into `distorted` (exit 6), and faces the reader skips with a warning.
// Every figure is measured here on the files written, by code of the test's own (edges welded by
// position, normals by cross product), and crossings by CGAL.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <CGAL/box_intersection_d.h>
#include <nlohmann/json.hpp>

#include "cgal_reference.h"
#include "test_support.h"
#include "untangle/read_meshes.h"

namespace untangle {
namespace {

using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;
using testing::write_text;
namespace fs = std::filesystem;

const fs::path kMakeHuman = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman";

// Edge-length ratios (after / before, over edges welded by input position) and flipped faces of
// `after` against `before`: the same mesh with moved positions.
struct Shape {
  std::vector<double> change;  // |ratio - 1|, ascending
  double stretch = 1.0;        // max of ratio and 1 / ratio
  std::size_t flipped = 0;
};

Shape shape_change(const Mesh& before, const Mesh& after) {
  std::map<Vec3, std::uint32_t> id;
  std::vector<std::uint32_t> rep;  // welded id -> first vertex
  std::vector<std::uint32_t> weld(before.positions.size());
  for (std::uint32_t i = 0; i < before.positions.size(); ++i) {
    auto [it, fresh] = id.emplace(before.positions[i], static_cast<std::uint32_t>(rep.size()));
    if (fresh) rep.push_back(i);
    weld[i] = it->second;
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  Shape s;
  auto length = [](const Vec3& a, const Vec3& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                     (a[2] - b[2]) * (a[2] - b[2]));
  };
  for (const Triangle& t : before.triangles) {
    for (int k = 0; k < 3; ++k) {
      std::uint32_t a = weld[t[k]], b = weld[t[(k + 1) % 3]];
      if (a == b) continue;
      edges[{std::min(a, b), std::max(a, b)}] = 1;
    }
    auto normal = [&](const Mesh& m) {
      const Vec3 &p = m.positions[t[0]], &q = m.positions[t[1]], &r = m.positions[t[2]];
      const Vec3 u{q[0] - p[0], q[1] - p[1], q[2] - p[2]}, v{r[0] - p[0], r[1] - p[1], r[2] - p[2]};
      return Vec3{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    };
    const Vec3 n0 = normal(before), n1 = normal(after);
    if (n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2] < 0.0) ++s.flipped;
  }
  for (const auto& [e, unused] : edges) {
    const double l0 = length(before.positions[rep[e.first]], before.positions[rep[e.second]]);
    const double l1 = length(after.positions[rep[e.first]], after.positions[rep[e.second]]);
    if (l0 <= 0.0) continue;
    const double ratio = l1 / l0;
    s.change.push_back(std::abs(ratio - 1.0));
    s.stretch = std::max(s.stretch, ratio > 0.0 ? std::max(ratio, 1.0 / ratio) : INFINITY);
  }
  std::sort(s.change.begin(), s.change.end());
  return s;
}

double p95(const Shape& s) {
  const std::size_t rank = (95 * s.change.size() + 99) / 100;
  return s.change[std::max<std::size_t>(rank, 1) - 1];
}

// Triangle pairs CGAL finds between the garment and the body or within the garment.
std::size_t garment_pairs(const Mesh& garment, const Mesh& body) {
  std::size_t n = 0;
  for (const auto& p : cgal_reference::triangle_pairs(std::vector<Mesh>{garment, body}))
    if (p[0] == 0 || p[2] == 0) ++n;
  return n;
}

struct Fixed {
  int exit_code = -1;
  nlohmann::json report;
  Mesh input, output, body;
};

Fixed fix_shipped_pair(const TempDir& dir, const std::string& extra,
                       const std::string& body = (kMakeHuman / "male_generic.obj").string()) {
  const std::string garment = (kMakeHuman / "male_casualsuit04.obj").string();
  const std::string out = dir.file("fixed.obj"), report = dir.file("fixed.json");
  const testing::RunResult r = run_cli("fix " + quote(garment) + " --obstacle " + quote(body) +
                                       " -o " + quote(out) + " --report " + quote(report) +
                                       " -q " + extra);
  Fixed f;
  f.exit_code = r.exit_code;
  if (!fs::exists(out)) return f;
  f.report = nlohmann::json::parse(read_text(report));
  f.input = read_meshes(garment, Role::kMovable).at(0);
  f.output = read_meshes(out, Role::kMovable).at(0);
  f.body = read_meshes(body, Role::kObstacle).at(0);
  return f;
}

TEST(Quality, ShippedPairEndsCleanWithinTheBounds) {
  TempDir dir;
  const Fixed f = fix_shipped_pair(dir, "");
  ASSERT_EQ(f.exit_code, 0) << f.report.dump(1);
  EXPECT_EQ(f.report["status"], "clean");
  EXPECT_TRUE(f.report["continuation"].is_null());  // clean within the bounds: not needed
  EXPECT_EQ(garment_pairs(f.output, f.body), 0u);
  const Shape s = shape_change(f.input, f.output);
  EXPECT_EQ(s.flipped, 0u);
  EXPECT_LE(p95(s), 0.05);
  EXPECT_LE(s.change.back(), 0.5);
  EXPECT_LE(s.stretch, 1.5);
  // The report says what the files say.
  const auto& q = f.report["quality"][0];
  EXPECT_NEAR(q["edge_change_max"].get<double>(), s.change.back(), 1e-9);
  EXPECT_NEAR(q["max_stretch"].get<double>(), s.stretch, 1e-9);
  EXPECT_EQ(q["flipped_faces"].get<std::size_t>(), s.flipped);
  EXPECT_TRUE(q["within_bounds"].get<bool>());
}

// The shipped body (or `source`) scaled by `factor` about its bounding box's centre, its `v` lines
// written with six decimals (as Blender's OBJ exporter writes them), every other line as it is.
std::string scaled_body_six_decimals(const TempDir& dir, double factor,
                                     const fs::path& source = kMakeHuman / "male_generic.obj") {
  const std::string text = read_text(source.string());
  const Mesh body = read_meshes(source.string(), Role::kObstacle).at(0);
  Vec3 lo = body.positions[0], hi = lo;
  for (const Vec3& p : body.positions)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  std::string out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    double x, y, z;
    if (line.rfind("v ", 0) == 0 && std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z) == 3) {
      const double p[3] = {x, y, z};
      char buffer[128];
      double q[3];
      for (int k = 0; k < 3; ++k) {
        const double centre = 0.5 * (lo[k] + hi[k]);
        q[k] = centre + factor * (p[k] - centre);
      }
      std::snprintf(buffer, sizeof buffer, "v %.6f %.6f %.6f", q[0], q[1], q[2]);
      out += buffer;
    } else {
      out += line;
    }
    out += '\n';
  }
  const std::string path = dir.file("body_scaled.obj");
  write_text(path, out);
  return path;
}

// `fix GARMENT --obstacle BODY -o OUT` with a report in `dir`: the report, or null (a failure
// here) when the run did not end free of crossings.
nlohmann::json fix_on_body(const TempDir& dir, const std::string& garment, const std::string& body,
                           const std::string& out) {
  const std::string report = dir.file("fixed.json");
  const testing::RunResult r = run_cli("fix " + quote(garment) + " --obstacle " + quote(body) +
                                       " -o " + quote(out) + " --report " + quote(report) + " -q");
  EXPECT_TRUE(testing::intersection_free(r.exit_code)) << read_text(report);
  if (!testing::intersection_free(r.exit_code)) return nullptr;
  return nlohmann::json::parse(read_text(report));
}

// The garment file `garment`, with more than `inside_before` vertices inside `body` (by CGAL),
// written as `out` with no crossing and nothing inside, judged by CGAL on the files.
void expect_freed(const std::string& garment, const std::string& out, const std::string& body,
                  std::size_t inside_before) {
  const Mesh input = read_meshes(garment, Role::kMovable).at(0);
  const Mesh output = read_meshes(out, Role::kMovable).at(0);
  const Mesh obstacle = read_meshes(body, Role::kObstacle).at(0);
  EXPECT_GT(cgal_reference::inside_count(input, obstacle), inside_before);
  EXPECT_EQ(garment_pairs(output, obstacle), 0u);
  EXPECT_EQ(cgal_reference::inside_count(output, obstacle), 0u);
}

// Issue 21's fragile case: a body a little larger, written with six decimals (what Blender's OBJ
// exporter writes), stalls the shipped garment at the default clearance; twice the clearance
// resolves it. fix retries by itself and says so; without retries the same run ends unresolved
// (both without the continuation, the default, which would run after them). Whatever the retry
// leaves, `fix` with the continuation ends within the bounds, judged here on the written file:
// the continuation runs exactly when the retry's result is beyond them. The body is
// 2% larger, the case (from 2026-12-05, when the region moves' ray points became the same
// in any unit, until the vertex order became free of half turns, 2026-12-06, that body was clean
// directly and 4% larger was the one that stalled).
TEST(Quality, UnresolvedRunIsRetriedWithALargerClearance) {
  TempDir dir;
  const std::string body = scaled_body_six_decimals(dir, 1.02);
  const Fixed once = fix_shipped_pair(dir, "--retries 0 --no-continuation", body);
  ASSERT_EQ(once.exit_code, 5) << once.report.dump(1);
  EXPECT_EQ(once.report["status"], "unresolved");
  EXPECT_TRUE(once.report["retries"].empty());
  // Its top and trousers (1,528 and 1,712 triangles) cross the body: no piece is moved whole (the
  // first version of that step slid the top forward off the torso and the trousers back).
  EXPECT_TRUE(once.report["piece_moves"].is_null());

  const Fixed f = fix_shipped_pair(dir, "--overwrite --no-continuation", body);
  ASSERT_TRUE(testing::intersection_free(f.exit_code)) << f.report.dump(1);
  EXPECT_EQ(garment_pairs(f.output, f.body), 0u);
  const auto& retries = f.report["retries"];
  ASSERT_FALSE(retries.empty());
  const auto& kept = retries.back();
  EXPECT_TRUE(kept["kept"].get<bool>());
  EXPECT_TRUE(kept["clean"].get<bool>());
  // Each retry doubles the clearance of the one before.
  EXPECT_DOUBLE_EQ(kept["clearance"].get<double>(),
                   std::ldexp(f.report["options"]["clearance"].get<double>(),
                              static_cast<int>(retries.size())));
  EXPECT_DOUBLE_EQ(f.report["clearance"].get<double>(), kept["clearance"].get<double>());
  EXPECT_EQ(f.report["before"]["crossings"], once.report["before"]["crossings"]);
  const bool retry_within = f.report["quality"][0]["within_bounds"].get<bool>();
  EXPECT_EQ(retry_within, f.exit_code == 0);

  const Fixed c = fix_shipped_pair(dir, "--overwrite", body);
  ASSERT_EQ(c.exit_code, 0) << c.report.dump(1);
  if (retry_within) {
    EXPECT_TRUE(c.report["continuation"].is_null());  // not needed: the same result
    EXPECT_EQ(c.report["quality"], f.report["quality"]);
  } else {
    EXPECT_TRUE(c.report["continuation"]["kept"].get<bool>());
    EXPECT_FALSE(c.report["retries"].back()["kept"].get<bool>());
  }
  EXPECT_EQ(garment_pairs(c.output, c.body), 0u);
  EXPECT_EQ(cgal_reference::inside_count(c.output, c.body), 0u);
  const Shape s = shape_change(c.input, c.output);
  EXPECT_EQ(s.flipped, 0u);
  EXPECT_LE(s.stretch, 1.5);
}

// Issue 21's deep penetration: the body 5% larger (six decimals) swallows the garment by up to 2.7
// cm; the direct repair pushes the garment out through the nearest surface and leaves it
// distorted. The continuation (the default) shrinks the body under the garment and grows it back
// in steps: clean, nothing inside, the shape kept. The test's own measures judge the written file.
TEST(Quality, DeepPenetrationIsReachedByTheContinuation) {
  TempDir dir;
  const std::string body = scaled_body_six_decimals(dir, 1.05);
  TempDir direct_dir;
  const Fixed direct = fix_shipped_pair(direct_dir, "--no-continuation", body);
  ASSERT_NE(direct.exit_code, -1);
  EXPECT_NE(direct.exit_code, 0) << "the direct repair reaches it: the test no longer tests";
  EXPECT_TRUE(direct.report["continuation"].is_null());
  EXPECT_FALSE(direct.report["options"]["continuation"].get<bool>());
  ASSERT_GT(cgal_reference::inside_count(direct.input, direct.body), 100u);

  const Fixed f = fix_shipped_pair(dir, "", body);
  ASSERT_EQ(f.exit_code, 0) << f.report.dump(1);
  EXPECT_TRUE(f.report["options"]["continuation"].get<bool>());
  EXPECT_EQ(f.report["status"], "clean");
  const auto& c = f.report["continuation"];
  ASSERT_TRUE(c.is_object());
  EXPECT_TRUE(c["kept"].get<bool>());
  EXPECT_TRUE(c["clean"].get<bool>());
  EXPECT_GT(c["deepest"].get<double>(), 0.1);  // decimetres: deeper than a quarter of an edge
  const auto& runs = c["runs"];
  ASSERT_GE(runs.size(), 2u);
  EXPECT_EQ(runs.front()["shrink"].get<double>(), 1.0);
  EXPECT_EQ(runs.back()["shrink"].get<double>(), 0.0);
  EXPECT_EQ(f.report["history"].back()["stage"], 4);
  // The written file: no crossing, nothing inside, the garment's shape kept.
  EXPECT_EQ(garment_pairs(f.output, f.body), 0u);
  EXPECT_EQ(cgal_reference::inside_count(f.output, f.body), 0u);
  const Shape s = shape_change(f.input, f.output);
  EXPECT_EQ(s.flipped, 0u);
  EXPECT_LE(p95(s), 0.05);
  EXPECT_LE(s.stretch, 1.5);
  const Shape d = shape_change(direct.input, direct.output);
  EXPECT_LT(s.stretch, d.stretch);
}

// Deeper: the body 8% larger about its centre moves each arm sideways out of its sleeve by more
// than the arm is thick. Shrunk along its normals the body cannot get out of male_casualsuit02
// (before the scaled continuation this run ended unresolved: the continuation gave up, and so did
// every retry); scaled down about its centre it can, and the scaled continuation grows it back in
// steps. What it writes is free of crossings with nothing inside, judged here on the file.
TEST(Quality, ArmsMovedOutOfTheirSleevesAreReachedByScalingTheBody) {
  TempDir dir;
  const std::string body = scaled_body_six_decimals(dir, 1.08);
  const std::string garment =
      (fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman_more" / "male_casualsuit02.obj")
          .string();
  const std::string out = dir.file("fixed.obj");
  const nlohmann::json j = fix_on_body(dir, garment, body, out);
  ASSERT_TRUE(j.is_object());
  const auto& normals = j["continuation"];
  ASSERT_TRUE(normals.is_object());
  EXPECT_FALSE(normals["kept"].get<bool>());
  ASSERT_TRUE(j["scaled_continuation"].is_object()) << j.dump(1);
  // One of the scaled continuations is kept: the factor of the least depth, or the second one,
  // of the fewest crossings (on this body written with six decimals the first gives up and the
  // second ends clean; on the body at full precision the first ends clean within the bounds).
  const auto& first = j["scaled_continuation"];
  const auto& scaled = first["kept"].get<bool>() ? first : j["second_scaled_continuation"];
  ASSERT_TRUE(scaled.is_object()) << j.dump(1);
  EXPECT_TRUE(scaled["kept"].get<bool>());
  EXPECT_TRUE(scaled["clean"].get<bool>());
  EXPECT_GT(scaled["factor"].get<double>(), 0.85);
  EXPECT_LT(scaled["factor"].get<double>(), 1.0);
  EXPECT_EQ(scaled["runs"].front()["shrink"].get<double>(), 1.0);
  EXPECT_EQ(scaled["runs"].back()["shrink"].get<double>(), 0.0);
  expect_freed(garment, out, body, 100);
}

// A garment that crosses its own body (female_casualsuit01: 3,611 crossings and 288 vertices
// inside at the body's own size; `fix` cleans that in a second) on that body 8% larger. Scaled
// down to the fewest crossings and inside vertices (0.842), the body's limbs stand inside the
// garment's walls, the first step stalls and the continuation gives up: before 2026-12-07 this run
// ended unresolved. The factor of the least depth inside (0.912; the body it was made on is at
// 1 / 1.08 = 0.926) starts from a shallow penetration, and the run ends free of crossings with
// nothing inside, judged here on the written file (stretched around a larger body: distorted).
TEST(Quality, GarmentCrossingItsOwnBodyIsReachedFromTheLeastDepth) {
  TempDir dir;
  const fs::path more = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman_more";
  const std::string body = scaled_body_six_decimals(dir, 1.08, more / "female_generic.obj");
  const std::string garment = (more / "female_casualsuit01.obj").string();
  const std::string out = dir.file("fixed.obj");
  const nlohmann::json j = fix_on_body(dir, garment, body, out);
  ASSERT_TRUE(j.is_object());
  const auto& scaled = j["scaled_continuation"];
  ASSERT_TRUE(scaled.is_object()) << j.dump(1);
  EXPECT_EQ(scaled["chosen_by"], "depth");
  EXPECT_TRUE(scaled["kept"].get<bool>());
  EXPECT_TRUE(scaled["clean"].get<bool>());
  EXPECT_NEAR(scaled["factor"].get<double>(), 1.0 / 1.08, 0.03);
  // Stretched beyond the bounds, so the factor of the fewest crossings is tried too, from the
  // input: the old choice, which gives up and is not kept.
  const auto& second = j["second_scaled_continuation"];
  ASSERT_TRUE(second.is_object()) << j.dump(1);
  EXPECT_EQ(second["chosen_by"], "count");
  EXPECT_FALSE(second["kept"].get<bool>());
  EXPECT_FALSE(second["clean"].get<bool>());
  EXPECT_LT(second["factor"].get<double>(), scaled["factor"].get<double>());
  expect_freed(garment, out, body, 1000);
}

TEST(Quality, RelaxationSmoothsWhatTheRepairPushed) {
  TempDir dir;
  TempDir other;
  const Fixed relaxed = fix_shipped_pair(dir, "");
  const Fixed plain = fix_shipped_pair(other, "--no-relax");
  ASSERT_EQ(relaxed.exit_code, 0);
  ASSERT_NE(plain.exit_code, -1);
  EXPECT_GT(relaxed.report["relax"]["sweeps"].get<int>(), 0);
  EXPECT_EQ(plain.report["relax"]["sweeps"].get<int>(), 0);
  EXPECT_EQ(garment_pairs(plain.output, plain.body), 0u);
  const Shape a = shape_change(relaxed.input, relaxed.output);
  const Shape b = shape_change(plain.input, plain.output);
  // Without the relaxation the repair's pushes stay steps in the cloth: larger changes, on more
  // edges. (The relaxation spreads a push over more edges, each changed a little: the 95th
  // percentile, at about 1% here, is not what it lowers.)
  EXPECT_LT(a.change.back(), b.change.back());
  auto beyond = [](const Shape& s, double x) {
    return s.change.end() - std::upper_bound(s.change.begin(), s.change.end(), x);
  };
  EXPECT_LT(beyond(a, 0.1), beyond(b, 0.1));
}

// --relax-sweeps bounds the relaxation: 2 sweeps run at most 2 (the default runs 7 here), the
// report says so, and 0 writes what --no-relax writes.
TEST(Quality, RelaxSweepsBoundTheRelaxation) {
  TempDir a, b, c;
  const Fixed two = fix_shipped_pair(a, "--relax-sweeps 2");
  ASSERT_TRUE(testing::intersection_free(two.exit_code)) << two.report.dump(1);
  EXPECT_EQ(two.report["options"]["relax_sweeps"], 2);
  EXPECT_GE(two.report["relax"]["sweeps"].get<int>(), 1);
  EXPECT_LE(two.report["relax"]["sweeps"].get<int>(), 2);
  EXPECT_EQ(garment_pairs(two.output, two.body), 0u);
  const Fixed none = fix_shipped_pair(b, "--relax-sweeps 0");
  const Fixed plain = fix_shipped_pair(c, "--no-relax");
  ASSERT_NE(none.exit_code, -1);
  ASSERT_NE(plain.exit_code, -1);
  EXPECT_EQ(none.report["relax"]["sweeps"].get<int>(), 0);
  EXPECT_EQ(read_text(b.file("fixed.obj")), read_text(c.file("fixed.obj")));
  EXPECT_EQ(run_cli("fix --relax-sweeps -1 x.obj").exit_code, 2);
}

TEST(Quality, BeyondTheBoundsIsDistortedAndStillWritten) {
  TempDir dir;
  const Fixed f = fix_shipped_pair(dir, "--max-stretch 1.001");
  ASSERT_EQ(f.exit_code, 6);
  EXPECT_EQ(f.report["status"], "distorted");
  EXPECT_FALSE(f.report["quality"][0]["within_bounds"].get<bool>());
  // Written all the same, and intersection-free.
  EXPECT_EQ(garment_pairs(f.output, f.body), 0u);
  EXPECT_GT(shape_change(f.input, f.output).stretch, 1.001);

  TempDir moves;
  const Fixed m = fix_shipped_pair(moves, "--max-move 0");
  EXPECT_EQ(m.exit_code, 6);
  EXPECT_EQ(m.report["status"], "distorted");
}

TEST(Quality, BoundsAreRefusedWhenMeaningless) {
  EXPECT_EQ(run_cli("fix a.obj -o b.obj --max-stretch 0.5").exit_code, 2);
  EXPECT_EQ(run_cli("fix a.obj -o b.obj --max-move -1").exit_code, 2);
}

TEST(Quality, TwoCornerFacesAreSkippedWithAWarningAndKept) {
  TempDir dir;
  // A panel through a box (both in one scene), the panel's file with a two-corner `f` line (a
  // tie's line element written as a face) and a one-corner one.
  std::string panel = "o panel\n";
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i)
      panel += "v " + std::to_string(-1.0 + 0.5 * i) + " " + std::to_string(-1.0 + 0.5 * j) +
               " 0.1\n";
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const int a = 1 + i + 5 * j;
      panel += "f " + std::to_string(a) + " " + std::to_string(a + 1) + " " +
               std::to_string(a + 6) + " " + std::to_string(a + 5) + "\n";
    }
  panel += "f 1 2\nf 3\n";
  const std::string in = dir.file("panel.obj");
  write_text(in, panel);
  const std::string box =
      "v -0.6 -0.6 -0.6\nv 0.6 -0.6 -0.6\nv 0.6 0.6 -0.6\nv -0.6 0.6 -0.6\n"
      "v -0.6 -0.6 0.6\nv 0.6 -0.6 0.6\nv 0.6 0.6 0.6\nv -0.6 0.6 0.6\n"
      "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  write_text(dir.file("box.obj"), box);
  const testing::RunResult c = run_cli("check " + quote(in));
  EXPECT_NE(c.exit_code, 3) << c.err;
  EXPECT_NE(c.err.find("warning: " + in + ": 2 faces with fewer than 3 corners skipped"),
            std::string::npos)
      << c.err;
  const std::string out = dir.file("fixed.obj");
  const testing::RunResult r =
      run_cli("fix " + quote(in) + " --obstacle " + quote(dir.file("box.obj")) + " -o " +
              quote(out) + " --max-stretch 100 --max-move 1");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string written = read_text(out);
  EXPECT_NE(written.find("\nf 1 2\nf 3\n"), std::string::npos);
  EXPECT_NE(written, panel);  // the panel was moved out of the box
  // -q keeps stderr quiet.
  EXPECT_EQ(run_cli("check -q " + quote(in)).err, "");
}

// Intersecting triangle pairs of a garment, as a triangle soup, with the body and with itself,
// each decided by CGAL's exact do_intersect(Triangle_3, Triangle_3) after a box intersection: for
// garments whose welded faces CGAL's Surface_mesh refuses (female_elegantsuit01's are not
// consistently oriented once welded). Garment triangles sharing a position are not tested against
// each other (they touch there).
std::size_t soup_pairs(const Mesh& garment, const Mesh& body) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
  std::vector<Kernel::Triangle_3> tris;
  std::vector<std::array<Vec3, 3>> corners;
  auto add = [&](const Mesh& m) {
    for (const Triangle& t : m.triangles) {
      std::array<Kernel::Point_3, 3> p;
      for (int k = 0; k < 3; ++k) {
        const Vec3& v = m.positions[t[k]];
        p[k] = Kernel::Point_3(v[0], v[1], v[2]);
      }
      tris.emplace_back(p[0], p[1], p[2]);
      corners.push_back({m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]});
    }
  };
  add(garment);
  const std::size_t garment_tris = tris.size();
  add(body);
  std::vector<Box> garment_boxes, body_boxes;
  for (std::uint32_t i = 0; i < tris.size(); ++i)
    if (!tris[i].is_degenerate()) (i < garment_tris ? garment_boxes : body_boxes).emplace_back(tris[i].bbox(), i);
  std::size_t n = 0;
  auto test = [&](const Box& a, const Box& b) {
    for (const Vec3& p : corners[a.info()])
      for (const Vec3& q : corners[b.info()])
        if (p == q) return;
    if (CGAL::do_intersect(tris[a.info()], tris[b.info()])) ++n;
  };
  CGAL::box_intersection_d(garment_boxes.begin(), garment_boxes.end(), body_boxes.begin(),
                           body_boxes.end(), test);
  CGAL::box_self_intersection_d(garment_boxes.begin(), garment_boxes.end(), test);
  return n;
}

// Issue 20's criterion on every MakeHuman garment on the body it was made for, as shipped
// (testdata/makehuman and testdata/makehuman_more, CC0): `fix` ends clean, and the written file,
// judged here, has no crossing with the body or itself (CGAL, soup_pairs), no vertex inside the body (CGAL's
// Side_of_triangle_mesh), no flipped face, edge-length change p95 at most 5% and max at most 50%,
// and no edge more than 1.5 times longer or shorter. Before the relaxation lifted its slides out to
// the clearance and stopped holding a vertex for good, male_casualsuit01 ended with stretch 1.70
// and 2 flipped faces, female_casualsuit01 with 1.52.
class MakeHumanGarment : public ::testing::TestWithParam<const char*> {};

TEST_P(MakeHumanGarment, EndsCleanWithinTheBounds) {
  const std::string name = GetParam();
  const fs::path more = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman_more";
  const fs::path garment = fs::exists(kMakeHuman / (name + ".obj")) ? kMakeHuman / (name + ".obj")
                                                                     : more / (name + ".obj");
  const fs::path body = name.rfind("male_", 0) == 0 ? kMakeHuman / "male_generic.obj"
                                                    : more / "female_generic.obj";
  TempDir dir;
  const std::string out = dir.file("fixed.obj"), report = dir.file("fixed.json");
  const testing::RunResult r = run_cli("fix " + quote(garment.string()) + " --obstacle " +
                                       quote(body.string()) + " -o " + quote(out) + " --report " +
                                       quote(report) + " -q");
  ASSERT_TRUE(fs::exists(out)) << r.err;
  const nlohmann::json rep = nlohmann::json::parse(read_text(report));
  EXPECT_EQ(r.exit_code, 0) << rep["quality"].dump(1);
  EXPECT_EQ(rep["status"], "clean");
  const Mesh input = read_meshes(garment.string(), Role::kMovable).at(0);
  const Mesh output = read_meshes(out, Role::kMovable).at(0);
  const Mesh obstacle = read_meshes(body.string(), Role::kObstacle).at(0);
  EXPECT_GT(cgal_reference::inside_count(input, obstacle), 0u);  // the input is tangled
  EXPECT_GT(soup_pairs(input, obstacle), 0u);
  EXPECT_EQ(soup_pairs(output, obstacle), 0u);
  EXPECT_EQ(cgal_reference::inside_count(output, obstacle), 0u);
  const Shape shape = shape_change(input, output);
  EXPECT_EQ(shape.flipped, 0u);
  EXPECT_LE(p95(shape), 0.05);
  EXPECT_LE(shape.change.back(), 0.5);
  EXPECT_LE(shape.stretch, 1.5);
}

INSTANTIATE_TEST_SUITE_P(Quality, MakeHumanGarment,
                         ::testing::Values("male_casualsuit01", "male_casualsuit02",
                                           "male_casualsuit04", "female_casualsuit01",
                                           "female_elegantsuit01", "female_sportsuit01"));

// Garments worn together (issue 21; FixOptions::layering): female_casualsuit01 (t-shirt and
// leggings) with female_sportsuit01 (crop top and leggings, the leggings nearly the same surface)
// on their body cross in 6,066 places, two surfaces a fraction of an edge apart over most of the
// body. Repaired together the result is free of crossings but distorted (edges up to 3.4 times
// their length, 14 flipped faces, measured 2026-12-06); laid one piece at a time (t-shirt, its leggings, the other leggings, the crop
// top), it is clean within the bounds. Judged on the files written, in both listing orders, which
// must write the same positions. (The pair was female_casualsuit01 with female_elegantsuit01 until
// the vertex order became free of half turns, 2026-12-06: the layers are ordered by median
// distance to the body, and there the t-shirt, 0.0489 against the dress top's 0.0498, came out
// 0.0510; laid over the dress top it stalls.)
Mesh soup_of(const std::vector<Mesh>& meshes) {
  Mesh soup;
  for (const Mesh& m : meshes) {
    const auto base = static_cast<std::uint32_t>(soup.positions.size());
    soup.positions.insert(soup.positions.end(), m.positions.begin(), m.positions.end());
    for (const Triangle& t : m.triangles)
      soup.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  return soup;
}

TEST(Quality, GarmentsWornTogetherAreLaidOneOverTheOther) {
  const fs::path more = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman_more";
  const std::string shirt = (more / "female_casualsuit01.obj").string();
  const std::string suit = (more / "female_sportsuit01.obj").string();
  const std::string body = (more / "female_generic.obj").string();
  struct Run {
    int exit_code = -1;
    nlohmann::json report;
    Mesh shirt, suit;
  };
  const auto fix = [&](const TempDir& dir, bool shirt_first, const std::string& extra) {
    const std::string a = shirt_first ? shirt : suit, b = shirt_first ? suit : shirt;
    const std::string report = dir.file("report.json");
    const testing::RunResult r =
        run_cli("fix " + quote(a) + " " + quote(b) + " --obstacle " + quote(body) +
                " --output-dir " + quote(dir.path().string()) + " --report " + quote(report) +
                " -q " + extra);
    Run run;
    run.exit_code = r.exit_code;
    if (!fs::exists(report)) return run;
    run.report = nlohmann::json::parse(read_text(report));
    run.shirt = read_meshes(dir.file("female_casualsuit01.obj"), Role::kMovable).at(0);
    run.suit = read_meshes(dir.file("female_sportsuit01.obj"), Role::kMovable).at(0);
    return run;
  };
  const Mesh shirt_in = read_meshes(shirt, Role::kMovable).at(0);
  const Mesh suit_in = read_meshes(suit, Role::kMovable).at(0);
  const Mesh obstacle = read_meshes(body, Role::kObstacle).at(0);
  ASSERT_GT(soup_pairs(soup_of({shirt_in, suit_in}), obstacle), 1000u);

  TempDir direct_dir;
  const Run direct = fix(direct_dir, true, "--no-layering");
  ASSERT_NE(direct.exit_code, -1);
  EXPECT_NE(direct.exit_code, 0) << "repaired together it is clean: the test no longer tests";
  EXPECT_TRUE(direct.report["layering"].is_null());
  EXPECT_FALSE(direct.report["options"]["layering"].get<bool>());

  TempDir dir;
  const Run laid = fix(dir, true, "");
  ASSERT_EQ(laid.exit_code, 0) << laid.report.dump(1);
  EXPECT_EQ(laid.report["status"], "clean");
  EXPECT_TRUE(laid.report["options"]["layering"].get<bool>());
  const auto& l = laid.report["layering"];
  ASSERT_TRUE(l.is_object());
  EXPECT_TRUE(l["kept"].get<bool>());
  EXPECT_TRUE(l["clean"].get<bool>());
  EXPECT_EQ(laid.report["history"].back()["stage"], 5);
  // Its first attempt ends unresolved: without the layering the retries run; with it, the
  // layering runs first and, clean within the bounds, leaves no retry to run.
  EXPECT_FALSE(direct.report["retries"].empty());
  EXPECT_TRUE(laid.report["retries"].empty()) << laid.report["retries"].dump();
  // The body's own crossings (toes, lips) are the body's, whichever attempt was kept.
  EXPECT_GT(direct.report["obstacles"]["crossing_pairs"].get<int>(), 0);
  EXPECT_EQ(laid.report["obstacles"], direct.report["obstacles"]);
  // Four layers, each piece of each garment once, nearest the body first.
  const auto& layers = l["layers"];
  ASSERT_EQ(layers.size(), 4u);
  std::set<std::pair<int, int>> pieces;
  for (std::size_t k = 0; k < layers.size(); ++k) {
    pieces.insert({layers[k]["mesh"].get<int>(), layers[k]["component"].get<int>()});
    if (k > 0) {
      EXPECT_LE(layers[k - 1]["distance"].get<double>(), layers[k]["distance"].get<double>());
    }
  }
  EXPECT_EQ(pieces, (std::set<std::pair<int, int>>{{0, 0}, {0, 1}, {1, 0}, {1, 1}}));
  // The written files: no crossing among the garments and the body, nothing inside the body, the
  // shapes kept.
  EXPECT_EQ(soup_pairs(soup_of({laid.shirt, laid.suit}), obstacle), 0u);
  EXPECT_EQ(cgal_reference::inside_count(laid.shirt, obstacle), 0u);
  EXPECT_EQ(cgal_reference::inside_count(laid.suit, obstacle), 0u);
  for (const auto& [in, out] :
       {std::pair{&shirt_in, &laid.shirt}, std::pair{&suit_in, &laid.suit}}) {
    const Shape shape = shape_change(*in, *out);
    EXPECT_EQ(shape.flipped, 0u);
    EXPECT_LE(shape.stretch, 1.5);
  }
  EXPECT_LT(shape_change(suit_in, laid.suit).stretch, shape_change(suit_in, direct.suit).stretch);

  // Listed the other way round: the same positions, bit for bit.
  TempDir swapped_dir;
  const Run swapped = fix(swapped_dir, false, "");
  ASSERT_EQ(swapped.exit_code, 0);
  EXPECT_EQ(swapped.shirt.positions, laid.shirt.positions);
  EXPECT_EQ(swapped.suit.positions, laid.suit.positions);

  // Pinned vertices stay where they are through the layering: of each garment, the four that the
  // unpinned run moved least (pinning those still lets the layering succeed; pinning vertices it
  // moved far left 704 crossings).
  std::vector<std::pair<int, std::uint32_t>> moved;  // (input, vertex)
  for (int g = 0; g < 2; ++g) {
    const Mesh& in = g == 0 ? shirt_in : suit_in;
    const Mesh& out = g == 0 ? laid.shirt : laid.suit;
    std::vector<std::pair<double, std::uint32_t>> by_move;
    for (std::uint32_t v = 0; v < in.positions.size(); ++v) {
      const Vec3 &a = in.positions[v], &b = out.positions[v];
      const double d = std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
      if (d > 0.0) by_move.emplace_back(d, v);
    }
    std::sort(by_move.begin(), by_move.end());
    for (std::size_t k = 0; k < 4 && k < by_move.size(); ++k)
      moved.emplace_back(g, by_move[k].second);
  }
  ASSERT_EQ(moved.size(), 8u);
  TempDir pinned_dir;
  std::string pins;
  for (const auto& [g, v] : moved) pins += std::to_string(g) + " " + std::to_string(v) + "\n";
  write_text(pinned_dir.file("pins.txt"), pins);
  const Run pinned = fix(pinned_dir, true, "--pin " + quote(pinned_dir.file("pins.txt")));
  ASSERT_TRUE(testing::intersection_free(pinned.exit_code)) << pinned.report.dump(1);
  ASSERT_TRUE(pinned.report["layering"].is_object());
  EXPECT_TRUE(pinned.report["layering"]["kept"].get<bool>()) << "the pins are not tested";
  for (const auto& [g, v] : moved) {
    const Vec3& before = (g == 0 ? shirt_in : suit_in).positions[v];
    EXPECT_EQ((g == 0 ? pinned.shirt : pinned.suit).positions[v], before) << g << " " << v;
  }
}

// Where the layers' order by median distance ends badly, the layering tries the order where the
// pieces overlap (issue 21). female_elegantsuit01 (dress: skirt and top) with female_sportsuit01
// (crop top and leggings) on their body: by median distance the dress top (0.0497) is laid first
// and the skirt (0.0915) last, over the leggings and the crop top, and the run keeps 77 crossings;
// where the pieces overlap the skirt lies inside the crop top and the leggings inside the skirt,
// and laid in that order the scene ends free of crossings (still beyond the bounds: an edge 4.1
// times its length). The written files are judged.
TEST(Quality, LayeringTriesTheOrderWhereThePiecesOverlap) {
  const fs::path more = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman_more";
  const std::string dress = (more / "female_elegantsuit01.obj").string();
  const std::string suit = (more / "female_sportsuit01.obj").string();
  const std::string body = (more / "female_generic.obj").string();
  TempDir dir;
  const std::string report_path = dir.file("report.json");
  const testing::RunResult r = run_cli("fix " + quote(dress) + " " + quote(suit) + " --obstacle " +
                                       quote(body) + " --output-dir " + quote(dir.path().string()) +
                                       " --report " + quote(report_path) + " -q");
  ASSERT_TRUE(fs::exists(report_path)) << r.err;
  const nlohmann::json report = nlohmann::json::parse(read_text(report_path));
  EXPECT_TRUE(testing::intersection_free(r.exit_code)) << r.err;
  const auto& l = report["layering"];
  ASSERT_TRUE(l.is_object());
  ASSERT_EQ(l["orders"].size(), 2u) << l.dump(1);
  const auto& by_distance = l["orders"][0];
  const auto& by_overlap = l["orders"][1];
  EXPECT_EQ(by_distance["rule"], "median_distance");
  EXPECT_FALSE(by_distance["clean"].get<bool>())
      << "the first order is clean: the test no longer tests";
  EXPECT_FALSE(by_distance["kept"].get<bool>());
  EXPECT_EQ(by_overlap["rule"], "overlap");
  EXPECT_TRUE(by_overlap["clean"].get<bool>());
  EXPECT_TRUE(by_overlap["kept"].get<bool>());
  EXPECT_TRUE(l["kept"].get<bool>());
  EXPECT_EQ(l["layers"], by_overlap["layers"]);
  // The same four pieces in another order.
  std::vector<std::pair<int, int>> a, b;
  for (const auto& layer : by_distance["layers"])
    a.emplace_back(layer["mesh"].get<int>(), layer["component"].get<int>());
  for (const auto& layer : by_overlap["layers"])
    b.emplace_back(layer["mesh"].get<int>(), layer["component"].get<int>());
  EXPECT_NE(a, b);
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.size(), 4u);
  // The written files: no crossing among the garments and the body, nothing inside the body.
  const Mesh dress_out = read_meshes(dir.file("female_elegantsuit01.obj"), Role::kMovable).at(0);
  const Mesh suit_out = read_meshes(dir.file("female_sportsuit01.obj"), Role::kMovable).at(0);
  const Mesh obstacle = read_meshes(body, Role::kObstacle).at(0);
  EXPECT_EQ(soup_pairs(soup_of({dress_out, suit_out}), obstacle), 0u);
  EXPECT_EQ(cgal_reference::inside_count(dress_out, obstacle), 0u);
  EXPECT_EQ(cgal_reference::inside_count(suit_out, obstacle), 0u);
}

}  // namespace
}  // namespace untangle
