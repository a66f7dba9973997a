// Hostile input: truncated, corrupt and oversized-header files, point clouds, and every file of
// Debian's assimp-testmodels end in a result or one clean error line; never a crash, a hang or a
// huge allocation, and never an output file.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "test_support.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::read_text;
using testing::TempDir;
using testing::write_text;

// Every run is limited in time (seconds, by timeout(1)) and in address space (KiB, by ulimit -v):
// a reader that hangs or believes a header claiming billions of elements fails the test instead
// of the machine.
constexpr int kTimeLimit = 20;
constexpr long kMemoryLimitKiB = 4000000;

struct Outcome {
  int exit_code = -1;  // the CLI's exit code, or -1 when it did not exit by itself
  int signal = 0;      // the signal that ended it, if any
  bool timed_out = false;
  std::string out, err;
  double seconds = 0;
};

// Runs `untangle ARGS` under both limits; `scratch` is a path prefix for the captured streams.
// Safe to call from several threads at once.
Outcome run_limited(const std::string& args, const std::string& scratch) {
  const std::string out = scratch + ".out", err = scratch + ".err";
#if defined(__SANITIZE_ADDRESS__)
  // ASan reserves terabytes of address space for its shadow, so no ulimit -v: its allocator
  // refuses the same sizes instead (std::bad_alloc), and a process whose resident memory passes
  // the limit is stopped. Leaks inside assimp's error paths are assimp's; leaks of untangle's own
  // code are still reported.
  const std::string suppressions = scratch + ".lsan";
  write_text(suppressions, "leak:libassimp.so\n");
  const std::string mb = std::to_string(kMemoryLimitKiB / 1024);
  const std::string limit =
      "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}max_allocation_size_mb=" + mb +
      ":hard_rss_limit_mb=" + mb +
      ":allocator_may_return_null=1\" LSAN_OPTIONS=\"print_suppressions=0:"
      "suppressions=" +
      suppressions + "\" ";
#else
  const std::string limit = "ulimit -v " + std::to_string(kMemoryLimitKiB) + " && ";
#endif
  const std::string command = limit + "exec timeout -k 5 " + std::to_string(kTimeLimit) + " '" +
                              UNTANGLE_BINARY + "' " + args + " >'" + out + "' 2>'" + err +
                              "' </dev/null";
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  Outcome r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (WIFSIGNALED(status)) {
    r.signal = WTERMSIG(status);
  } else if (WIFEXITED(status)) {
    const int code = WEXITSTATUS(status);
    // timeout(1): 124 when the time ran out, 128 + n when the command died of signal n.
    if (code == 124 || code == 137) {
      r.timed_out = true;
    } else if (code > 128) {
      r.signal = code - 128;
    } else {
      r.exit_code = code;
    }
  }
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

// Runs every command on a few workers (the suite is sized for two cores) and returns the
// outcomes in command order.
std::vector<Outcome> run_all(const std::vector<std::string>& args, const TempDir& scratch) {
  std::vector<Outcome> outcomes(args.size());
  std::atomic<std::size_t> next{0};
  const unsigned workers = std::clamp(std::thread::hardware_concurrency(), 2u, 4u);
  std::vector<std::thread> threads;
  for (unsigned w = 0; w < workers; ++w) {
    threads.emplace_back([&] {
      for (std::size_t i = next++; i < args.size(); i = next++) {
        outcomes[i] = run_limited(args[i], scratch.file("run" + std::to_string(i)));
      }
    });
  }
  for (std::thread& t : threads) t.join();
  return outcomes;
}

std::size_t line_count(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

// Why an outcome is not acceptable for reading `path`, or "" when it is: a result (0 clean,
// 5 intersecting) or exit 3 with one line "error: PATH: ..." on stderr, readable, nothing on
// stdout.
std::string problem(const std::string& path, const Outcome& r) {
  if (r.timed_out) return "no answer within " + std::to_string(kTimeLimit) + " s";
  if (r.signal != 0) return "killed by signal " + std::to_string(r.signal) + " " + r.err;
  if (r.exit_code == 0 || r.exit_code == 5) return "";
  if (r.exit_code != 3) return "exit " + std::to_string(r.exit_code) + ": " + r.err;
  if (line_count(r.err) != 1)
    return "exit 3 but " + std::to_string(line_count(r.err)) + " lines: " + r.err;
  if (r.err.rfind("error: " + path + ": ", 0) != 0)
    return "message does not start 'error: FILE: ': " + r.err;
  for (const char* raw : {"bad_alloc", "std::", "length_error", "max_size()"}) {
    if (r.err.find(raw) != std::string::npos) return "unreadable message: " + r.err;
  }
  if (!r.out.empty()) return "exit 3 with output on stdout: " + r.out;
  return "";
}

// ---- the tetrahedron every generated file holds: closed, outward, clean ----

constexpr float kVertices[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
constexpr int kFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

void put_u16(std::string& s, std::uint16_t v) {
  for (int k = 0; k < 2; ++k) s += static_cast<char>((v >> (8 * k)) & 0xFF);
}

void put_u32(std::string& s, std::uint32_t v, bool big_endian = false) {
  for (int k = 0; k < 4; ++k) {
    const int shift = big_endian ? 8 * (3 - k) : 8 * k;
    s += static_cast<char>((v >> shift) & 0xFF);
  }
}

void put_f32(std::string& s, float f, bool big_endian = false) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &f, 4);
  put_u32(s, bits, big_endian);
}

std::string obj_text() {
  std::ostringstream s;
  for (const auto& v : kVertices) s << "v " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
  for (const auto& f : kFaces) s << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
  return s.str();
}

// `keyword` OFF is read by untangle's own reader, COFF (with colours) by assimp.
std::string off_text(const std::string& keyword) {
  std::ostringstream s;
  s << keyword << "\n4 4 6\n";
  for (const auto& v : kVertices) {
    s << v[0] << ' ' << v[1] << ' ' << v[2] << (keyword == "COFF" ? " 1 1 1 1" : "") << '\n';
  }
  for (const auto& f : kFaces) s << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return s.str();
}

std::string ply_header(const std::string& format, std::size_t vertices, std::size_t faces) {
  return "ply\nformat " + format + " 1.0\ncomment tetrahedron\nelement vertex " +
         std::to_string(vertices) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
         std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
}

std::string ply_ascii() {
  std::ostringstream s;
  s << ply_header("ascii", 4, 4);
  for (const auto& v : kVertices) s << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
  for (const auto& f : kFaces) s << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return s.str();
}

std::string ply_binary(bool big_endian) {
  std::string s = ply_header(big_endian ? "binary_big_endian" : "binary_little_endian", 4, 4);
  for (const auto& v : kVertices) {
    for (float c : v) put_f32(s, c, big_endian);
  }
  for (const auto& f : kFaces) {
    s += '\3';
    for (int i : f) put_u32(s, static_cast<std::uint32_t>(i), big_endian);
  }
  return s;
}

std::string stl_ascii() {
  std::ostringstream s;
  s << "solid tetrahedron\n";
  for (const auto& f : kFaces) {
    s << " facet normal 0 0 0\n  outer loop\n";
    for (int i : f) {
      s << "   vertex " << kVertices[i][0] << ' ' << kVertices[i][1] << ' ' << kVertices[i][2]
        << '\n';
    }
    s << "  endloop\n endfacet\n";
  }
  s << "endsolid tetrahedron\n";
  return s.str();
}

std::string stl_binary() {
  std::string s = "binary tetrahedron";
  s.resize(80, ' ');
  put_u32(s, 4);
  for (const auto& f : kFaces) {
    for (int k = 0; k < 3; ++k) put_f32(s, 0.0f);
    for (int i : f) {
      for (float c : kVertices[i]) put_f32(s, c);
    }
    put_u16(s, 0);
  }
  return s;
}

// Positions (48 bytes) then 16-bit indices (24 bytes).
std::string gltf_buffer() {
  std::string s;
  for (const auto& v : kVertices) {
    for (float c : v) put_f32(s, c);
  }
  for (const auto& f : kFaces) {
    for (int i : f) put_u16(s, static_cast<std::uint16_t>(i));
  }
  return s;
}

nlohmann::json gltf_document(const std::string& uri) {
  nlohmann::json buffer = {{"byteLength", 72}};
  if (!uri.empty()) buffer["uri"] = uri;
  return {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"buffers", {buffer}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
        {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 24}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", 4},
         {"type", "VEC3"},
         {"min", {0, 0, 0}},
         {"max", {1, 1, 1}}},
        {{"bufferView", 1}, {"componentType", 5123}, {"count", 12}, {"type", "SCALAR"}}}},
  };
}

