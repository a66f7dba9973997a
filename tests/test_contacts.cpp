// Contact is not penetration (DESIGN §2, issue 20): a garment sewn to its body at shared seam
// vertices, with and without a dent through the body, plain, rotated and with every face repeated.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "scene_files.h"
#include "scenes/scenes.h"
#include "test_support.h"
#include "untangle/read_meshes.h"

namespace untangle {
namespace {

using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;

constexpr int kSlices = 24;       // sewn_garment's slices
constexpr int kGarmentRings = 11;  // the two seam rings and nine between
constexpr std::size_t kSeamVertices = 2 * kSlices;
constexpr std::size_t kGarmentTriangles = 2 * kSlices * (kGarmentRings - 1);
const Vec3 kRotation{0.3, 0.7, 1.1};  // about x, y, z: no axis of the scene stays on an axis

bool on_seam(std::size_t v) {
  return v < static_cast<std::size_t>(kSlices) || v >= static_cast<std::size_t>(kSlices) * (kGarmentRings - 1);
}

struct FixRun {
  int exit_code = -1;
  nlohmann::json report;
  Mesh input, output;  // the garment
  std::string out;
};

FixRun fix_scene(const scenes::Scene& scene, const TempDir& dir) {
  const testing::SceneFiles files = testing::write_scene(scene, dir);
  FixRun run;
  const auto r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("out.obj")) + " --report " +
                         quote(dir.file("report.json")));
  run.exit_code = r.exit_code;
  run.out = r.out + r.err;
  run.report = nlohmann::json::parse(read_text(dir.file("report.json")));
  run.input = read_meshes(files.movable[0], Role::kMovable).front();
  run.output = read_meshes(dir.file("out.obj"), Role::kMovable).front();
  return run;
}

// The contacts entry of meshes (a, b) in a counts object, or null.
nlohmann::json contact(const nlohmann::json& counts, int a, int b) {
  for (const auto& c : counts["contacts"])
    if (c["meshes"][0] == a && c["meshes"][1] == b) return c;
  return nullptr;
}

// Checks what must hold of every sewn garment after fix: written clean, the seam vertices where
// they were bit for bit, the contacts reported before and after, and (unrotated scene) every
// garment vertex outside the body's cylinder.
void expect_sewn_and_clean(const FixRun& run, bool rotated) {
  EXPECT_EQ(run.exit_code, 0) << run.out;
  EXPECT_EQ(run.report["status"], "clean") << run.out;
  EXPECT_EQ(run.report["after"]["crossings"], 0);
  EXPECT_EQ(run.report["after"]["inside_vertices"], 0);
  for (const char* when : {"before", "after"}) {
    const auto seam = contact(run.report[when], 0, 1);
    ASSERT_FALSE(seam.is_null()) << when << ": no contact between garment and body";
    EXPECT_EQ(seam["seam_vertices"], kSeamVertices) << when;
  }
  EXPECT_NE(run.out.find("contacts (not crossings): 48 seam vertices"), std::string::npos) << run.out;
  ASSERT_EQ(run.input.positions.size(), run.output.positions.size());
  for (std::size_t v = 0; v < run.input.positions.size(); ++v) {
    if (on_seam(v)) {
      EXPECT_EQ(run.input.positions[v], run.output.positions[v]) << "seam vertex " << v << " moved";
    }
    if (!rotated && !on_seam(v)) {
      const Vec3& p = run.output.positions[v];
      EXPECT_GE(std::hypot(p[0], p[1]), 0.5) << "garment vertex " << v << " inside the body";
    }
  }
  EXPECT_EQ(run.input.triangles, run.output.triangles);
}

