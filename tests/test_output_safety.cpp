// Issue 22 §1: every file a run writes is checked before any work against every file it reads
// and against each other; a clash is exit 4, one line naming both paths, and nothing is written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "test_support.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;
using testing::write_text;

// A garment square crossing a body square at right angles through its middle.
constexpr const char* kGarment = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n";
constexpr const char* kBody =
    "v -0.5 0.1 -1\nv 0.5 0.1 -1\nv 0.5 0.1 1\nv -0.5 0.1 1\nf 1 2 3\nf 1 3 4\n";

using Points = std::vector<std::array<float, 3>>;
const Points kGarmentPoints = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
const Points kBodyPoints = {{-0.5f, 0.1f, -1}, {0.5f, 0.1f, -1}, {0.5f, 0.1f, 1}, {-0.5f, 0.1f, 1}};

// A glTF 2.0 file `path` of two triangles whose buffer is the side file `bin` (a name in the
// same folder).
void write_gltf(const std::string& path, const std::string& bin, const Points& points) {
  const std::uint32_t indices[] = {0, 1, 2, 0, 2, 3};
  std::string data(points.size() * 12 + sizeof(indices), '\0');
  std::memcpy(data.data(), points.data(), points.size() * 12);
  std::memcpy(data.data() + points.size() * 12, indices, sizeof(indices));
  std::array<float, 3> lo = points[0], hi = points[0];
  for (const auto& p : points)
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
  nlohmann::json j;
  j["asset"] = {{"version", "2.0"}};
  j["scene"] = 0;
  j["scenes"] = {{{"nodes", {0}}}};
  j["nodes"] = {{{"mesh", 0}}};
  j["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}};
  j["buffers"] = {{{"uri", bin}, {"byteLength", data.size()}}};
  j["bufferViews"] = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", points.size() * 12}},
                      {{"buffer", 0}, {"byteOffset", points.size() * 12}, {"byteLength", sizeof(indices)}}};
  j["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", points.size()}, {"type", "VEC3"},
                     {"min", lo}, {"max", hi}},
                    {{"bufferView", 1}, {"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}}};
  write_text(path, j.dump());
  write_text((fs::path(path).parent_path() / bin).string(), data);
}

std::size_t line_count(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

// A scene on disk: g.obj (movable), b.obj (obstacle).
struct Scene {
  TempDir dir;
  std::string g = dir.file("g.obj"), b = dir.file("b.obj"), out = dir.file("out.obj");
  Scene() {
    write_text(g, kGarment);
    write_text(b, kBody);
  }
  std::string fix(const std::string& extra) const {
    return "fix " + quote(g) + " --obstacle " + quote(b) + " -o " + quote(out) + " " + extra;
  }
};

// Exit 4 with one line on stderr naming every path in `named`, the inputs as they were, and no
// output written.
void expect_refused(const testing::RunResult& r, const std::vector<std::string>& named,
                    const Scene& s) {
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(line_count(r.err), 1u) << r.err;
  EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
  for (const std::string& path : named) EXPECT_NE(r.err.find(path), std::string::npos) << path << ": " << r.err;
  EXPECT_EQ(read_text(s.g), kGarment);
  EXPECT_EQ(read_text(s.b), kBody);
  EXPECT_FALSE(fs::exists(s.out)) << r.err;
}

TEST(OutputSafety, ReportOnTheInputIsRefused) {
  Scene s;
  const auto r = run_cli(s.fix("--report " + quote(s.g)));
  expect_refused(r, {"--report " + s.g, "the input " + s.g}, s);
  // --overwrite never makes an input writable.
  expect_refused(run_cli(s.fix("--report " + quote(s.g) + " --overwrite")), {s.g}, s);
}

TEST(OutputSafety, ReportOnTheOutputIsRefused) {
  Scene s;
  expect_refused(run_cli(s.fix("--report " + quote(s.out))), {"--report " + s.out, "output " + s.out}, s);
}

TEST(OutputSafety, ContoursOnTheObstacleIsRefused) {
  Scene s;
  expect_refused(run_cli(s.fix("--contours " + quote(s.b))), {"--contours " + s.b, "the obstacle " + s.b}, s);
  // check too, and the report and contours of one run are two files.
  expect_refused(run_cli("check " + quote(s.g) + " --obstacle " + quote(s.b) + " --contours " + quote(s.b)),
                 {s.b}, s);
  expect_refused(run_cli("check " + quote(s.g) + " --report " + quote(s.g)), {s.g}, s);
  expect_refused(run_cli("info " + quote(s.g) + " " + quote(s.b) + " --report " + quote(s.b) + " --overwrite"),
                 {"--report " + s.b, "the input " + s.b}, s);
  const std::string both = s.dir.file("both.txt");
  expect_refused(run_cli(s.fix("--report " + quote(both) + " --contours " + quote(both))), {both}, s);
  EXPECT_FALSE(fs::exists(both));
}

TEST(OutputSafety, PinFileIsNeverWritten) {
  Scene s;
  const std::string pins = s.dir.file("pins.txt");
  write_text(pins, "0\n");
  expect_refused(run_cli(s.fix("--pin " + quote(pins) + " --report " + quote(pins))), {pins}, s);
  EXPECT_EQ(read_text(pins), "0\n");
}

TEST(OutputSafety, ExistingReportOrContoursNeedOverwrite) {
  Scene s;
  const std::string report = s.dir.file("r.json");
  write_text(report, "keep\n");
  expect_refused(run_cli(s.fix("--report " + quote(report))), {report}, s);
  EXPECT_EQ(read_text(report), "keep\n");
  auto r = run_cli("check " + quote(s.g) + " --obstacle " + quote(s.b) + " --contours " + quote(report));
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(read_text(report), "keep\n");
  r = run_cli("info " + quote(s.g) + " --report " + quote(report));
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(read_text(report), "keep\n");
  r = run_cli("info " + quote(s.g) + " --report " + quote(report) + " --overwrite");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(nlohmann::json::parse(read_text(report), nullptr, false).is_discarded());
  r = run_cli(s.fix("--report " + quote(report) + " --overwrite"));
  EXPECT_TRUE(testing::intersection_free(r.exit_code)) << r.err;  // written and clean
  EXPECT_EQ(nlohmann::json::parse(read_text(report))["command"], "fix");
}

// The .mtl that assimp's OBJ exporter writes next to the output, and the .bin of a .gltf output.
TEST(OutputSafety, SideFilesOfTheOutputNeedOverwrite) {
  Scene s;
  const std::string g = s.dir.file("g.gltf"), b = s.dir.file("b.gltf");
  write_gltf(g, "g.bin", kGarmentPoints);
  write_gltf(b, "b.bin", kBodyPoints);
  const std::string mtl = s.dir.file("out.mtl");
  write_text(mtl, "keep\n");
  const std::string fix = "fix " + quote(g) + " --obstacle " + quote(b) + " -o " + quote(s.out);
  expect_refused(run_cli(fix), {mtl, s.out}, s);
  EXPECT_EQ(read_text(mtl), "keep\n");

  fs::create_directory(s.dir.file("e"));
  const std::string e = s.dir.file("e/e.gltf"), bin = s.dir.file("e/e.bin");
  write_text(bin, "keep\n");
  auto r = run_cli("fix " + quote(g) + " --obstacle " + quote(b) + " -o " + quote(e));
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find(bin), std::string::npos) << r.err;
  EXPECT_EQ(read_text(bin), "keep\n");
  EXPECT_FALSE(fs::exists(e));

  // With --overwrite both are replaced, and the outputs read back.
  r = run_cli(fix + " --overwrite");
  EXPECT_TRUE(testing::intersection_free(r.exit_code)) << r.err;  // written and clean
  EXPECT_NE(read_text(mtl), "keep\n");
  r = run_cli("fix " + quote(g) + " --obstacle " + quote(b) + " -o " + quote(e) + " --overwrite");
  EXPECT_TRUE(testing::intersection_free(r.exit_code)) << r.err;  // written and clean
  EXPECT_NE(read_text(bin), "keep\n");
}

// A side file of the output that is a side file of an input (the input's buffer) is refused
// even with --overwrite, and so is a --report on an input's side file.
TEST(OutputSafety, SideFilesOfTheInputsAreNeverWritten) {
  Scene s;
  const std::string g = s.dir.file("g.gltf"), b = s.dir.file("b.gltf");
  write_gltf(g, "shared.bin", kGarmentPoints);
  write_gltf(b, "b.bin", kBodyPoints);
  const std::string before = read_text(s.dir.file("shared.bin"));
  const std::string shared = s.dir.file("shared.gltf");
  auto r = run_cli("fix " + quote(g) + " --obstacle " + quote(b) + " -o " + quote(shared) + " --overwrite");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find(s.dir.file("shared.bin")), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(shared));
  r = run_cli("check " + quote(g) + " --obstacle " + quote(b) + " --report " + quote(s.dir.file("b.bin")) +
              " --overwrite");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(read_text(s.dir.file("shared.bin")), before);
  // An OBJ's material library.
  write_text(s.g, std::string("mtllib g.mtl\n") + kGarment);
  write_text(s.dir.file("g.mtl"), "newmtl a\n");
  r = run_cli("fix " + quote(s.g) + " --obstacle " + quote(s.b) + " -o " + quote(s.out) + " --contours " +
              quote(s.dir.file("g.mtl")) + " --overwrite");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(read_text(s.dir.file("g.mtl")), "newmtl a\n");
  EXPECT_FALSE(fs::exists(s.out));
}