std::string base64(const std::string& bytes) {
  static const char* const kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t chunk = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      v = (v << 8) | (k < chunk ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    }
    for (std::size_t k = 0; k < 4; ++k)
      out += k <= chunk ? kAlphabet[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

std::string gltf_embedded() {
  return gltf_document("data:application/octet-stream;base64," + base64(gltf_buffer())).dump();
}

std::string glb() {
  std::string json = gltf_document("").dump();
  while (json.size() % 4 != 0) json += ' ';
  const std::string bin = gltf_buffer();
  std::string s = "glTF";
  put_u32(s, 2);
  put_u32(s, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  put_u32(s, static_cast<std::uint32_t>(json.size()));
  s += "JSON";
  s += json;
  put_u32(s, static_cast<std::uint32_t>(bin.size()));
  s += std::string("BIN\0", 4);
  s += bin;
  return s;
}

struct Format {
  std::string name;                       // file name, extension included
  std::string bytes;                      // a valid tetrahedron
  std::string companion_name, companion;  // a second file it refers to (glTF's .bin), if any
};

std::vector<Format> formats() {
  return {
      {"tet.obj", obj_text(), "", ""},
      {"tet.off", off_text("OFF"), "", ""},
      {"tet_colour.off", off_text("COFF"), "", ""},
      {"tet_ascii.ply", ply_ascii(), "", ""},
      {"tet_le.ply", ply_binary(false), "", ""},
      {"tet_be.ply", ply_binary(true), "", ""},
      {"tet_ascii.stl", stl_ascii(), "", ""},
      {"tet_binary.stl", stl_binary(), "", ""},
      {"tet.gltf", gltf_document("tet.bin").dump(), "tet.bin", gltf_buffer()},
      {"tet_embedded.gltf", gltf_embedded(), "", ""},
      {"tet.glb", glb(), "", ""},
  };
}

// One generated input: the file to read and what was done to it.
struct Case {
  std::string path;
  std::string what;
};

// Writes `bytes` as `name` (and its companion) into a fresh folder of `root`.
std::string write_case(const TempDir& root, std::size_t index, const std::string& name,
                       const std::string& bytes, const std::string& companion_name = "",
                       const std::string* companion = nullptr) {
  const fs::path folder = root.path() / ("case" + std::to_string(index));
  fs::create_directories(folder);
  write_text((folder / name).string(), bytes);
  if (companion != nullptr) write_text((folder / companion_name).string(), *companion);
  return (folder / name).string();
}

// Truncations (every length up to 48 bytes, then 16 spread over the rest) and corruptions (one
// to three bytes replaced by values that upset parsers), seeded: the same cases every run.
std::vector<Case> damaged(const TempDir& root, const Format& format, std::mt19937& rng,
                          std::size_t& index, const std::string& bytes, bool damage_companion) {
  std::vector<Case> cases;
  const std::string label = format.name + (damage_companion ? " (its .bin)" : "");
  auto add = [&](const std::string& data, const std::string& what) {
    const std::string* companion = format.companion_name.empty() ? nullptr : &format.companion;
    const std::string path =
        damage_companion
            ? write_case(root, index++, format.name, format.bytes, format.companion_name, &data)
            : write_case(root, index++, format.name, data, format.companion_name, companion);
    cases.push_back({path, label + " " + what});
  };
  std::set<std::size_t> lengths;
  for (std::size_t n = 1; n < std::min<std::size_t>(bytes.size(), 48); ++n) lengths.insert(n);
  for (std::size_t k = 1; k < 16; ++k) lengths.insert(bytes.size() * k / 16);
  lengths.insert(bytes.size() - 1);
  for (std::size_t n : lengths) {
    if (n > 0 && n < bytes.size())
      add(bytes.substr(0, n), "truncated to " + std::to_string(n) + " bytes");
  }
  const unsigned char kValues[] = {0x00, 0xFF, 0x7F, 0x80, '9', '-', ' ', '\n', '[', '"'};
  for (int k = 0; k < 24; ++k) {
    std::string data = bytes;
    std::string what = "with bytes replaced:";
    const int changes = 1 + static_cast<int>(rng() % 3);
    for (int c = 0; c < changes; ++c) {
      const std::size_t at = rng() % data.size();
      const unsigned char value = rng() % 3 == 0
                                      ? static_cast<unsigned char>(data[at] ^ (1u << (rng() % 8)))
                                      : kValues[rng() % sizeof(kValues)];
      data[at] = static_cast<char>(value);
      what += " @" + std::to_string(at) + "=" + std::to_string(value);
    }
    add(data, what);
  }
  return cases;
}

// Runs `check` on every case and lists the unacceptable outcomes in one failure.
void expect_clean_outcomes(const std::vector<Case>& cases, const TempDir& scratch) {
  std::vector<std::string> args;
  for (const Case& c : cases) args.push_back("check " + quote(c.path));
  const std::vector<Outcome> outcomes = run_all(args, scratch);
  std::ostringstream problems;
  std::size_t bad = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string why = problem(cases[i].path, outcomes[i]);
    if (!why.empty()) {
      ++bad;
      problems << "\n  " << cases[i].what << " (" << cases[i].path << "): " << why;
    }
  }
  EXPECT_EQ(bad, 0u) << bad << " of " << cases.size() << " inputs:" << problems.str();
}

// ---- 1. truncated and corrupt files ----

TEST(HostileInput, GeneratedTetrahedraAreClean) {
  TempDir dir;
  std::size_t index = 0;
  std::vector<Case> cases;
  for (const Format& f : formats()) {
    const std::string* companion = f.companion_name.empty() ? nullptr : &f.companion;
    cases.push_back(
        {write_case(dir, index++, f.name, f.bytes, f.companion_name, companion), f.name});
  }
  std::vector<std::string> args;
  for (const Case& c : cases) args.push_back("check " + quote(c.path));
  const std::vector<Outcome> outcomes = run_all(args, dir);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    // Without this the damaged variants below would test nothing.
    EXPECT_EQ(outcomes[i].exit_code, 0) << cases[i].what << ": " << outcomes[i].err;
  }
}

TEST(HostileInput, TruncatedAndCorruptFilesFailCleanly) {
  TempDir dir;
  std::mt19937 rng(20240605);
  std::size_t index = 0;
  std::vector<Case> cases;
  for (const Format& f : formats()) {
    for (Case& c : damaged(dir, f, rng, index, f.bytes, false)) cases.push_back(std::move(c));
    if (!f.companion_name.empty()) {
      for (Case& c : damaged(dir, f, rng, index, f.companion, true)) cases.push_back(std::move(c));
      // The .bin missing altogether.
      cases.push_back({write_case(dir, index++, f.name, f.bytes), f.name + " without its .bin"});
    }
  }
  expect_clean_outcomes(cases, dir);
}

// ---- 2. headers that claim more than the file holds ----

struct Bomb {
  const char* name;
  std::string bytes;
  const char* says;  // a word the message must contain ("" for assimp's own words)
};

std::vector<Bomb> bombs() {
  const std::string three_vertices = "0 0 0\n1 0 0\n0 1 0\n";
  std::string stl = std::string(80, ' ');
  put_u32(stl, 4000000000u);
  stl += std::string(100, '\0');
  std::string ply_binary_vertices =
      ply_header("binary_little_endian", 3000000000u, 1) + std::string(100, '\0');
  std::string ply_binary_list = ply_header("binary_little_endian", 3, 1) + std::string(36, '\0');
  ply_binary_list += '\xff';  // uchar list size 255 > what follows
  ply_binary_list += std::string(12, '\0');
  std::string ply_uint_list =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uint int vertex_indices\nend_header\n" +
      std::string(36, '\0');
  put_u32(ply_uint_list, 4000000000u);
  ply_uint_list += std::string(12, '\0');
  std::string glb_json = glb();
  glb_json[12] = glb_json[13] = glb_json[14] = glb_json[15] = '\x7f';  // JSON chunk of ~2 GB
  std::string glb_bin = glb();
  const std::size_t bin_header =
      20 + (static_cast<unsigned char>(glb_bin[12]) | static_cast<unsigned char>(glb_bin[13]) << 8);
  glb_bin[bin_header + 3] = '\x7f';  // binary chunk of ~2 GB
  nlohmann::json accessor =
      gltf_document("data:application/octet-stream;base64," + base64(gltf_buffer()));
  accessor["accessors"][0]["count"] = 3000000000u;
  nlohmann::json buffer =
      gltf_document("data:application/octet-stream;base64," + base64(gltf_buffer()));
  buffer["buffers"][0]["byteLength"] = 3000000000u;
  return {
      {"vertices.ply", ply_header("ascii", 3000000000u, 1) + three_vertices + "3 0 1 2\n",
       "claims"},
      {"faces.ply", ply_header("ascii", 3, 3000000000u) + three_vertices + "3 0 1 2\n", "claims"},
      {"list.ply", ply_header("ascii", 3, 1) + three_vertices + "4000000000 0 1 2\n", "claims"},
      {"vertices_binary.ply", ply_binary_vertices, "claims"},
      {"list_binary.ply", ply_binary_list, "claims"},
      {"uint_list_binary.ply", ply_uint_list, "claims"},
      {"vertices.off", "OFF\n3000000000 1 0\n" + three_vertices, "claims"},
      {"faces.off", "OFF\n3 3000000000 0\n" + three_vertices + "3 0 1 2\n", "claims"},
      {"corners.off", "OFF\n3 1 0\n" + three_vertices + "18446744073709551615 0 1 2\n", ""},
      {"vertices_colour.off", "COFF\n3000000000 1 0\n0 0 0 1 1 1 1\n", "claims"},
      {"faces_normal.off", "NOFF\n3 3000000000 0\n0 0 0 0 0 1\n", "claims"},
      {"facets.stl", stl, ""},
      {"json_chunk.glb", glb_json, "claims"},
      {"bin_chunk.glb", glb_bin, "claims"},
      {"accessor.gltf", accessor.dump(), ""},
      {"buffer.gltf", buffer.dump(), ""},
  };
}

TEST(HostileInput, HugeClaimedCountsFailWithoutAllocating) {
  TempDir dir;
  std::vector<Case> cases;
  std::vector<std::string> args;
  const std::vector<Bomb> all = bombs();
  for (const Bomb& b : all) {
    cases.push_back({dir.file(b.name), b.name});
    write_text(cases.back().path, b.bytes);
    args.push_back("check " + quote(cases.back().path));
  }
  const std::vector<Outcome> outcomes = run_all(args, dir);
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Outcome& r = outcomes[i];
    EXPECT_EQ(r.exit_code, 3) << all[i].name << ": " << r.err;
    EXPECT_EQ(problem(cases[i].path, r), "") << all[i].name;
    EXPECT_NE(r.err.find(all[i].says), std::string::npos) << all[i].name << ": " << r.err;
  }
}

