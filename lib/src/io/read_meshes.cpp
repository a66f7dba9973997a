// Reading meshes: OBJ and plain OFF by our own readers, every other format through the assimp
// module (io/assimp_module.h), loaded only then.
#include "untangle/read_meshes.h"

#include <pthread.h>

#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

#include "io/assimp_module.h"
#include "io/prechecks.h"
#include "io/read_obj.h"
#include "io/read_off.h"
#include "untangle/error.h"

namespace untangle {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw Error(ExitCode::kUnreadableInput, path, message);
}

// What a reader's running out of memory means for a file that fits on disk.
constexpr const char* kTooManyElements =
    "file claims more elements than it holds, or is corrupt (the reader ran out of memory)";

// Names go into JSON reports, which must be valid UTF-8; files carry Latin-1 names or garbage.
// Invalid sequences become U+FFFD.
std::string valid_utf8(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  std::size_t i = 0;
  while (i < s.size()) {
    const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = b(i);
    std::size_t n = 0;
    unsigned char lo = 0x80, hi = 0xBF;  // range of the first continuation byte
    if (c < 0x80) {
      n = 1;
    } else if (c >= 0xC2 && c <= 0xDF) {
      n = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      n = 3;
      if (c == 0xE0) lo = 0xA0;  // overlong
      if (c == 0xED) hi = 0x9F;  // surrogates
    } else if (c >= 0xF0 && c <= 0xF4) {
      n = 4;
      if (c == 0xF0) lo = 0x90;  // overlong
      if (c == 0xF4) hi = 0x8F;  // above U+10FFFF
    }
    bool ok = n > 0 && i + n <= s.size();
    for (std::size_t k = 1; ok && k < n; ++k) {
      const unsigned char d = b(i + k);
      ok = k == 1 ? (d >= lo && d <= hi) : (d >= 0x80 && d <= 0xBF);
    }
    if (ok) {
      out.append(s, i, n);
      i += n;
    } else {
      out += "\xEF\xBF\xBD";
      ++i;
    }
  }
  return out;
}

// Runs `work` on a thread with a large stack and hands back its result or its exception.
// assimp's importers, its validation and aiNode's destructor recurse once per level of nesting in
// the file, and a hostile file needs only a few bytes per level: a default thread stack is soon
// exhausted. The stack is reserved address space, touched only as deep as used.
template <class Result, class Work>
Result on_large_stack(Work work) {
  constexpr std::size_t kStack = std::size_t{512} << 20;
  struct Job {
    Work* work;
    Result result;
    std::exception_ptr error;
  } job{&work, Result(), nullptr};
  auto run = [](void* arg) -> void* {
    Job& j = *static_cast<Job*>(arg);
    try {
      j.result = (*j.work)();
    } catch (...) {
      j.error = std::current_exception();
    }
    return nullptr;
  };
  pthread_attr_t attributes;
  pthread_t thread;
  bool started = false;
  if (pthread_attr_init(&attributes) == 0) {
    started = pthread_attr_setstacksize(&attributes, kStack) == 0 &&
              pthread_create(&thread, &attributes, run, &job) == 0;
    pthread_attr_destroy(&attributes);
  }
  if (!started) return work();  // no room for the stack: read on this thread
  pthread_join(thread, nullptr);
  if (job.error) std::rethrow_exception(job.error);
  return std::move(job.result);
}

}  // namespace

void precheck_for_assimp(const std::string& path, const std::string& extension,
                         std::uint64_t size) {
  const std::string start = file_start(path, 16);
  // The checks go by content, not only by extension: when the importer of a known extension
  // refuses a file, assimp tries every importer on its content, so a PLY file named .glb reaches
  // the PLY importer (which loops forever on a header without end_header). The one exception is
  // .stl: the STL importer takes every .stl file, and a binary STL's free 80-byte header may start
  // with anything.
  const bool stl = extension == ".stl";
  if (extension == ".ply" || (!stl && lower(start.substr(0, 3)) == "ply")) {
    precheck_ply(path, size);
  }
  if (extension == ".glb" || (!stl && start.compare(0, 4, "glTF") == 0)) {
    precheck_glb(path, size);
  } else if (extension == ".gltf") {
    precheck_gltf(path, size);
  }
  std::string_view first(start);
  const std::string keyword = lower(std::string(next_token(first)));
  // "off" anywhere in the first word: assimp also takes "OFF3" (counts glued to it) for OFF.
  if (extension == ".off" || (!stl && keyword.find("off") != std::string::npos)) {
    precheck_off(path, size);
  }
}

std::vector<Mesh> read_meshes(const std::string& path, Role role) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) fail(path, "no such file");
  if (std::filesystem::is_directory(status)) fail(path, "is a directory, not a mesh file");
  // A FIFO or device would block or never end: only regular files are read.
  if (!std::filesystem::is_regular_file(status)) fail(path, "not a regular file");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  {
    std::ifstream probe(path, std::ios::binary);
    if (ec || !probe) fail(path, "cannot open for reading");
    if (size == 0 || probe.peek() == std::ifstream::traits_type::eof()) {
      fail(path, "empty file (0 bytes); untangle needs surface meshes");
    }
  }

  const std::string extension = lower(std::filesystem::path(path).extension().string());
  std::vector<Mesh> meshes;
  try {
    if (extension == ".obj") {
      meshes.push_back(read_obj(path, role));
    } else if (extension == ".off" && is_plain_off(path)) {
      meshes.push_back(read_off(path, role));
    } else {
      meshes = on_large_stack<std::vector<Mesh>>([&] {
        precheck_for_assimp(path, extension, size);
        return assimp_module::get(path, ExitCode::kUnreadableInput).read(path, role);
      });
    }
  } catch (const std::bad_alloc&) {
    fail(path, kTooManyElements);
  } catch (const std::length_error&) {
    fail(path, kTooManyElements);
  }
  for (Mesh& mesh : meshes) {
    mesh.name = valid_utf8(mesh.name);
    mesh.node_name = valid_utf8(mesh.node_name);
    for (std::string& group : mesh.group_names) group = valid_utf8(group);
    for (std::string& object : mesh.group_objects) object = valid_utf8(object);
  }
  return meshes;
}

}  // namespace untangle