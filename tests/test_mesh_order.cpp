// Order-free layers (issue 21): the same meshes listed in any order give the same crossings, the
// same illegal vertices and the same positions, bit for bit. Ids across meshes follow the order the
// repair and detection number the meshes in, and with them the symbolic perturbation (exact ties
// decided by vertex id) and the order moves are summed in; that order must come from the meshes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "resolve/illegal_vertices.h"
#include "scenes/scenes.h"
#include "test_support.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"
#include "untangle/read_meshes.h"

namespace untangle {
namespace {

using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;
namespace fs = std::filesystem;

const fs::path kMakeHuman = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman";

Mesh read_one(const fs::path& path, Role role) {
  std::vector<Mesh> meshes = read_meshes(path.string(), role);
  EXPECT_EQ(meshes.size(), 1u) << path;
  return meshes.empty() ? Mesh{} : meshes.front();
}

// A second garment layer made from `garment`: every vertex moved along its normal (the sum of its
// faces' cross products) by 0.3 mean edge lengths times sin(3 * 2 pi * t), t its height in the
// garment's box from 0 to 1, except where that sine is within 0.2 of 0: there it keeps its
// position bit for bit. The layer passes through the garment in those bands, where the two share
// positions and faces (exact ties for the perturbation to decide), and pokes into the body where
// it moves inward. Its last triangle is left out: meshes alike in counts and valences keep their
// listing order (canonical_order.h), and this layer is to be ordered by what it is.
Mesh second_layer(const Mesh& garment) {
  Mesh layer = garment;
  std::vector<Vec3> normal(garment.positions.size(), Vec3{0, 0, 0});
  double edges = 0.0;
  std::size_t edge_count = 0;
  for (const Triangle& t : garment.triangles) {
    const Vec3 &a = garment.positions[t[0]], &b = garment.positions[t[1]], &c = garment.positions[t[2]];
    const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const Vec3 n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    for (std::uint32_t i : t)
      for (int k = 0; k < 3; ++k) normal[i][k] += n[k];
    edges += std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    ++edge_count;
  }
  const double h = edges / static_cast<double>(std::max<std::size_t>(edge_count, 1));
  double lo = INFINITY, hi = -INFINITY;
  for (const Vec3& p : garment.positions) {
    lo = std::min(lo, p[1]);
    hi = std::max(hi, p[1]);
  }
  for (std::size_t i = 0; i < layer.positions.size(); ++i) {
    const double s = std::sin(3.0 * 2.0 * M_PI * (garment.positions[i][1] - lo) / (hi - lo));
    const double length = std::sqrt(normal[i][0] * normal[i][0] + normal[i][1] * normal[i][1] +
                                    normal[i][2] * normal[i][2]);
    if (std::abs(s) < 0.2 || length == 0.0) continue;
    for (int k = 0; k < 3; ++k) layer.positions[i][k] += 0.3 * h * s * normal[i][k] / length;
  }
  layer.name = "layer";
  layer.triangles.pop_back();
  if (!layer.polygon.empty()) {
    const std::uint32_t face = layer.polygon.back();
    layer.polygon.pop_back();
    if (layer.polygon.empty() || layer.polygon.back() != face) --layer.source_faces;  // its face is gone
  }
  if (!layer.triangle_group.empty()) layer.triangle_group.resize(layer.triangles.size());
  return layer;
}

// The shipped garment, a second layer made from it (second_layer) and the body, as an obstacle.
std::vector<Mesh> garment_layers() {
  const Mesh garment = read_one(kMakeHuman / "male_casualsuit04.obj", Role::kMovable);
  return {garment, second_layer(garment), read_one(kMakeHuman / "male_generic.obj", Role::kObstacle)};
}

// Two cloth layers through each other and through a body: open tubes around a closed capsule
// (obstacle), their radii waving around it with different phases and frequencies, so that each
// pokes into the body and the two cross each other. Not degenerate: what differs between listing
// orders here is the order the repair sums its moves in.
std::vector<Mesh> tube_layers() {
  auto wavy = [](double radius, double amplitude, int waves, double phase, int slices, int rings,
                 const char* name) {
    Mesh tube = scenes::open_tube({0, 0, 0}, radius, 1.6, slices, rings, name);
    for (Vec3& p : tube.positions) {
      const double angle = std::atan2(p[1], p[0]);
      const double f = 1.0 + amplitude * std::sin(waves * angle + phase + 3.0 * p[2]);
      p[0] *= f;
      p[1] *= f;
    }
    return tube;
  };
  std::vector<Mesh> meshes{wavy(0.56, 0.14, 5, 0.0, 40, 17, "inner"),
                           wavy(0.6, 0.12, 3, 1.0, 36, 15, "outer"),
                           scenes::capsule({0, 0, 0}, 0.5, 2.0, 32, 11, "body")};
  meshes.back().role = Role::kObstacle;
  return meshes;
}

// `meshes` listed in `order` (order[k] = which of them comes k-th).
std::vector<Mesh> listed(const std::vector<Mesh>& meshes, const std::vector<std::uint32_t>& order) {
  std::vector<Mesh> out;
  for (std::uint32_t m : order) out.push_back(meshes[m]);
  return out;
}

// A detection's crossings, named by the meshes as in `meshes` (order[k] for the k-th listed).
using NamedCrossing = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>;
std::set<NamedCrossing> named_crossings(const Intersections& found,
                                        const std::vector<std::uint32_t>& order) {
  std::set<NamedCrossing> out;
  for (const Crossing& c : found.crossings)
    out.insert({order[c.edge_mesh], c.edge_v0, c.edge_v1, order[c.face_mesh], c.face});
  return out;
}

// Per mesh of `meshes`, the values listed per mesh in `order`.
template <class T>
std::vector<T> per_original(const std::vector<T>& per_listed, const std::vector<std::uint32_t>& order) {
  std::vector<T> out(per_listed.size());
  for (std::size_t k = 0; k < per_listed.size() && k < order.size(); ++k) out[order[k]] = per_listed[k];
  return out;
}

std::vector<std::tuple<std::uint32_t, std::uint32_t, std::size_t, std::size_t, std::size_t>>
named_contacts(const IntersectionCounts& counts, const std::vector<std::uint32_t>& order) {
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::size_t, std::size_t, std::size_t>> out;
  for (const MeshContact& c : counts.contacts)
    out.emplace_back(std::min(order[c.mesh_a], order[c.mesh_b]), std::max(order[c.mesh_a], order[c.mesh_b]),
                     c.seam_vertices, c.repeated_faces, c.coplanar_pairs);
  std::sort(out.begin(), out.end());
  return out;
}

const std::vector<std::vector<std::uint32_t>> kOrders = {{0, 1, 2}, {1, 0, 2}, {2, 1, 0}};

// check and render --inside: the same crossings (by mesh, edge and face), contours, contour
// length to the bit, contacts and illegal vertices whichever order the garment, its second layer
// and the body are listed in.
TEST(MeshOrder, CheckFindsTheSameInEveryListingOrder) {
  const std::vector<Mesh> meshes = garment_layers();
  DetectOptions options;
  options.threads = 2;
  const Intersections first = find_intersections(listed(meshes, kOrders[0]), options);
  ASSERT_GT(first.counts.crossings, 0u);
  const auto illegal_first = illegal_vertices(listed(meshes, kOrders[0]), true, 2);
  for (std::size_t k = 1; k < kOrders.size(); ++k) {
    const auto& order = kOrders[k];
    SCOPED_TRACE("order " + std::to_string(order[0]) + std::to_string(order[1]) + std::to_string(order[2]));
    const Intersections found = find_intersections(listed(meshes, order), options);
    EXPECT_EQ(found.counts.crossings, first.counts.crossings);
    EXPECT_EQ(found.counts.triangle_pairs, first.counts.triangle_pairs);
    EXPECT_EQ(found.counts.contours, first.counts.contours);
    EXPECT_EQ(found.counts.contour_length, first.counts.contour_length);
    EXPECT_EQ(found.counts.inside_vertices, first.counts.inside_vertices);
    EXPECT_EQ(per_original(found.counts.inside_by_mesh, order), first.counts.inside_by_mesh);
    EXPECT_EQ(named_contacts(found.counts, order), named_contacts(first.counts, kOrders[0]));
    EXPECT_TRUE(named_crossings(found, order) == named_crossings(first, kOrders[0]));
    EXPECT_TRUE(per_original(illegal_vertices(listed(meshes, order), true, 2), order) == illegal_first);
  }
}

// fix_meshes: the same positions, bit for bit, and the same counts and quality per mesh, for two
// cloth layers through each other and a body listed in every order.
TEST(MeshOrder, FixMovesTheSameInEveryListingOrder) {
  const std::vector<Mesh> meshes = tube_layers();
  FixOptions options;
  options.threads = 2;
  options.max_iterations = 15;  // enough for the orders to part on the old code; keeps it quick
  options.retries = 0;
  std::vector<Mesh> first = listed(meshes, kOrders[0]);
  const FixResult r0 = fix_meshes(first, options);
  ASSERT_GT(r0.before.crossings, 0u);
  ASSERT_GT(r0.displacement.moved_vertices, 0u);
  for (std::size_t k = 1; k < kOrders.size(); ++k) {
    const auto& order = kOrders[k];
    SCOPED_TRACE("order " + std::to_string(order[0]) + std::to_string(order[1]) + std::to_string(order[2]));
    std::vector<Mesh> fixed = listed(meshes, order);
    const FixResult r = fix_meshes(fixed, options);
    EXPECT_EQ(r.clean, r0.clean);
    EXPECT_EQ(r.iterations, r0.iterations);
    EXPECT_EQ(r.before.crossings, r0.before.crossings);
    EXPECT_EQ(r.after.crossings, r0.after.crossings);
    EXPECT_EQ(r.after.inside_vertices, r0.after.inside_vertices);
    EXPECT_EQ(per_original(r.after.inside_by_mesh, order), r0.after.inside_by_mesh);
    EXPECT_EQ(r.displacement.moved_vertices, r0.displacement.moved_vertices);
    const std::vector<QualityStats> quality = per_original(r.quality, order);
    ASSERT_EQ(quality.size(), r0.quality.size());
    for (std::size_t m = 0; m < quality.size(); ++m) {
      EXPECT_EQ(quality[m].edge_change_max, r0.quality[m].edge_change_max) << "mesh " << m;
      EXPECT_EQ(quality[m].max_displacement, r0.quality[m].max_displacement) << "mesh " << m;
    }
    const std::vector<Mesh> back = per_original(fixed, order);
    for (std::size_t m = 0; m < back.size(); ++m)
      EXPECT_TRUE(back[m].positions == first[m].positions) << "mesh " << m << " moved differently";
  }
}

// What the CLI reports and writes for `meshes` (the movable ones listed in their order, or in the
// reverse order when `swapped`; obstacles after --obstacle): check's report and, when `fix`,
// fix's and the bytes it writes, per movable mesh in the order of `meshes`.
struct CliRun {
  nlohmann::json check, fix;
  std::vector<std::string> written;
};

CliRun run_commands(const TempDir& dir, const std::vector<Mesh>& meshes, bool swapped, bool fix) {
  const std::string tag = swapped ? "swapped" : "listed";
  std::vector<std::string> inputs, outputs;
  std::string obstacles;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const std::string path = dir.file(std::to_string(m) + ".obj");
    if (!fs::exists(path)) scenes::write_obj(meshes[m], path);
    if (meshes[m].role == Role::kObstacle) {
      obstacles += " --obstacle " + quote(path);
    } else {
      inputs.push_back(path);
      outputs.push_back(dir.file(tag + "_out" + std::to_string(m) + ".obj"));
    }
  }
  std::string args, out_args;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const std::size_t m = swapped ? inputs.size() - 1 - k : k;
    args += " " + quote(inputs[m]);
    out_args += " -o " + quote(outputs[m]);
  }
  args += obstacles + " --threads 2 -q --report ";
  CliRun run;
  const auto checked = run_cli("check" + args + quote(dir.file(tag + "_check.json")));
  EXPECT_EQ(checked.exit_code, 5) << checked.err;  // intersections found
  run.check = nlohmann::json::parse(read_text(dir.file(tag + "_check.json")));
  if (!fix) return run;
  const auto fixed = run_cli("fix" + args + quote(dir.file(tag + "_fix.json")) + out_args +
                             " --max-iterations 15 --retries 0");  // as FixMovesTheSame...
  run.fix = nlohmann::json::parse(read_text(dir.file(tag + "_fix.json")));
  for (std::size_t m = 0; m < outputs.size(); ++m) {
    run.written.push_back(read_text(outputs[m]));
    EXPECT_FALSE(run.written.back().empty()) << fixed.err;
    EXPECT_NE(run.written.back(), read_text(inputs[m])) << "nothing moved in movable mesh " << m;
  }
  return run;
}