// glTF lets small files describe large data: accessors without a buffer view (implicit zeros),
// sparse parts, one accessor used by thousands of primitives or morph targets, one mesh placed by
// thousands of nodes. Each is bounded before anything is allocated.
TEST(HostileInput, GltfReuseAndImplicitDataAreBounded) {
  TempDir dir;
  // A strip of 99,999 vertices (33,333 triangles without indices): 1.2 MB of positions.
  const std::uint32_t n = 99999;
  std::string positions;
  for (std::uint32_t i = 0; i < n; ++i) {
    put_f32(positions, static_cast<float>(i % 2));
    put_f32(positions, static_cast<float>(i / 2));
    put_f32(positions, 0.0f);
  }
  write_text(dir.file("strip.bin"), positions);
  const nlohmann::json strip = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
      {"buffers", {{{"byteLength", positions.size()}, {"uri", "strip.bin"}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteLength", positions.size()}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", n},
         {"type", "VEC3"},
         {"min", {0, 0, 0}},
         {"max", {1, n / 2, 0}}}}},
  };
  std::map<std::string, nlohmann::json> files;
  files["morph_targets.gltf"] = strip;
  files["morph_targets.gltf"]["meshes"][0]["primitives"][0]["targets"] =
      std::vector<nlohmann::json>(2000, {{"POSITION", 0}});
  files["primitives.gltf"] = strip;
  files["primitives.gltf"]["meshes"][0]["primitives"] =
      std::vector<nlohmann::json>(2000, {{"attributes", {{"POSITION", 0}}}});
  files["instances.gltf"] = strip;
  files["instances.gltf"]["nodes"] = std::vector<nlohmann::json>(1000, {{"mesh", 0}});
  for (int i = 0; i < 1000; ++i) files["instances.gltf"]["scenes"][0]["nodes"][i] = i;
  files["zeros.gltf"] = strip;
  files["zeros.gltf"]["accessors"][0].erase("bufferView");
  files["zeros.gltf"]["accessors"][0]["count"] = 300000000;
  files["sparse_count.gltf"] = strip;
  files["sparse_count.gltf"]["bufferViews"].push_back({{"buffer", 0}, {"byteLength", 8}});
  files["sparse_count.gltf"]["accessors"][0]["sparse"] = {
      {"count", 3000000000u},
      {"indices", {{"bufferView", 1}, {"componentType", 5125}}},
      {"values", {{"bufferView", 0}}}};
  files["sparse_view.gltf"] = files["sparse_count.gltf"];
  files["sparse_view.gltf"]["accessors"][0]["sparse"]["count"] = 4;  // 16 bytes of indices in 8

  std::vector<std::string> names, args;
  for (const auto& [name, document] : files) {
    names.push_back(name);
    write_text(dir.file(name), document.dump());
    args.push_back("check " + quote(dir.file(name)));
  }
  const std::map<std::string, std::string> says = {
      {"instances.gltf", "expand"},         {"morph_targets.gltf", "over and over"},
      {"primitives.gltf", "over and over"}, {"sparse_count.gltf", "sparse part claims"},
      {"sparse_view.gltf", "reaches past"}, {"zeros.gltf", "no data behind"}};
  const std::vector<Outcome> outcomes = run_all(args, dir);
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(outcomes[i].exit_code, 3) << names[i] << ": " << outcomes[i].err;
    EXPECT_EQ(problem(dir.file(names[i]), outcomes[i]), "") << names[i];
    EXPECT_NE(outcomes[i].err.find(says.at(names[i])), std::string::npos)
        << names[i] << ": " << outcomes[i].err;
  }
}

