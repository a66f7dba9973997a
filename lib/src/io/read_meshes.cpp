// Reading meshes through assimp: world-space triangles, vertex order kept, polygons fanned.
#include "untangle/read_meshes.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <pthread.h>

#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <new>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

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

// assimp's messages end in newlines and sometimes repeat the path; keep one clean line.
std::string one_line(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// assimp reports exceptions of the standard library thrown inside an importer by their what():
// "std::bad_alloc", "vector::_M_default_append", "cannot create std::vector larger than
// max_size()". Those mean a count in the file was believed; say so instead.
bool is_allocation_failure(const std::string& why) {
  return why == "std::bad_alloc" || why == "std::bad_array_new_length" ||
         why.rfind("vector::", 0) == 0 || why.rfind("basic_string::", 0) == 0 ||
         why.find("max_size()") != std::string::npos;
}

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

// Some of assimp's bundled parsers (openddlparser for OpenGEX) write to std::cerr or std::cout.
// The library never prints: while an importer runs the standard streams go nowhere.
// The streams are process-wide: readers on several threads share one silence, counted, and the
// last to leave restores the streams.
class SilencedStreams {
 public:
  SilencedStreams() {
    const std::lock_guard<std::mutex> lock(shared().mutex);
    Shared& s = shared();
    if (s.users++ == 0) {
      s.out = std::cout.rdbuf(&s.null);
      s.err = std::cerr.rdbuf(&s.null);
      s.log = std::clog.rdbuf(&s.null);
    }
  }
  ~SilencedStreams() {
    const std::lock_guard<std::mutex> lock(shared().mutex);
    Shared& s = shared();
    if (--s.users == 0) {
      std::cout.rdbuf(s.out);
      std::cerr.rdbuf(s.err);
      std::clog.rdbuf(s.log);
    }
  }
  SilencedStreams(const SilencedStreams&) = delete;
  SilencedStreams& operator=(const SilencedStreams&) = delete;

 private:
  struct NullBuffer : std::streambuf {
    int overflow(int c) override { return traits_type::not_eof(c); }
  };
  struct Shared {
    std::mutex mutex;
    NullBuffer null;
    std::streambuf* out = nullptr;
    std::streambuf* err = nullptr;
    std::streambuf* log = nullptr;
    int users = 0;
  };
  static Shared& shared() {
    static Shared s;
    return s;
  }
};

// Some importers drop faces they cannot use and only log it (glTF 2: "Some faces had out-of-range
// indices. Those faces were dropped."): the mesh would then read as smaller than the file and could
// check "clean" with a hole in it. assimp's logger is process-wide, so its warnings and errors go
// to one stream that hands each message to the reader on the calling thread (importers log on the
// thread that runs ReadFile).
class ImporterMessages {
 public:
  ImporterMessages() {
    static std::once_flag once;
    std::call_once(once, [] {
      Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
      Assimp::DefaultLogger::get()->attachStream(new Forward,
                                                 Assimp::Logger::Warn | Assimp::Logger::Err);
    });
    current() = &messages_;
  }
  ~ImporterMessages() { current() = nullptr; }
  ImporterMessages(const ImporterMessages&) = delete;
  ImporterMessages& operator=(const ImporterMessages&) = delete;

  // The first message that says faces were lost, or "".
  std::string dropped_faces() const {
    for (const std::string& m : messages_) {
      const std::string l = lower(m);
      if (l.find("out-of-range") != std::string::npos || l.find("out of range") != std::string::npos)
        return m;
    }
    return "";
  }

 private:
  struct Forward : Assimp::LogStream {
    void write(const char* message) override {
      std::vector<std::string>* sink = current();
      if (sink == nullptr || sink->size() >= 64) return;
      // assimp prefixes "Warn,  T0: " (severity and thread): keep only the words.
      std::string text(message);
      if (text.rfind("Warn,", 0) == 0 || text.rfind("Error,", 0) == 0) {
        const std::size_t colon = text.find(": ");
        if (colon != std::string::npos) text.erase(0, colon + 2);
      }
      sink->push_back(std::move(text));
    }
  };
  static std::vector<std::string>*& current() {
    thread_local std::vector<std::string>* sink = nullptr;
    return sink;
  }
  std::vector<std::string> messages_;
};

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

// Each instance of a mesh is copied with its world transform. What the copies add on top of the
// meshes themselves is bounded: a node graph that places one large mesh a million times is a
// small file that expands without limit.
constexpr std::uint64_t kMaxInstancedCopies = std::uint64_t{1} << 26;  // vertices and faces

void check_instancing(const aiScene& scene, const std::string& path) {
  std::uint64_t in_file = 0, expanded = 0;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    in_file += std::uint64_t{scene.mMeshes[m]->mNumVertices} + scene.mMeshes[m]->mNumFaces;
  }
  std::vector<const aiNode*> stack{scene.mRootNode};
  while (!stack.empty()) {
    const aiNode* node = stack.back();
    stack.pop_back();
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      if (node->mMeshes[k] >= scene.mNumMeshes) continue;  // reported by collect
      const aiMesh& mesh = *scene.mMeshes[node->mMeshes[k]];
      expanded = saturating_add(expanded, std::uint64_t{mesh.mNumVertices} + mesh.mNumFaces);
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) {
      if (node->mChildren[c] != nullptr) stack.push_back(node->mChildren[c]);
    }
  }
  if (expanded > in_file && expanded - in_file > kMaxInstancedCopies) {
    fail(path, "its node graph places meshes so often that they expand to " +
                   std::to_string(expanded) + " vertices and faces (" + std::to_string(in_file) +
                   " in the file); refused above " + std::to_string(kMaxInstancedCopies) +
                   " copied");
  }
}

