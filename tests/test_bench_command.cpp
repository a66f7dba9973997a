// `untangle bench` end to end: the quick suite as JSON (every stage timed, the counts agree with
// an independent in-process repair of the same generated scene), the plots (CSV and SVG), the
// --data pairing, the human tables, and usage and data errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "scenes/scenes.h"
#include "test_support.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"

namespace untangle {
namespace {

using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;

const char* const kStages[] = {"load", "detect", "contours", "regions", "displace", "write", "verify", "total"};

// One run of `bench --quick --json --repeat 1 --plot DIR --data DIR` shared by the tests below:
// the data folder holds one small garment/body pair (a sheet through a sphere, the body named by
// the garment's prefix) and a garment without a body.
class BenchQuick : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const std::string data = dir_->file("data");
    std::filesystem::create_directories(data + "/garments");
    std::filesystem::create_directories(data + "/bodies");
    const scenes::Scene s = scenes::sheet_through_sphere();
    scenes::write_obj(s.movable[0], data + "/garments/female_sheet.obj");
    scenes::write_obj(s.obstacles[0], data + "/bodies/female_generic.obj");
    scenes::write_obj(s.movable[0], data + "/garments/male_orphan.obj");
    result_ = new testing::RunResult(run_cli("bench --quick --json --repeat 1 --plot " +
                                             quote(dir_->file("plots")) + " --data " + quote(data)));
  }
  static void TearDownTestSuite() {
    delete result_;
    delete dir_;
  }
  static nlohmann::json report() { return nlohmann::json::parse(result_->out); }
  static TempDir* dir_;
  static testing::RunResult* result_;
};
TempDir* BenchQuick::dir_ = nullptr;
testing::RunResult* BenchQuick::result_ = nullptr;

TEST_F(BenchQuick, JsonHasEveryStageForEveryScene) {
  ASSERT_EQ(result_->exit_code, 0) << result_->err;
  const nlohmann::json j = report();  // stdout carries only JSON
  EXPECT_EQ(j["command"], "bench");
  ASSERT_FALSE(j["scenes"].empty());
  std::map<std::string, std::set<std::string>> methods;
  for (const auto& row : j["scenes"]) {
    const std::string where = row["scene"].get<std::string>() + " " + row["method"].get<std::string>();
    methods[row["scene"].get<std::string>()].insert(row["method"].get<std::string>());
    for (const char* stage : kStages) {
      ASSERT_TRUE(row["timing_ms"].contains(stage)) << where << ": no " << stage;
      const double best = row["timing_ms"][stage]["best"], median = row["timing_ms"][stage]["median"];
      EXPECT_GE(best, 0.0) << where << " " << stage;
      EXPECT_LE(best, median) << where << " " << stage;
    }
    EXPECT_GT(row["timing_ms"]["load"]["best"].get<double>(), 0.0) << where << ": load reads files";
    const bool intersection_free = row["crossings_after"] == 0 && row["inside_after"] == 0;
    EXPECT_EQ(row["status"] == "clean" || row["status"] == "distorted", intersection_free) << where;
    if (intersection_free && (row["max_stretch"] > 1.5 || row["flipped_faces"] > 0)) {
      EXPECT_EQ(row["status"], "distorted") << where;
    }
    EXPECT_EQ(row["history"].size(), row["iterations"].get<std::size_t>() + 1) << where;
    EXPECT_EQ(row["history"][0]["crossings"], row["crossings_before"]) << where;
  }
  for (const auto& [scene, m] : methods) EXPECT_EQ(m, (std::set<std::string>{"region", "paper"})) << scene;
  ASSERT_FALSE(j["accuracy"].empty());
  std::set<std::pair<double, double>> settings;
  for (const auto& row : j["accuracy"]) settings.insert({row["clearance"].get<double>(), row["step"].get<double>()});
  EXPECT_EQ(settings.size(), 9u);
}