// `fix` reads everything before it writes anything: a bad input leaves no file behind.
// A face that names a vertex the file does not have is an error in every format, also where
// assimp drops the face and only logs it (glTF 2, COFF): read as clean, the mesh would have a hole.
TEST(HostileInput, FaceIndicesOutOfRangeFailInEveryFormat) {
  TempDir dir;
  const std::string four_vertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  std::string buffer = gltf_buffer();
  buffer[48 + 2 * 5] = 99;  // the last corner of the second face: vertex 99 of 4
  const std::vector<std::pair<std::string, std::string>> files = {
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 99\n"},
      {"range.off", "OFF\n4 2 0\n" + four_vertices + "3 0 1 2\n3 0 1 99\n"},
      {"range_colour.off", "COFF\n4 2 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n"
                           "0 0 1 1 1 1 1\n3 0 1 2\n3 0 1 99\n"},
      {"range.ply", ply_header("ascii", 4, 2) + four_vertices + "3 0 1 2\n3 0 1 99\n"},
      {"range.gltf",
       gltf_document("data:application/octet-stream;base64," + base64(buffer)).dump()},
  };
  std::vector<Case> cases;
  std::vector<std::string> args;
  for (const auto& [name, bytes] : files) {
    cases.push_back({dir.file(name), name});
    write_text(cases.back().path, bytes);
    args.push_back("check " + quote(cases.back().path));
  }
  const std::vector<Outcome> outcomes = run_all(args, dir);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    EXPECT_EQ(outcomes[i].exit_code, 3) << cases[i].what << ": " << outcomes[i].err;
    EXPECT_EQ(problem(cases[i].path, outcomes[i]), "") << cases[i].what;
    const std::string err = outcomes[i].err;
    EXPECT_TRUE(err.find("range") != std::string::npos || err.find("refers to vertex") != std::string::npos)
        << cases[i].what << ": " << err;
  }
}

