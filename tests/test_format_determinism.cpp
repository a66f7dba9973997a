// Issue 22 §2: the same input gives the same bytes in every writable format, across runs (the
// exporters' clocks) and thread counts.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "test_support.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;
using testing::write_text;

// A garment square (text PLY, so that it can be written in every format) through a body square.
constexpr const char* kGarmentPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n3 0 1 2\n3 0 2 3\n";
constexpr const char* kBody =
    "v -0.5 0.1 -1\nv 0.5 0.1 -1\nv 0.5 0.1 1\nv -0.5 0.1 1\nf 1 2 3\nf 1 3 4\n";

// Every extension untangle writes through assimp (`untangle formats`), OBJ from a non-OBJ input.
constexpr const char* kWritable[] = {"obj", "ply", "stl", "gltf", "glb", "dae", "fbx", "x", "3ds", "x3d", "assbin"};

TEST(FormatDeterminism, SameBytesInEveryWritableFormatAcrossRunsAndThreads) {
  TempDir dir;
  write_text(dir.file("g.ply"), kGarmentPly);
  write_text(dir.file("b.obj"), kBody);
  for (const char* run : {"1", "2"}) fs::create_directory(dir.file(run));
  auto fix = [&](const std::string& run, const std::string& ext, const std::string& threads) {
    const auto r = run_cli("fix " + quote(dir.file("g.ply")) + " --obstacle " + quote(dir.file("b.obj")) +
                           " -o " + quote(dir.file(run + "/o." + ext)) + " -q --threads " + threads);
    EXPECT_EQ(r.exit_code, 0) << ext << ": " << r.err;
  };
  for (const char* ext : kWritable) fix("1", ext, "1");
  // The clocks in FBX and Collada files count seconds.
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  for (const char* ext : kWritable) fix("2", ext, "2");
  std::size_t compared = 0;
  for (const auto& entry : fs::directory_iterator(dir.file("1"))) {
    const fs::path other = fs::path(dir.file("2")) / entry.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_TRUE(read_text(entry.path().string()) == read_text(other.string())) << entry.path().filename();
    ++compared;
  }
  EXPECT_GE(compared, std::size(kWritable));
}

}  // namespace
}  // namespace untangle