// The generated scenes' counts against the same scene repaired in this process (no files, no CLI):
// crossings before, iterations and crossings after must match.
TEST_F(BenchQuick, CountsAgreeWithAnIndependentRepair) {
  ASSERT_EQ(result_->exit_code, 0) << result_->err;
  std::map<std::string, scenes::Scene> generated;
  for (const scenes::Scene& s : scenes::named_scenes()) generated[s.name] = s;
  std::size_t checked = 0, clean = 0;
  const nlohmann::json j = report();
  for (const auto& row : j["scenes"]) {
    if (row["source"] != "generated") continue;
    const std::string name = row["scene"];
    ASSERT_EQ(generated.count(name), 1u) << name;
    std::vector<Mesh> meshes = scenes::scene_meshes(generated[name]);
    FixOptions options;
    options.method = row["method"] == "paper" ? FixMethod::kPaper : FixMethod::kRegion;
    const FixResult fixed = fix_meshes(meshes, options);
    DetectOptions detect;
    detect.skip_obstacle_pairs = true;
    const std::size_t after = find_intersections(meshes, detect).counts.crossings;
    const std::string where = name + " " + row["method"].get<std::string>();
    EXPECT_EQ(row["crossings_before"], fixed.before.crossings) << where;
    EXPECT_EQ(row["iterations"], fixed.iterations) << where;
    EXPECT_EQ(row["crossings_after"], after) << where;
    EXPECT_EQ(row["moved_vertices"], fixed.displacement.moved_vertices) << where;
    ++checked;
    clean += after == 0 ? 1 : 0;
  }
  EXPECT_EQ(checked, 8u);  // four quick scenes, two methods
  EXPECT_GT(clean, 0u);
}

TEST_F(BenchQuick, DataFolderPairsGarmentsWithTheirBody) {
  ASSERT_EQ(result_->exit_code, 0) << result_->err;
  const nlohmann::json j = report();
  std::set<std::string> data_scenes;
  for (const auto& row : j["scenes"])
    if (row["source"] == "data") data_scenes.insert(row["scene"]);
  EXPECT_EQ(data_scenes, (std::set<std::string>{"female_sheet", "female_sheet_x1.02"}));
  bool orphan_noted = false;
  for (const auto& note : j["notes"])
    orphan_noted |= note.get<std::string>().find("male_orphan.obj: no body") != std::string::npos;
  EXPECT_TRUE(orphan_noted) << j["notes"].dump();
  // The garment is the generated sheet against the generated sphere: the same counts as the scene.
  std::map<std::string, nlohmann::json> by_key;
  for (const auto& row : j["scenes"]) by_key[row["scene"].get<std::string>() + row["method"].get<std::string>()] = row;
  for (const char* method : {"region", "paper"}) {
    const auto& a = by_key[std::string("female_sheet") + method];
    const auto& b = by_key[std::string("sheet_through_sphere") + method];
    EXPECT_EQ(a["crossings_before"], b["crossings_before"]) << method;
    EXPECT_EQ(a["crossings_after"], b["crossings_after"]) << method;
  }
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  for (std::string f; std::getline(in, f, sep);) fields.push_back(f);
  return fields;
}