TEST(HostileInput, FixOnBadInputLeavesNothingBehind) {
  TempDir dir;
  const std::vector<Bomb> all = bombs();
  for (const Bomb& b : {all[0], all[6], all[12]}) {
    const std::string input = dir.file(b.name);
    write_text(input, b.bytes);
    const std::string output = dir.file(std::string("fixed_") + b.name);
    const Outcome r = run_limited("fix " + quote(input) + " -o " + quote(output), dir.file("run"));
    EXPECT_EQ(r.exit_code, 3) << b.name << ": " << r.err;
    std::vector<std::string> left;
    for (const auto& entry : fs::directory_iterator(dir.path())) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("fixed_", 0) == 0 || name.rfind(".untangle", 0) == 0) left.push_back(name);
    }
    EXPECT_TRUE(left.empty()) << b.name << ": left " << left.front();
  }
}

// Nesting a recursive reader would follow to the end of the stack: a glTF node chain, JSON
// brackets, a Collada node chain (read on a thread with a large stack).
TEST(HostileInput, DeepNestingDoesNotOverflowTheStack) {
  TempDir dir;
  nlohmann::json chain =
      gltf_document("data:application/octet-stream;base64," + base64(gltf_buffer()));
  const int depth = 30000;
  chain["nodes"] = nlohmann::json::array();
  for (int i = 0; i < depth; ++i) chain["nodes"].push_back({{"children", {i + 1}}});
  chain["nodes"].push_back({{"mesh", 0}});
  write_text(dir.file("chain.gltf"), chain.dump());
  write_text(dir.file("brackets.gltf"), std::string(1000000, '[') + std::string(1000000, ']'));
  std::string dae =
      "<?xml version=\"1.0\"?><COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" "
      "version=\"1.4.1\"><library_geometries><geometry id=\"g\"><mesh><source id=\"p\">"
      "<float_array id=\"pa\" count=\"9\">0 0 0 1 0 0 0 1 0</float_array><technique_common>"
      "<accessor source=\"#pa\" count=\"3\" stride=\"3\"><param name=\"X\" type=\"float\"/>"
      "<param name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/></accessor>"
      "</technique_common></source><vertices id=\"v\"><input semantic=\"POSITION\" "
      "source=\"#p\"/></vertices><triangles count=\"1\"><input semantic=\"VERTEX\" source=\"#v\" "
      "offset=\"0\"/><p>0 1 2</p></triangles></mesh></geometry></library_geometries>"
      "<library_visual_scenes><visual_scene id=\"s\">";
  for (int i = 0; i < depth; ++i) dae += "<node id=\"n" + std::to_string(i) + "\">";
  dae += "<instance_geometry url=\"#g\"/>";
  for (int i = 0; i < depth; ++i) dae += "</node>";
  dae +=
      "</visual_scene></library_visual_scenes><scene><instance_visual_scene url=\"#s\"/>"
      "</scene></COLLADA>";
  write_text(dir.file("chain.dae"), dae);
  expect_clean_outcomes({{dir.file("chain.gltf"), "glTF node chain"},
                         {dir.file("brackets.gltf"), "JSON brackets"},
                         {dir.file("chain.dae"), "Collada node chain"}},
                        dir);
}

