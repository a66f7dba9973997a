// Reading meshes through assimp: world-space triangles, vertex order kept, polygons fanned.
#include "untangle/read_meshes.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "io/read_obj.h"
#include "io/read_off.h"
#include "untangle/error.h"

namespace untangle {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw Error(ExitCode::kUnreadableInput, path, message);
}

// assimp's messages end in newlines and sometimes repeat the path; keep one clean line.
std::string one_line(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent,
             const std::string& path, Role role, std::vector<Mesh>& out) {
  const aiMatrix4x4 world = parent * node.mTransformation;
  for (unsigned k = 0; k < node.mNumMeshes; ++k) {
    const aiMesh& in = *scene.mMeshes[node.mMeshes[k]];
    Mesh mesh;
    mesh.path = path;
    mesh.name = in.mName.length > 0 ? in.mName.C_Str() : node.mName.C_Str();
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
      // Points and lines carry no surface: skipped. Polygons become fans around their first corner.
      for (unsigned c = 2; c < face.mNumIndices; ++c) {
        mesh.triangles.push_back({face.mIndices[0], face.mIndices[c - 1], face.mIndices[c]});
        mesh.polygon.push_back(f);
      }
    }
    if (!mesh.triangles.empty()) out.push_back(std::move(mesh));
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    collect(scene, *node.mChildren[c], world, path, role, out);
  }
}

}  // namespace

std::vector<Mesh> read_meshes(const std::string& path, Role role) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) fail(path, "no such file");
  if (std::filesystem::is_directory(status)) fail(path, "is a directory, not a mesh file");
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) fail(path, "cannot open for reading");
    if (probe.peek() == std::ifstream::traits_type::eof()) {
      fail(path, "empty file (0 bytes); untangle needs surface meshes");
    }
  }

  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".obj") return {read_obj(path, role)};
  if (extension == ".off" && is_plain_off(path)) return {read_off(path, role)};

  Assimp::Importer importer;
  // No joining, no pre-transforming, no triangulation by assimp: vertex order stays as in the
  // file and polygons are fanned here, so every triangle knows its source face.
  const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
  if (scene == nullptr) {
    std::string why = one_line(importer.GetErrorString());
    if (why.find("contains no faces") != std::string::npos) {
      fail(path, "no triangles (0 faces); untangle needs surface meshes");
    }
    if (why.empty()) why = "unknown error";
    fail(path, "cannot read mesh: " + why);
  }
  if (scene->mRootNode == nullptr) fail(path, "no scene graph in the file");

  std::vector<Mesh> meshes;
  collect(*scene, *scene->mRootNode, aiMatrix4x4(), path, role, meshes);
  if (meshes.empty()) {
    std::size_t faces = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) faces += scene->mMeshes[m]->mNumFaces;
    fail(path, "no triangles (" + std::to_string(faces) +
                   " faces, all points or lines); untangle needs surface meshes");
  }
  return meshes;
}

}  // namespace untangle
