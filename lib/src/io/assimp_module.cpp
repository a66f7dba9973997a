// Loading the assimp module on first need: where it is looked for, and the checks that refuse a
// module of another build.
#include "io/assimp_module.h"

#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>

namespace untangle::assimp_module {
namespace {

namespace fs = std::filesystem;

// The folder of the executable (or shared object) this library is linked into: dladdr on one of
// its functions, else /proc/self/exe (dladdr names the main program as it was started, which may
// be a relative path).
std::string own_folder() {
  std::error_code ec;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&search_path), &info) != 0 && info.dli_fname != nullptr &&
      info.dli_fname[0] == '/') {
    const fs::path file = fs::weakly_canonical(info.dli_fname, ec);
    if (!ec) return file.parent_path().string();
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

std::string describe(const Sizes& s) {
  return "interface " + std::to_string(s.interface) + ", Mesh " + std::to_string(s.mesh) +
         ", std::string " + std::to_string(s.string) + ", Error " + std::to_string(s.error) +
         ", PlacedMesh " + std::to_string(s.placed_mesh) + ", std::function " +
         std::to_string(s.function) + " bytes";
}

bool operator==(const Sizes& a, const Sizes& b) {
  return a.interface == b.interface && a.mesh == b.mesh && a.string == b.string &&
         a.error == b.error && a.placed_mesh == b.placed_mesh && a.function == b.function;
}

// Loads `file` and checks its interface; "" and `out` set, or why not.
std::string try_load(const std::string& file, const Interface*& out) {
  dlerror();
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    return why != nullptr ? why : file + ": cannot be loaded";
  }
  using Entry = const Interface* (*)();
  auto entry = reinterpret_cast<Entry>(dlsym(handle, kEntryPoint));
  if (entry == nullptr) return file + ": no " + kEntryPoint + " (not an untangle assimp module)";
  const Interface* found = entry();
  if (found == nullptr) return file + ": " + kEntryPoint + " returned nothing";
  // The module stays mapped even when refused: a library it loaded may not be unloadable.
  if (found->version != kInterfaceVersion) {
    return file + ": interface version " + std::to_string(found->version) + ", this untangle needs " +
           std::to_string(kInterfaceVersion) + " (a module of another build)";
  }
  if (!(found->sizes == sizes_here())) {
    return file + ": built with other type sizes (" + describe(found->sizes) + "; here " +
           describe(sizes_here()) + "), a module of another build";
  }
  if (found->build == nullptr || std::strcmp(found->build, kBuild) != 0) {
    return file + ": built by '" + (found->build != nullptr ? found->build : "?") +
           "', this untangle by '" + kBuild + "' (a module of another build)";
  }
  out = found;
  return "";
}

struct State {
  std::mutex mutex;
  const Interface* module = nullptr;
  std::string failure;  // why loading failed (tried once per process)
  bool tried = false;
};

State& state() {
  static State s;
  return s;
}

}  // namespace

std::vector<std::string> search_path() {
  const char* forced = std::getenv("UNTANGLE_ASSIMP_MODULE");
  if (forced != nullptr && forced[0] != '\0') return {forced};  // set and not empty
  std::vector<std::string> paths;
  const std::string own = own_folder();
  if (!own.empty()) paths.push_back((fs::path(own) / kFileName).string());
#ifdef UNTANGLE_ASSIMP_MODULE_DIR
  const std::string built = (fs::path(UNTANGLE_ASSIMP_MODULE_DIR) / kFileName).string();
  if (paths.empty() || paths.front() != built) paths.push_back(built);
#endif
  return paths;
}

const Interface& get(const std::string& path, ExitCode code) {
  State& s = state();
  const std::lock_guard<std::mutex> lock(s.mutex);
  if (s.module == nullptr && !s.tried) {
    s.tried = true;
    // The first place that holds a file is the one: a module there that fails to load or is
    // refused is the error (not hidden by another one further on). When no place holds one, every
    // place is named.
    std::string why;
    for (const std::string& file : search_path()) {
      std::error_code ec;
      if (!fs::exists(file, ec)) {
        why += (why.empty() ? "" : "; ") + file + ": no such file";
        continue;
      }
      why = try_load(file, s.module);
      break;
    }
    if (s.module == nullptr) s.failure = why.empty() ? "no place to look for it" : why;
  }
  if (s.module == nullptr) {
    throw Error(code, path,
                std::string(path.empty() ? "" : "needs assimp, but ") +
                    "the assimp module could not be loaded: " + s.failure);
  }
  return *s.module;
}

bool loaded() {
  State& s = state();
  const std::lock_guard<std::mutex> lock(s.mutex);
  return s.module != nullptr;
}

}  // namespace untangle::assimp_module