// A FIFO would block a reader forever; a folder is not a mesh.
TEST(HostileInput, SpecialFilesFailFast) {
  TempDir dir;
  ASSERT_EQ(::mkfifo(dir.file("pipe.obj").c_str(), 0600), 0);
  fs::create_directories(dir.file("folder.obj"));
  for (const char* name : {"pipe.obj", "folder.obj"}) {
    const Outcome r = run_limited("check " + quote(dir.file(name)), dir.file("run"));
    EXPECT_EQ(r.exit_code, 3) << name << ": " << r.err;
    EXPECT_EQ(problem(dir.file(name), r), "") << name;
  }
}

// Names from files go into JSON reports: bytes that are not UTF-8 must not break them.
TEST(HostileInput, NamesThatAreNotUtf8StillGiveAReport) {
  TempDir dir;
  std::string stl = stl_ascii();
  stl.replace(6, 11, "t\xe9tra\xff\x80");  // "solid tetrahedron": Latin-1 and stray bytes
  write_text(dir.file("latin1.stl"), stl);
  std::string obj = "g K\xf6rper\n" + obj_text();
  write_text(dir.file("latin1.obj"), obj);
  for (const char* name : {"latin1.stl", "latin1.obj"}) {
    const Outcome r = run_limited("info " + quote(dir.file(name)) + " --report -", dir.file("run"));
    EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_FALSE(nlohmann::json::parse(r.out, nullptr, false).is_discarded()) << name << r.out;
  }
}

