// The assimp module (issue 24): OBJ and OFF never load it, a file that needs it loads it once, a
// missing or stale module is one clear line with the exit code of the file concerned, and no
// executable links libassimp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/assimp_module.h"
#include "scene_files.h"
#include "test_support.h"
#include "untangle/error.h"
#include "untangle/formats.h"
#include "untangle/read_meshes.h"
#include "untangle/version.h"
#include "untangle/write_meshes.h"

namespace untangle::testing {
namespace {

namespace fs = std::filesystem;

// Sets an environment variable for the CLI processes a test starts, restoring it afterwards.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

constexpr const char* kNoModule = "/nonexistent/libuntangle_assimp.so";

std::string command_output(const std::string& command) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  pclose(pipe);
  return out;
}

std::size_t lines(const std::string& text) {
  std::size_t n = 0;
  for (char c : text) n += c == '\n' ? 1 : 0;
  return n;
}

// A plain OFF copy of `mesh`'s triangles.
void write_off(const Mesh& mesh, const std::string& path) {
  std::ostringstream s;
  s.precision(17);
  s << "OFF\n" << mesh.positions.size() << " " << mesh.triangles.size() << " 0\n";
  for (const auto& p : mesh.positions) s << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (const auto& t : mesh.triangles) s << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  write_text(path, s.str());
}

const std::string kPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kTrianglePly = kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
// Past the prechecks, refused by assimp's validation (in the module).
const std::string kOutOfRangePly = kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 99\n";
const std::string kCorruptFbx = std::string("Kaydara FBX Binary  \0\x1a\0\xe8\x1c\0\0garbagegarbagegarbage", 48);
const std::string kTruncatedFbx = "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n\tFBXHeaderVersion: 1003\n";

// Every command on OBJ and OFF files, with a module that cannot be loaded: any attempt to load it
// would fail the command, so each success shows that the path never asked for it.
TEST(AssimpModule, ObjAndOffNeverLoadIt) {
  TempDir dir;
  const SceneFiles files = write_scene(scenes::sheet_on_spikes(), dir);
  const std::string sheet_off = dir.file("sheet.off"), body_off = dir.file("body.off");
  write_off(read_meshes(files.movable[0], Role::kMovable).front(), sheet_off);
  write_off(read_meshes(files.obstacles[0], Role::kObstacle).front(), body_off);
  const ScopedEnv no_module("UNTANGLE_ASSIMP_MODULE", kNoModule);

  RunResult r = run_cli("info " + quote(files.movable[0]) + " " + quote(files.obstacles[0]));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("check" + files.inputs_args() + " --report " + quote(dir.file("check.json")));
  EXPECT_EQ(r.exit_code, 5) << r.err;
  r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("fixed.obj")));
  EXPECT_TRUE(intersection_free(r.exit_code)) << r.out << r.err;
  r = run_cli("check " + quote(dir.file("fixed.obj")) + " --obstacle " + quote(files.obstacles[0]));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("fix " + quote(sheet_off) + " --obstacle " + quote(body_off) + " -o " +
              quote(dir.file("fixed.off")) + " --preview " + quote(dir.path().string()));
  EXPECT_TRUE(intersection_free(r.exit_code)) << r.out << r.err;
  r = run_cli("render" + files.inputs_args() + " -o " + quote(dir.file("scene.png")) +
              " --contours --inside --size 64x48");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("simulate --example ball --frames 2 --output-dir " + quote(dir.file("sim")));
  EXPECT_NE(r.exit_code, 3) << r.err;
  EXPECT_NE(r.exit_code, 4) << r.err;
  EXPECT_EQ(r.err.find("assimp module"), std::string::npos) << r.err;

  // --version says why it cannot name assimp's version, and still succeeds.
  r = run_cli("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find(std::string("assimp unknown (the assimp module could not be loaded: ") +
                       kNoModule + ": no such file)"),
            std::string::npos)
      << r.out;
}

// In this process: the library's OBJ and OFF paths (reading, writing, what writing would lose,
// whether it can write) leave the module unloaded.
TEST(AssimpModule, LibraryObjAndOffPathsLeaveItUnloaded) {
  if (assimp_module::loaded()) GTEST_SKIP() << "an earlier test in this process loaded it";
  TempDir dir;
  const SceneFiles files = write_scene(scenes::sheet_on_spikes(), dir);
  Mesh sheet = read_meshes(files.movable[0], Role::kMovable).front();
  write_off(sheet, dir.file("sheet.off"));
  const Mesh off = read_meshes(dir.file("sheet.off"), Role::kMovable).front();
  sheet.positions[0][2] += 0.25;
  write_meshes(files.movable[0], dir.file("out.obj"), {&sheet});
  write_meshes(dir.file("sheet.off"), dir.file("out.off"), {&off});
  EXPECT_EQ(read_meshes(dir.file("out.obj"), Role::kMovable).front().positions, sheet.positions);
  EXPECT_EQ(export_loss(files.movable[0], dir.file("out.obj")), "");
  EXPECT_TRUE(can_write(dir.file("out.obj")));
  EXPECT_TRUE(can_write(dir.file("out.off")));
  EXPECT_TRUE(side_files_of_output(files.movable[0], dir.file("out.obj")).empty());
  EXPECT_FALSE(assimp_module::loaded());

  // A PLY needs it: loaded once, on demand.
  write_text(dir.file("tri.ply"), kTrianglePly);
  EXPECT_EQ(read_meshes(dir.file("tri.ply"), Role::kMovable).front().triangles.size(), 1u);
  EXPECT_TRUE(assimp_module::loaded());
}

