// The assimp module's reader: world-space triangles, vertex order kept, polygons fanned. The
// library's read_meshes (lib/src/io/read_meshes.cpp) checks the file and runs this on a thread
// with a large stack.
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <cmath>
#include <cstdint>
#include <exception>
#include <iostream>
#include <mutex>
#include <new>
#include <streambuf>
#include <string>
#include <utility>
#include <vector>

#include "functions.h"
#include "io/prechecks.h"
#include "untangle/error.h"

namespace untangle::assimp_module {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw Error(ExitCode::kUnreadableInput, path, message);
}

// What a reader's running out of memory means for a file that fits on disk (as read_meshes says).
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

std::vector<Mesh> read(const std::string& path, Role role) {
  Assimp::Importer importer;

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

}  // namespace untangle::assimp_module