// ---- 4. point clouds and line-only files ----

TEST(HostileInput, PointCloudsAndLinesHaveNoTriangles) {
  const std::string three = "0 0 0\n1 0 0\n0 1 0\n";
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  std::string points_binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + xyz + "end_header\n";
  for (int v = 0; v < 3; ++v) {
    for (float c : kVertices[v]) put_f32(points_binary, c);
  }
  std::string no_facets = std::string(80, ' ');
  put_u32(no_facets, 0);
  nlohmann::json points =
      gltf_document("data:application/octet-stream;base64," + base64(gltf_buffer()));
  points["meshes"][0]["primitives"][0]["mode"] = 0;
  nlohmann::json lines = points;
  lines["meshes"][0]["primitives"][0]["mode"] = 1;
  const std::pair<const char*, std::string> files[] = {
      {"points.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + xyz + "end_header\n" + three},
      {"points_binary.ply", points_binary},
      {"lines.ply", ply_header("ascii", 3, 2) + three + "2 0 1\n2 1 2\n"},
      {"edges.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + xyz +
                        "element edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n" +
                        three + "0 1\n1 2\n"},
      {"points.off", "OFF\n3 0 0\n" + three},
      {"lines.off", "OFF\n3 2 0\n" + three + "2 0 1\n2 1 2\n"},
      {"points_colour.off", "COFF\n3 0 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n"},
      {"lines_colour.off",
       "COFF\n3 2 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n2 0 1\n2 1 2\n"},
      {"no_facets.stl", "solid nothing\nendsolid nothing\n"},
      {"no_facets_binary.stl", no_facets},
      {"points.gltf", points.dump()},
      {"lines.gltf", lines.dump()},
  };
  TempDir dir;
  std::vector<std::string> args;
  for (const auto& [name, bytes] : files) {
    write_text(dir.file(name), bytes);
    args.push_back("check " + quote(dir.file(name)));
  }
  const std::vector<Outcome> outcomes = run_all(args, dir);
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string path = dir.file(files[i].first);
    EXPECT_EQ(outcomes[i].exit_code, 3) << files[i].first << ": " << outcomes[i].err;
    EXPECT_EQ(problem(path, outcomes[i]), "") << files[i].first;
    EXPECT_NE(outcomes[i].err.find("no triangles"), std::string::npos)
        << files[i].first << ": " << outcomes[i].err;
  }
}