// Found before the repair: exit 4 and nothing written, not the repair's 5 hidden behind it.
TEST(OutputSafety, MissingReportFolderIsFoundBeforeAnyWork) {
  Scene s;
  const std::string report = s.dir.file("no/such/dir/r.json");
  expect_refused(run_cli(s.fix("--report " + quote(report))), {"--report " + report}, s);
  expect_refused(run_cli(s.fix("--contours " + quote(s.dir.file("no/c.obj")))), {"--contours " + s.dir.file("no/c.obj")}, s);
  const auto r = run_cli("check " + quote(s.g) + " --report " + quote(report));
  EXPECT_EQ(r.exit_code, 4) << r.err;
}

TEST(OutputSafety, UnwritableFolderIsRefused) {
  if (::geteuid() == 0) GTEST_SKIP() << "root writes into any folder";
  Scene s;
  fs::create_directory(s.dir.file("ro"));
  fs::permissions(s.dir.file("ro"), fs::perms::owner_read | fs::perms::owner_exec);
  const std::string report = s.dir.file("ro/r.json");
  expect_refused(run_cli(s.fix("--report " + quote(report))), {report}, s);
  fs::permissions(s.dir.file("ro"), fs::perms::owner_all);
}

TEST(OutputSafety, SymlinksAndDotDotAreResolved) {
  Scene s;
  const std::string link = s.dir.file("link.obj");
  fs::create_symlink(s.g, link);
  expect_refused(run_cli(s.fix("--report " + quote(link) + " --overwrite")), {link, s.g}, s);
  // -o through a symlink to the obstacle.
  const std::string to_body = s.dir.file("body-link.obj");
  fs::create_symlink(s.b, to_body);
  auto r = run_cli("fix " + quote(s.g) + " --obstacle " + quote(s.b) + " -o " + quote(to_body) + " --overwrite");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(read_text(s.b), kBody);
  // A symlinked folder, and `..`.
  fs::create_directory_symlink(s.dir.path(), s.dir.file("same"));
  fs::create_directory(s.dir.file("sub"));
  for (const std::string& alias : {s.dir.file("same/g.obj"), s.dir.file("sub/../g.obj")})
    expect_refused(run_cli(s.fix("--report " + quote(alias) + " --overwrite")), {alias}, s);
  // The report and the output through two names of one file that does not exist yet.
  expect_refused(run_cli(s.fix("--report " + quote(s.dir.file("same/out.obj")))), {s.out}, s);
}