// A missing module: one line naming the file that needed it, the exit code of that file (3 for
// an input, 4 for an output), never a crash; `formats` needs it too.
TEST(AssimpModule, MissingModuleIsOneLineNamingTheFile) {
  TempDir dir;
  const SceneFiles files = write_scene(scenes::sheet_on_spikes(), dir);
  write_text(dir.file("tri.ply"), kTrianglePly);
  const ScopedEnv no_module("UNTANGLE_ASSIMP_MODULE", kNoModule);
  const std::string why =
      std::string("needs assimp, but the assimp module could not be loaded: ") + kNoModule +
      ": no such file";

  RunResult r = run_cli("check " + quote(dir.file("tri.ply")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find(dir.file("tri.ply") + ": " + why), std::string::npos) << r.err;

  // An OFF input may be written as PLY, which needs the module.
  write_off(read_meshes(files.movable[0], Role::kMovable).front(), dir.file("sheet.off"));
  r = run_cli("fix " + quote(dir.file("sheet.off")) + " --obstacle " + quote(files.obstacles[0]) +
              " -o " + quote(dir.file("out.ply")));
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find(dir.file("out.ply") + ": " + why), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.file("out.ply")));
  // An OBJ input is never written as PLY: told so, without the module.
  r = run_cli("fix" + files.inputs_args() + " -o " + quote(dir.file("out.ply")));
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find(dir.file("out.ply") + ": an OBJ input is written as OBJ"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir.file("out.ply")));

  r = run_cli("formats");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("the assimp module could not be loaded"), std::string::npos) << r.err;
}

// A module of another build is refused before any of its functions is called: beside a copy of
// the binary (looked for first) a module of another interface version, then one whose types
// have other sizes; a copy alone finds the build folder's module.
TEST(AssimpModule, CopiedBinaryFindsTheBuildsModuleAndRefusesAStaleOne) {
  TempDir dir;
  const std::string copy = dir.file("untangle");
  fs::copy_file(UNTANGLE_BINARY, copy);
  fs::permissions(copy, fs::perms::owner_all);
  write_text(dir.file("tri.ply"), kTrianglePly);
  auto run_copy = [&](const std::string& args) {
    const std::string out = command_output("'" + copy + "' " + args + " 2>&1");
    return out;
  };
  EXPECT_NE(run_copy("--version").find("\nassimp 5."), std::string::npos) << run_copy("--version");

  const std::string beside = dir.file("libuntangle_assimp.so");
  fs::copy_file(UNTANGLE_STALE_VERSION_MODULE, beside);
  std::string out = run_copy("check " + quote(dir.file("tri.ply")));
  EXPECT_NE(out.find(dir.file("tri.ply") + ": needs assimp, but the assimp module could not be loaded: " +
                     beside + ": interface version " +
                     std::to_string(assimp_module::kInterfaceVersion + 1) + ", this untangle needs " +
                     std::to_string(assimp_module::kInterfaceVersion) + " (a module of another build)"),
            std::string::npos)
      << out;
  EXPECT_EQ(lines(out), 1u) << out;
  EXPECT_NE(run_copy("--version").find("\nassimp unknown ("), std::string::npos);

  fs::copy_file(UNTANGLE_STALE_SIZES_MODULE, beside, fs::copy_options::overwrite_existing);
  out = run_copy("check " + quote(dir.file("tri.ply")) + " 2>&1; echo status $?");
  EXPECT_NE(out.find(beside + ": built with other type sizes ("), std::string::npos) << out;
  EXPECT_NE(out.find("status 3"), std::string::npos) << out;
}

// Errors thrown in the module reach the CLI's handlers as before: the same one line and exit 3
// (the messages of the build that linked assimp into the executable), and in this process the
// same untangle::Error.
TEST(AssimpModule, CorruptPlyAndFbxKeepTheirMessages) {
  TempDir dir;
  write_text(dir.file("range.ply"), kOutOfRangePly);
  write_text(dir.file("bad.fbx"), kCorruptFbx);
  write_text(dir.file("truncated.fbx"), kTruncatedFbx);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {dir.file("range.ply"),
       "cannot read mesh: Validation failed: aiMesh::mFaces[0]::mIndices[2] is out of range"},
      {dir.file("bad.fbx"),
       "cannot read mesh: FBX-Tokenize (offset 0x1f) block offset is out of range"},
      {dir.file("truncated.fbx"),
       "cannot read mesh: FBX-Parser (TOK_DATA, line 4, col 0) unexpected end of file, expected "
       "bracket, comma or key"},
  };
  for (const auto& [file, why] : cases) {
    const std::string message = file + ": " + why;
    const RunResult r = run_cli("check " + quote(file));
    EXPECT_EQ(r.exit_code, 3) << file;
    EXPECT_EQ(r.err, "error: " + message + "\n");
    try {
      read_meshes(file, Role::kMovable);
      ADD_FAILURE() << file << " was read";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::kUnreadableInput);
      EXPECT_EQ(e.path(), file);
      EXPECT_EQ(std::string(e.what()), message);
    }
  }
}

// No executable of the build links libassimp (or what it brings: draco, minizip); the module does.
TEST(AssimpModule, ExecutablesDoNotLinkAssimp) {
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  for (const std::string& file : {std::string(UNTANGLE_BINARY), self}) {
    const std::string deps = command_output("ldd '" + file + "'");
    ASSERT_NE(deps.find("libc.so"), std::string::npos) << file << ":\n" << deps;
    for (const char* library : {"assimp", "draco", "minizip"})
      EXPECT_EQ(deps.find(library), std::string::npos) << file << " links " << library << ":\n" << deps;
  }
  const std::string module = assimp_module::search_path().back();
  EXPECT_NE(command_output("ldd '" + module + "'").find("libassimp"), std::string::npos) << module;
}

}  // namespace
}  // namespace untangle::testing
