// The CLI end to end: exit codes, one-line errors naming the file, reports, contour files.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>

#include "test_support.h"

namespace untangle {
namespace {

using testing::quote;
using testing::run_cli;
using testing::TempDir;
using testing::write_text;

// Two unit squares (two triangles each) crossing at right angles through each other's middle.
constexpr const char* kSquareA =
    "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n";
constexpr const char* kSquareB =
    "v -0.5 0.1 -1\nv 0.5 0.1 -1\nv 0.5 0.1 1\nv -0.5 0.1 1\nf 1 2 3\nf 1 3 4\n";
constexpr const char* kSquareFar =
    "v -1 -1 5\nv 1 -1 5\nv 1 1 5\nv -1 1 5\nf 1 2 3\nf 1 3 4\n";

std::size_t line_count(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

struct BadInput {
  const char* name;
  const char* content;  // nullptr: the file does not exist
};

// Every kind of unreadable input: exit 3, one line on stderr naming the file, nothing on stdout.
TEST(Cli, BadInputGivesOneLineAndExitThree) {
  const BadInput cases[] = {
      {"missing.obj", nullptr},
      {"empty.obj", ""},
      {"unknown.xyz", "this is not a mesh\n"},
      {"points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"},
      {"lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n"},
      {"nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
      {"inf.obj", "v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n"},
      {"truncated.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"},
  };
  TempDir dir;
  for (const BadInput& c : cases) {
    const std::string path = dir.file(c.name);
    if (c.content != nullptr) write_text(path, c.content);
    for (const char* command : {"check", "info"}) {
      const auto r = run_cli(std::string(command) + " " + quote(path));
      EXPECT_EQ(r.exit_code, 3) << c.name << ": " << r.err;
      EXPECT_EQ(line_count(r.err), 1u) << c.name << ": " << r.err;
      EXPECT_NE(r.err.find(path), std::string::npos) << c.name << ": " << r.err;
      EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
      EXPECT_TRUE(r.out.empty()) << c.name;
    }
  }
}

TEST(Cli, CheckExitCodesAndReport) {
  TempDir dir;
  write_text(dir.file("a.obj"), kSquareA);
  write_text(dir.file("b.obj"), kSquareB);
  write_text(dir.file("far.obj"), kSquareFar);

  const auto clean = run_cli("check " + quote(dir.file("a.obj")) + " --obstacle " +
                             quote(dir.file("far.obj")));
  EXPECT_EQ(clean.exit_code, 0) << clean.err;
  EXPECT_NE(clean.out.find("status: clean"), std::string::npos);

  const auto hit = run_cli("check " + quote(dir.file("a.obj")) + " " + quote(dir.file("b.obj")) +
                           " --report - --contours " + quote(dir.file("c.obj")));
  EXPECT_EQ(hit.exit_code, 5) << hit.err;
  const nlohmann::json report = nlohmann::json::parse(hit.out);  // stdout carries only JSON
  EXPECT_EQ(report["schema_version"], 13);
  const std::string version = run_cli("--version").out;  // "untangle X.Y.Z" first
  EXPECT_EQ("untangle " + report["untangle_version"].get<std::string>(), version.substr(0, version.find('\n')));
  EXPECT_EQ(report["command"], "check");
  EXPECT_EQ(report["status"], "intersecting");
  ASSERT_EQ(report["meshes"].size(), 2u);
  for (const char* key : {"path", "name", "role", "vertices", "faces", "boundary_loops"})
    EXPECT_TRUE(report["meshes"][0].contains(key)) << key;
  EXPECT_EQ(report["meshes"][0]["role"], "movable");
  const auto& before = report["before"];
  for (const char* key : {"crossings", "triangle_pairs", "contours", "contour_length", "tracks",
                          "pairs", "loop_vertices", "non_separating"})
    EXPECT_TRUE(before.contains(key)) << key;
  for (const char* key : {"CL", "BB", "BI", "II"}) EXPECT_TRUE(before["tracks"].contains(key));
  for (const char* key : {"CL/CL", "BB/II", "BI/BI", "self"}) EXPECT_TRUE(before["pairs"].contains(key));
  for (const char* key : {"load", "detect", "contours", "total"})
    EXPECT_TRUE(report["timing_ms"].contains(key)) << key;

  // Square B (x in [-0.5, 0.5], z in [-1, 1]) passes through the middle of A: one contour from
  // one vertical edge of B to the other, inside A — BB on B, II on A; A's edges are not crossed.
  EXPECT_EQ(before["contours"], 1);
  EXPECT_EQ(before["pairs"]["BB/II"], 1);
  ASSERT_EQ(report["contours"].size(), 1u);
  const auto& contour = report["contours"][0];
  EXPECT_EQ(contour["closed"], false);
  const auto types = contour["types"];
  const auto meshes = contour["meshes"];
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(types[k], meshes[k] == 1 ? "BB" : "II");
  }
  EXPECT_NEAR(contour["length"].get<double>(), 1.0, 1e-12);  // from x = -0.5 to 0.5 at y = 0.1

  const std::string obj = testing::read_text(dir.file("c.obj"));
  EXPECT_NE(obj.find("o contour_0_"), std::string::npos);
  EXPECT_NE(obj.find("\nl 1 2"), std::string::npos);
}

TEST(Cli, ReportToFileAndInfo) {
  TempDir dir;
  write_text(dir.file("a.obj"), kSquareA);
  const auto r = run_cli("info " + quote(dir.file("a.obj")) + " --report " + quote(dir.file("r.json")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("boundary loops 1"), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(testing::read_text(dir.file("r.json")));
  EXPECT_EQ(j["command"], "info");
  EXPECT_EQ(j["meshes"][0]["triangles"], 2);
  EXPECT_EQ(j["meshes"][0]["vertices"], 4);
  EXPECT_EQ(j["meshes"][0]["welded_vertices"], 4);
  EXPECT_EQ(j["meshes"][0]["closed"], false);
}

TEST(Cli, ReportIntoMissingFolderIsExitFour) {
  TempDir dir;
  write_text(dir.file("a.obj"), kSquareA);
  const auto r = run_cli("check " + quote(dir.file("a.obj")) + " --report " +
                         quote(dir.file("no/such/folder/r.json")));
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(line_count(r.err), 1u) << r.err;
}

TEST(Cli, UsageErrorsAreExitTwo) {
  EXPECT_EQ(run_cli("").exit_code, 2);
  EXPECT_EQ(run_cli("check").exit_code, 2);
  EXPECT_EQ(run_cli("check a.obj --no-such-option").exit_code, 2);
  EXPECT_EQ(run_cli("check a.obj --threads -3").exit_code, 2);
  EXPECT_EQ(run_cli("--help").exit_code, 0);
}

// The command line reserves 512 MiB of address space for its heap at start (app/process_memory.h;
// man page, NOTES). A limit on address space below that (ulimit -v) only turns the reserve off:
// the same check gives the same verdict and the same report, and a fix the same bytes.
TEST(Cli, AnAddressSpaceLimitBelowTheHeapReserveChangesNothing) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space; no ulimit -v under it";
#else
  const std::filesystem::path data =
      std::filesystem::path(UNTANGLE_SOURCE_DIR) / "testdata" / "makehuman";
  const std::string garment = quote((data / "male_casualsuit04.obj").string());
  const std::string body = quote((data / "male_generic.obj").string());
  TempDir dir;
  const auto run = [&](const std::string& prefix, const std::string& name) {
    const std::string out = dir.file(name + ".obj"), err = dir.file(name + ".err");
    const std::string command = prefix + "'" + UNTANGLE_BINARY + "' fix " + garment +
                                " --obstacle " + body + " -o " + quote(out) + " -q 2>" +
                                quote(err) + " </dev/null";
    const int status = std::system(command.c_str());
    EXPECT_EQ(testing::read_text(err), "") << name;
    return std::make_pair(WIFEXITED(status) ? WEXITSTATUS(status) : -1, testing::read_text(out));
  };
  const auto plain = run("", "plain");
  const auto limited = run("ulimit -v 400000 && ", "limited");  // 400 MB, under the reserve
  EXPECT_TRUE(testing::intersection_free(plain.first)) << plain.first;
  EXPECT_EQ(limited.first, plain.first);
  EXPECT_FALSE(plain.second.empty());
  EXPECT_TRUE(limited.second == plain.second) << "the written garments differ";
#endif
}

}  // namespace
}  // namespace untangle