TEST(OutputSafety, HardLinksAreResolved) {
  Scene s;
  const std::string hard = s.dir.file("hard.obj");
  fs::create_hard_link(s.b, hard);
  expect_refused(run_cli(s.fix("--contours " + quote(hard) + " --overwrite")), {hard, s.b}, s);
  const auto r =
      run_cli("fix " + quote(s.g) + " --obstacle " + quote(s.b) + " -o " + quote(hard) + " --overwrite");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(read_text(s.b), kBody);
}

TEST(OutputSafety, StdoutCombinations) {
  Scene s;
  // Both on stdout cannot be told apart: refused before any work.
  expect_refused(run_cli(s.fix("--report - --contours -")), {"--report -", "--contours -"}, s);
  auto r = run_cli("check " + quote(s.g) + " --obstacle " + quote(s.b) + " --report - --contours -");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_TRUE(r.out.empty());
  // The contours alone on stdout: nothing else there, the report in its file.
  const std::string report = s.dir.file("r.json");
  r = run_cli("check " + quote(s.g) + " --obstacle " + quote(s.b) + " --contours - --report " + quote(report));
  EXPECT_EQ(r.exit_code, 5) << r.err;
  EXPECT_EQ(r.out.find("status:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\nl "), std::string::npos) << r.out;
  EXPECT_EQ(nlohmann::json::parse(read_text(report))["command"], "check");
  // A mesh never goes to stdout.
  r = run_cli("fix " + quote(s.g) + " --obstacle " + quote(s.b) + " -o -");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_TRUE(r.out.empty());
  // The report alone on stdout.
  r = run_cli(s.fix("--report -"));
  EXPECT_TRUE(testing::intersection_free(r.exit_code)) << r.err;  // written and clean
  EXPECT_EQ(nlohmann::json::parse(r.out)["command"], "fix");
}

}  // namespace
}  // namespace untangle