TEST_F(BenchQuick, PlotsAreWellFormedCsvAndSvg) {
  ASSERT_EQ(result_->exit_code, 0) << result_->err;
  const nlohmann::json j = report();
  std::map<std::string, std::size_t> records;  // per scene, history records over its methods
  for (const auto& row : j["scenes"]) records[row["scene"]] += row["history"].size();
  for (const auto& [scene, expected_rows] : records) {
    const std::string csv = read_text(dir_->file("plots/" + scene + ".csv"));
    std::istringstream in(csv);
    std::string line;
    ASSERT_TRUE(std::getline(in, line)) << scene;
    EXPECT_EQ(line, "iteration,elapsed_ms,crossings,contour_length,method");
    std::map<std::string, std::pair<int, double>> last;  // per method: iteration, elapsed
    std::size_t rows = 0;
    while (std::getline(in, line)) {
      const std::vector<std::string> f = split(line, ',');
      ASSERT_EQ(f.size(), 5u) << scene << ": " << line;
      ASSERT_TRUE(f[4] == "region" || f[4] == "paper") << line;
      const int iteration = std::stoi(f[0]);
      const double elapsed = std::stod(f[1]);
      EXPECT_GE(std::stod(f[3]), 0.0) << line;
      if (last.count(f[4]) != 0) {
        EXPECT_EQ(iteration, last[f[4]].first + 1) << scene << ": " << line;
        EXPECT_GE(elapsed, last[f[4]].second) << scene << ": elapsed goes back at " << line;
      } else {
        EXPECT_EQ(iteration, 0) << scene;
      }
      last[f[4]] = {iteration, elapsed};
      ++rows;
    }
    EXPECT_EQ(rows, expected_rows) << scene;

    const std::string svg = read_text(dir_->file("plots/" + scene + ".svg"));
    EXPECT_EQ(svg.rfind("<svg", 0), 0u) << scene;
    EXPECT_NE(svg.find("</svg>"), std::string::npos) << scene;
    for (const char* method : {"region", "paper"}) {
      // one polyline per panel (crossings, contour length)
      std::size_t count = 0;
      for (std::size_t at = svg.find(std::string("<polyline class=\"") + method + "\"");
           at != std::string::npos; at = svg.find(std::string("<polyline class=\"") + method + "\"", at + 1))
        ++count;
      EXPECT_EQ(count, 2u) << scene << " " << method;
    }
    for (const char* tag : {"text", "g", "title", "circle"}) {
      std::size_t open = 0, close = 0;
      for (std::size_t at = svg.find(std::string("<") + tag + (tag[1] ? "" : " ")); at != std::string::npos;
           at = svg.find(std::string("<") + tag + (tag[1] ? "" : " "), at + 1))
        ++open;
      for (std::size_t at = svg.find(std::string("</") + tag + ">"); at != std::string::npos;
           at = svg.find(std::string("</") + tag + ">", at + 1))
        ++close;
      EXPECT_EQ(open, close) << scene << ": <" << tag << "> not balanced";
    }
  }
}

TEST(BenchCommand, PrintsTheTables) {
  const testing::RunResult r = run_cli("bench --quick --repeat 1 --method region");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* column : {"scene", "before", "iter", "load", "detect", "contours", "regions", "displace",
                             "write", "verify", "total best/median", "after", "inside", "max/edge", "mean/edge", "edge chg",
                             "stretch", "flips"})
    EXPECT_NE(r.out.find(column), std::string::npos) << column;
  for (const char* scene : {"sheet_through_sphere", "strip_through_sheet", "sheets_corner", "tube_around_body"})
    EXPECT_NE(r.out.find(scene), std::string::npos) << scene;
  EXPECT_NE(r.out.find("clearance"), std::string::npos);
  EXPECT_EQ(r.out.find(" paper "), std::string::npos) << "--method region runs region only";
}

TEST(BenchCommand, UsageAndDataErrors) {
  for (const char* args : {"bench --repeat 0", "bench --repeat", "bench --method fast", "bench --bogus",
                           "bench --threads -1", "bench extra.obj"}) {
    const testing::RunResult r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << args;
  }
  TempDir dir;
  const testing::RunResult missing = run_cli("bench --quick --data " + quote(dir.file("nowhere")));
  EXPECT_EQ(missing.exit_code, 3) << missing.err;
  EXPECT_NE(missing.err.find("nowhere"), std::string::npos) << missing.err;
  std::filesystem::create_directories(dir.file("empty/garments"));
  std::filesystem::create_directories(dir.file("empty/bodies"));
  const testing::RunResult empty = run_cli("bench --quick --data " + quote(dir.file("empty")));
  EXPECT_EQ(empty.exit_code, 3) << empty.err;
}

}  // namespace
}  // namespace untangle