// ---- regression files: testdata/hostile ----

// Each file there once crashed, hung or allocated without bound (testdata/hostile/README.md);
// all are broken, so each must give exit 3. They double as a seed corpus for fuzzing the loader.
TEST(HostileInput, RegressionFilesFailCleanly) {
  const fs::path folder = fs::path(UNTANGLE_SOURCE_DIR) / "testdata" / "hostile";
  ASSERT_TRUE(fs::is_directory(folder)) << folder;
  TempDir dir;
  std::vector<Case> cases;
  std::vector<std::string> args;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file() || entry.path().filename() == "README.md") continue;
    cases.push_back({entry.path().string(), entry.path().filename().string()});
  }
  std::sort(cases.begin(), cases.end(),
            [](const Case& a, const Case& b) { return a.path < b.path; });
  ASSERT_FALSE(cases.empty());
  for (const Case& c : cases) args.push_back("check " + quote(c.path));
  const std::vector<Outcome> outcomes = run_all(args, dir);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    EXPECT_EQ(outcomes[i].exit_code, 3) << cases[i].what << ": " << outcomes[i].err;
    EXPECT_EQ(problem(cases[i].path, outcomes[i]), "") << cases[i].what;
  }
}

// ---- 3. Debian's assimp-testmodels ----

constexpr const char* kTestModels = "/usr/share/assimp/models";

// Every file of the package but its images (textures of the models) goes through `check`:
// models, invalid models, and the odd readme, shader or .bin that no reader claims.
TEST(AssimpTestModels, EveryFileGivesAResultOrACleanError) {
  if (!fs::is_directory(kTestModels)) {
    GTEST_SKIP() << kTestModels << " is missing: install Debian's assimp-testmodels package "
                 << "(scripts/setup.sh does) to run untangle over its files";
  }
  const std::set<std::string> images = {".png", ".jpg", ".jpeg", ".tga", ".bmp", ".dds",
                                        ".gif", ".tif", ".tiff", ".hdr", ".ktx", ".pcx"};
  std::vector<std::string> paths;
  for (const auto& entry : fs::recursive_directory_iterator(kTestModels)) {
    if (!entry.is_regular_file()) continue;
    std::string extension = entry.path().extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (images.count(extension) == 0) paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  ASSERT_FALSE(paths.empty());
  std::vector<std::string> args;
  for (const std::string& p : paths) args.push_back("check " + quote(p));
  TempDir dir;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Outcome> outcomes = run_all(args, dir);
  const double total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::map<int, std::size_t> by_exit;
  std::ostringstream problems;
  std::size_t bad = 0, slowest = 0;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    ++by_exit[outcomes[i].exit_code];
    if (outcomes[i].seconds > outcomes[slowest].seconds) slowest = i;
    const std::string why = problem(paths[i], outcomes[i]);
    if (!why.empty()) {
      ++bad;
      problems << "\n  " << paths[i] << ": " << why;
    }
  }
  EXPECT_EQ(bad, 0u) << bad << " of " << paths.size() << " files:" << problems.str();
  // Numbers for the log, not limits: speed is measured by benchmarks, never asserted by a test.
  std::cout << "[ info     ] " << paths.size() << " files in " << total << " s;";
  for (const auto& [code, count] : by_exit) std::cout << " exit " << code << ": " << count << ";";
  std::cout << " slowest " << paths[slowest] << " (" << outcomes[slowest].seconds << " s)\n";
}

}  // namespace
}  // namespace untangle