// Meshes of the node graph in pre-order (node, then its children in order), with world
// transforms. Iterative: a deep node graph must not exhaust the stack.
void collect(const aiScene& scene, const std::string& path, Role role, std::vector<Mesh>& out) {
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack{{scene.mRootNode, aiMatrix4x4()}};
  while (!stack.empty()) {
    const auto [node, parent] = stack.back();
    stack.pop_back();
    const aiMatrix4x4 world = parent * node->mTransformation;
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      if (node->mMeshes[k] >= scene.mNumMeshes)
        fail(path, "a node refers to mesh " + std::to_string(node->mMeshes[k]) +
                       " but the file has " + std::to_string(scene.mNumMeshes));
      const aiMesh& in = *scene.mMeshes[node->mMeshes[k]];
      if (in.mNumVertices > 0 && in.mVertices == nullptr) fail(path, "a mesh without positions");
      Mesh mesh;
      mesh.path = path;
      mesh.name = in.mName.length > 0 ? in.mName.C_Str() : node->mName.C_Str();
      mesh.node_name = node->mName.C_Str();
      mesh.role = role;
      mesh.positions.resize(in.mNumVertices);
      for (unsigned v = 0; v < in.mNumVertices; ++v) {
        const aiVector3D p = world * in.mVertices[v];
        mesh.positions[v] = {static_cast<double>(p.x), static_cast<double>(p.y),
                             static_cast<double>(p.z)};
        for (double c : mesh.positions[v]) {
          if (!std::isfinite(c)) {
            fail(path, "vertex " + std::to_string(v) + " has a NaN or infinite coordinate");
          }
        }
      }
      mesh.source_faces = in.mNumFaces;
      for (unsigned f = 0; f < in.mNumFaces; ++f) {
        const aiFace& face = in.mFaces[f];
        for (unsigned c = 0; c < face.mNumIndices; ++c) {
          if (face.mIndices[c] >= in.mNumVertices) {
            fail(path, "face " + std::to_string(f) + " refers to vertex " +
                           std::to_string(face.mIndices[c]) + " but the mesh has " +
                           std::to_string(in.mNumVertices) + " vertices");
          }
        }
        // Points and lines carry no surface: skipped. Polygons become fans around their first
        // corner.
        for (unsigned c = 2; c < face.mNumIndices; ++c) {
          mesh.triangles.push_back({face.mIndices[0], face.mIndices[c - 1], face.mIndices[c]});
          mesh.polygon.push_back(f);
        }
      }
      if (!mesh.triangles.empty()) out.push_back(std::move(mesh));
    }
    for (unsigned c = node->mNumChildren; c-- > 0;) {
      if (node->mChildren[c] == nullptr) fail(path, "a node of the scene graph is missing");
      stack.emplace_back(node->mChildren[c], world);
    }
  }
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

namespace {

std::vector<Mesh> read_with_assimp(const std::string& path, Role role, const std::string& extension,
                                   std::uint64_t size) {
  Assimp::Importer importer;
  precheck_for_assimp(path, extension, size);

  const aiScene* scene = nullptr;
  std::string why;
  ImporterMessages messages;
  {
    SilencedStreams silenced;
    try {
      // No joining, no pre-transforming, no triangulation by assimp: vertex order stays as in the
      // file and polygons are fanned here, so every triangle knows its source face.
      scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
    } catch (const std::bad_alloc&) {
      why = "std::bad_alloc";
    } catch (const std::exception& e) {
      why = e.what();
    } catch (...) {
      why = "unknown error";
    }
  }
  if (scene == nullptr) {
    if (why.empty()) why = one_line(importer.GetErrorString());
    // assimp's words for a file without surfaces (STL without facets, OFF or glTF without faces, a
    // scene of cameras and lights).
    for (const char* empty : {"contains no faces", "has no faces", "contains no vertices",
                              "no facets defined", "no valid faces"}) {
      if (why.find(empty) != std::string::npos) {
        fail(path, "no triangles (0 faces); untangle needs surface meshes");
      }
    }
    if (why.find("mNumMeshes is 0") != std::string::npos) {
      fail(path, "no triangles (no meshes in the file); untangle needs surface meshes");
    }
    if (is_allocation_failure(why))
      fail(path, std::string("cannot read mesh: ") + kTooManyElements);
    if (why.empty()) why = "unknown error";
    fail(path, "cannot read mesh: " + why);
  }
  if (scene->mRootNode == nullptr) fail(path, "no scene graph in the file");
  const std::string dropped = messages.dropped_faces();
  if (!dropped.empty()) fail(path, "face indices out of range: " + one_line(dropped));

  check_instancing(*scene, path);
  std::vector<Mesh> meshes;
  collect(*scene, path, role, meshes);
  if (meshes.empty()) {
    std::size_t faces = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) faces += scene->mMeshes[m]->mNumFaces;
    fail(path, "no triangles (" + std::to_string(faces) +
                   " faces, all points or lines); untangle needs surface meshes");
  }
  return meshes;
}

}  // namespace

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
      meshes = on_large_stack<std::vector<Mesh>>(
          [&] { return read_with_assimp(path, role, extension, size); });
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