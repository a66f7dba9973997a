// The interface between untangle_lib and the assimp module (libuntangle_assimp.so, issue 24).
// Every call into assimp lives in the module, which the library loads with dlopen the first time
// a file needs it (a format other than OBJ and plain OFF, `untangle formats`, `--version`), so
// that a process that reads and writes only OBJ and OFF never maps libassimp and pays none of its
// start-up cost. Library and module come from one build (same compiler, same flags): C++ types
// cross the boundary, and an untangle::Error thrown in the module reaches the caller unchanged
// (its type is header-only, matched by name). A module from another build is refused by
// `check_interface` before any of its functions is called.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "untangle/error.h"
#include "untangle/mesh.h"

namespace untangle::assimp_module {

// Raised whenever the interface below changes (members, their order or their signatures).
constexpr std::uint32_t kInterfaceVersion = 1;

// The module's one exported symbol: `extern "C" const Interface* untangle_assimp_interface()`.
constexpr const char* kEntryPoint = "untangle_assimp_interface";

// The file name of the module, looked for beside the running executable, then in the build
// folder (UNTANGLE_ASSIMP_MODULE_DIR); the environment variable UNTANGLE_ASSIMP_MODULE, when set
// and not empty, is the one path tried. The first place that holds a file is the one loaded.
constexpr const char* kFileName = "libuntangle_assimp.so";

// One placed mesh of a glTF input as assimp read it (read_meshes order), for the in-place glTF
// writer: which of the file's meshes it is, its positions as stored, and per vertex whether the
// new world position differs from the stored one mapped through the instance's transform, and if
// so the new position mapped back into the mesh's frame (assimp's float arithmetic).
struct PlacedMesh {
  std::size_t mesh_index = 0;
  std::vector<std::array<float, 3>> stored;
  std::vector<std::uint8_t> moved;
  std::vector<std::array<float, 3>> local;  // meaningful where moved
};

// Tries to write the glTF input in place (write_gltf_in_place); false: export with assimp instead.
using PatchInPlace = std::function<bool(const std::vector<PlacedMesh>&)>;

// Animations, skins (meshes with bones) and distinct textures as assimp imports a file.
struct Carried {
  std::size_t animations = 0, skins = 0, textures = 0;
};

struct ImporterInfo {
  std::string name;        // "Stanford Polygon Library"
  std::string extensions;  // space separated, as assimp lists them: "*.ply" or "ply"
};

struct ExporterInfo {
  std::string id;         // "plyb"
  std::string extension;  // "ply"
  std::string description;
};

// The sizes of what crosses the boundary, as the side that compiled them sees them.
struct Sizes {
  std::size_t interface = 0, mesh = 0, string = 0, error = 0, placed_mesh = 0, function = 0;
};

struct Interface {
  std::uint32_t version = 0;  // first, so that any module's version can be read
  Sizes sizes;
  const char* build;  // compiler version and sanitizer flag, compared as text

  // "5.2.5": aiGetVersionMajor/Minor/Patch of the libassimp the module is linked against.
  std::string (*assimp_version)();
  // Every triangle mesh of `path` in world space (read_meshes' contract for assimp formats,
  // after its prechecks). Throws Error(kUnreadableInput) naming `path`.
  std::vector<Mesh> (*read)(const std::string& path, Role role);
  // Re-imports `input`, replaces its positions by `meshes` (read_meshes order) and writes
  // `staged` in the format of its extension; a glTF written as glTF is first offered to
  // `patch_in_place`. Returns the assimp export id used ("" when patched in place), for
  // finish_deterministic_export. Throws Error(kOutputNotWritten) naming `staged`.
  std::string (*write)(const std::string& input, const std::string& staged,
                       const std::string& final_folder, const std::vector<const Mesh*>& meshes,
                       const PatchInPlace& patch_in_place);
  // What assimp imports of `input`; false when it cannot import it.
  bool (*carried)(const std::string& input, Carried& out);
  std::vector<ImporterInfo> (*importers)();
  std::vector<ExporterInfo> (*exporters)();
};

// The sizes and build text of this side of the boundary.
inline Sizes sizes_here() {
  Sizes s;
  s.interface = sizeof(Interface);
  s.mesh = sizeof(Mesh);
  s.string = sizeof(std::string);
  s.error = sizeof(Error);
  s.placed_mesh = sizeof(PlacedMesh);
  s.function = sizeof(PatchInPlace);
  return s;
}

#if defined(__SANITIZE_ADDRESS__)
#define UNTANGLE_ASSIMP_MODULE_SANITIZED " asan"
#else
#define UNTANGLE_ASSIMP_MODULE_SANITIZED ""
#endif
constexpr const char* kBuild = __VERSION__ UNTANGLE_ASSIMP_MODULE_SANITIZED;

// An interface that says what this side was built with, its functions not yet set: where a
// module starts its table.
inline Interface interface_of_this_build() {
  Interface t{};
  t.version = kInterfaceVersion;
  t.sizes = sizes_here();
  t.build = kBuild;
  return t;
}

// Library side (lib/src/io/assimp_module.cpp).

// The module's interface, loaded on first use (thread-safe; never unloaded). Throws
// Error(code, path, "... the assimp module could not be loaded: <why>") when the module is
// missing, not loadable (dlerror's text) or from another build; `path` is the file that needed it
// ("" for `untangle formats`).
const Interface& get(const std::string& path, ExitCode code);

// Whether the module has been loaded by this process.
bool loaded();

// Every path tried, in order (for messages and tests).
std::vector<std::string> search_path();

}  // namespace untangle::assimp_module