// (a) Sewn at two seam rings, dented through the body between them: fix moves the dent out and
// leaves the seams sewn; the scene rotated off every axis gives the same counts.
TEST(Contacts, SewnGarmentWithADentEndsCleanWithItsSeamsSewn) {
  TempDir plain_dir, rotated_dir;
  const scenes::Scene scene = scenes::sewn_garment(true, false);
  const FixRun plain = fix_scene(scene, plain_dir);
  const FixRun rotated = fix_scene(scenes::rotated_scene(scene, kRotation), rotated_dir);
  expect_sewn_and_clean(plain, false);
  expect_sewn_and_clean(rotated, true);
  EXPECT_GT(plain.report["before"]["crossings"].get<int>(), 0) << "the dent must cross the body";
  EXPECT_GT(plain.report["before"]["inside_vertices"].get<int>(), 0);
  for (const char* key : {"crossings", "contours", "inside_vertices", "contacts"})
    EXPECT_EQ(plain.report["before"][key], rotated.report["before"][key]) << key;
  EXPECT_EQ(plain.report["after"]["contacts"], rotated.report["after"]["contacts"]);
}

// (b) The same with every face of both meshes repeated with the opposite winding: the repeats are
// contact within each mesh, the crossings and seams are those of (a), and fix ends the same way.
TEST(Contacts, RepeatedFacesAreContactNotCrossings) {
  TempDir single_dir, repeated_dir, rotated_dir;
  const FixRun single = fix_scene(scenes::sewn_garment(true, false), single_dir);
  const scenes::Scene scene = scenes::sewn_garment(true, true);
  const FixRun repeated = fix_scene(scene, repeated_dir);
  const FixRun rotated = fix_scene(scenes::rotated_scene(scene, kRotation), rotated_dir);
  expect_sewn_and_clean(repeated, false);
  expect_sewn_and_clean(rotated, true);
  const std::size_t body_triangles = scene.obstacles[0].triangles.size() / 2;
  for (const FixRun* run : {&repeated, &rotated}) {
    const auto& before = run->report["before"];
    EXPECT_EQ(before["crossings"], single.report["before"]["crossings"]);
    EXPECT_EQ(before["contours"], single.report["before"]["contours"]);
    EXPECT_EQ(before["inside_vertices"], single.report["before"]["inside_vertices"]);
    ASSERT_FALSE(contact(before, 0, 0).is_null());
    ASSERT_FALSE(contact(before, 1, 1).is_null());
    EXPECT_EQ(contact(before, 0, 0)["repeated_faces"], kGarmentTriangles);
    EXPECT_EQ(contact(before, 1, 1)["repeated_faces"], body_triangles);
    EXPECT_EQ(contact(before, 0, 1)["repeated_faces"], 0);
    EXPECT_EQ(run->report["after"]["contacts"], before["contacts"]);
  }
  EXPECT_EQ(repeated.input.triangles.size(), 2 * kGarmentTriangles);
}

// (c) Sewn and nowhere through the body: check finds no crossing, reports the contacts, exits 0;
// rotated alike.
TEST(Contacts, GarmentTouchingOnlyAtSeamsChecksClean) {
  for (bool rotate : {false, true}) {
    TempDir dir;
    scenes::Scene scene = scenes::sewn_garment(false, false);
    if (rotate) scene = scenes::rotated_scene(scene, kRotation);
    const testing::SceneFiles files = testing::write_scene(scene, dir);
    const auto r = run_cli("check" + files.inputs_args() + " --report " + quote(dir.file("report.json")));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("contacts (not crossings): 48 seam vertices, 0 repeated faces"), std::string::npos)
        << r.out;
    const auto report = nlohmann::json::parse(read_text(dir.file("report.json")));
    EXPECT_EQ(report["status"], "clean");
    EXPECT_EQ(report["before"]["crossings"], 0);
    EXPECT_EQ(report["before"]["inside_vertices"], 0);
    const auto seam = contact(report["before"], 0, 1);
    ASSERT_FALSE(seam.is_null());
    EXPECT_EQ(seam["seam_vertices"], kSeamVertices);
    EXPECT_EQ(seam["repeated_faces"], 0);
  }
}

}  // namespace
}  // namespace untangle
