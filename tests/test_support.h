// Shared helpers of the tests: running the CLI, temporary folders, small inline meshes.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace untangle::testing {

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// A fresh folder under the system temp folder, removed on destruction.
class TempDir {
 public:
  TempDir() {
    static std::mt19937_64 rng(std::random_device{}());
    path_ = std::filesystem::temp_directory_path() /
            ("untangle-test-" + std::to_string(rng()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Runs the built untangle CLI with `args` (already shell-quoted), capturing stdout and stderr.
inline RunResult run_cli(const std::string& args) {
  TempDir dir;
  const std::string out = dir.file("out.txt"), err = dir.file("err.txt");
  const std::string command = std::string("'") + UNTANGLE_BINARY + "' " + args + " >'" + out +
                              "' 2>'" + err + "' </dev/null";
  const int status = std::system(command.c_str());
  RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

inline std::string quote(const std::string& s) { return "'" + s + "'"; }

// What fix says of written files free of crossings and inside vertices: exit 0 and status clean,
// or exit 6 and status distorted when a mesh's shape is beyond the quality bounds. Tests of other
// properties (bytes, determinism, formats, exactness) accept both; tests/test_quality.cpp judges
// the bounds.
inline bool intersection_free(int fix_exit_code) { return fix_exit_code == 0 || fix_exit_code == 6; }
inline bool intersection_free(const std::string& fix_status) {
  return fix_status == "clean" || fix_status == "distorted";
}

}  // namespace untangle::testing