void expect_same_runs(const CliRun& a, const CliRun& b) {
  for (const char* field : {"crossings", "triangle_pairs", "contours", "contour_length", "inside_vertices"}) {
    EXPECT_EQ(a.check["before"][field], b.check["before"][field]) << "check " << field;
    if (a.fix.is_null() || b.fix.is_null()) return;
    EXPECT_EQ(a.fix["before"][field], b.fix["before"][field]) << "fix before " << field;
    EXPECT_EQ(a.fix["after"][field], b.fix["after"][field]) << "fix after " << field;
  }
  EXPECT_EQ(a.fix["status"], b.fix["status"]);
  EXPECT_EQ(a.fix["iterations"], b.fix["iterations"]);
  ASSERT_EQ(a.written.size(), b.written.size());
  for (std::size_t m = 0; m < a.written.size(); ++m)
    EXPECT_TRUE(a.written[m] == b.written[m]) << "movable mesh " << m << " was written differently";
}

// The CLI, on files: `check` counts and `fix` outputs (bytes), counts and status are the same
// with the two tube layers around the body listed either way, and `check` finds the same with the
// shipped garment and its second layer (exact ties between the layers) listed either way.
TEST(MeshOrder, CliWritesTheSameFilesInEitherListingOrder) {
  {
    SCOPED_TRACE("tube layers");
    TempDir dir;
    const std::vector<Mesh> meshes = tube_layers();
    expect_same_runs(run_commands(dir, meshes, false, true), run_commands(dir, meshes, true, true));
  }
  {
    SCOPED_TRACE("garment layers");
    TempDir dir;
    const std::vector<Mesh> meshes = garment_layers();
    expect_same_runs(run_commands(dir, meshes, false, false), run_commands(dir, meshes, true, false));
  }
}

}  // namespace
}  // namespace untangle
