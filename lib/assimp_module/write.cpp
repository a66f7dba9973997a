// The assimp module's writer: re-import the input, put the new positions in, export (or hand a
// glTF to the library's in-place writer); and what an import carries, for export_loss.
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "functions.h"
#include "io/prechecks.h"
#include "untangle/error.h"

namespace untangle::assimp_module {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw Error(ExitCode::kOutputNotWritten, path, message);
}

void collect_nodes(const aiNode& node, const aiMatrix4x4& parent,
                   std::vector<std::pair<unsigned, aiMatrix4x4>>& out) {
  const aiMatrix4x4 world = parent * node.mTransformation;
  for (unsigned k = 0; k < node.mNumMeshes; ++k) out.push_back({node.mMeshes[k], world});
  for (unsigned c = 0; c < node.mNumChildren; ++c) collect_nodes(*node.mChildren[c], world, out);
}

// Whether a PLY or STL file is binary, so that the output keeps the input's encoding.
bool is_binary(const std::string& path, const std::string& ext) {
  std::ifstream in(path, std::ios::binary);
  std::string head(512, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (ext == "ply") return head.find("format binary") != std::string::npos;
  if (ext == "stl") return head.rfind("solid", 0) != 0 || head.find("facet") == std::string::npos;
  return false;
}

std::string export_format(const Assimp::Exporter& exporter, const std::string& ext,
                          const std::string& input = {}) {
  if (!input.empty() && extension_of(input) == ext && (ext == "ply" || ext == "stl") &&
      is_binary(input, ext))
    return ext + "b";
  std::string found;
  for (std::size_t i = 0; i < exporter.GetExportFormatCount(); ++i) {
    const aiExportFormatDesc* d = exporter.GetExportFormatDescription(i);
    if (ext != d->fileExtension) continue;
    const std::string id = d->id;
    // glTF: prefer version 2. FBX: ASCII, because assimp 5.2 cannot read back the binary FBX it
    // writes, and every output is verified by reading it back. PLY and STL: the first listed.
    if (found.empty() || id == "gltf2" || id == "glb2" || id == "fbxa") found = id;
  }
  return found;
}

// Texture files named relative to the input are named relative to the output's folder instead,
// so that the exported file still finds them (embedded textures, "*<k>", stay as they are).
void keep_texture_paths(aiScene& scene, const std::string& input, const std::string& final_folder) {
  std::error_code ec;
  const fs::path from = fs::absolute(fs::path(input).parent_path(), ec).lexically_normal();
  const fs::path to = fs::absolute(final_folder, ec).lexically_normal();
  if (from == to) return;
  for (unsigned m = 0; m < scene.mNumMaterials; ++m) {
    aiMaterial& material = *scene.mMaterials[m];
    for (int type = aiTextureType_DIFFUSE; type <= AI_TEXTURE_TYPE_MAX; ++type) {
      const auto t = static_cast<aiTextureType>(type);
      for (unsigned k = 0; k < material.GetTextureCount(t); ++k) {
        aiString path;
        if (material.GetTexture(t, k, &path) != AI_SUCCESS) continue;
        const std::string name = path.C_Str();
        if (name.empty() || name[0] == '*' || name.rfind("data:", 0) == 0 || fs::path(name).is_absolute() ||
            name.find("://") != std::string::npos)
          continue;
        const fs::path moved = (from / name).lexically_normal().lexically_relative(to);
        if (moved.empty()) continue;
        const aiString replaced(moved.generic_string());
        material.AddProperty(&replaced, AI_MATKEY_TEXTURE(t, k));
      }
    }
  }
}

void name_nodes(aiNode& node, std::size_t& next) {
  if (node.mName.length == 0) node.mName.Set("node_" + std::to_string(next));
  ++next;
  for (unsigned c = 0; c < node.mNumChildren; ++c) name_nodes(*node.mChildren[c], next);
}

// Before export in format `format_id`: names every unnamed node "node_<k>" (depth first) where
// the exporter would otherwise name it after its pointer (X), so that the same scene gives the
// same bytes (io/deterministic_export.h fixes the rest after export).
void name_unnamed_nodes(const std::string& format_id, aiScene& scene) {
  if (format_id != "x" || scene.mRootNode == nullptr) return;
  std::size_t next = 0;
  name_nodes(*scene.mRootNode, next);
}

void count_carried(const aiScene& scene, Carried& c) {
  c = Carried();
  c.animations = scene.mNumAnimations;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) c.skins += scene.mMeshes[m]->mNumBones > 0 ? 1 : 0;
  std::vector<std::string> paths;
  for (unsigned m = 0; m < scene.mNumMaterials; ++m) {
    for (int type = aiTextureType_DIFFUSE; type <= AI_TEXTURE_TYPE_MAX; ++type) {
      const auto t = static_cast<aiTextureType>(type);
      for (unsigned k = 0; k < scene.mMaterials[m]->GetTextureCount(t); ++k) {
        aiString path;
        if (scene.mMaterials[m]->GetTexture(t, k, &path) != AI_SUCCESS) continue;
        if (std::find(paths.begin(), paths.end(), path.C_Str()) == paths.end()) paths.push_back(path.C_Str());
      }
    }
  }
  c.textures = std::max<std::size_t>(paths.size(), scene.mNumTextures);
}

}  // namespace

std::string write(const std::string& input, const std::string& output,
                  const std::string& final_folder, const std::vector<const Mesh*>& meshes,
                  const PatchInPlace& patch_in_place) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(input, 0);
  if (scene == nullptr || scene->mRootNode == nullptr) fail(output, "cannot re-read " + input);
  std::vector<std::pair<unsigned, aiMatrix4x4>> instances;
  collect_nodes(*scene->mRootNode, aiMatrix4x4(), instances);
  const std::string in_ext = extension_of(input), out_ext = extension_of(output);
  if ((in_ext == "gltf" || in_ext == "glb") && in_ext == out_ext) {
    // The instances read_meshes returns: those with triangles, each with what the in-place
    // writer needs (assimp's float arithmetic stays here).
    std::vector<PlacedMesh> placed;
    for (const auto& [index, world] : instances) {
      if (index >= scene->mNumMeshes) fail(output, "cannot re-read " + input);
      const aiMesh* mesh = scene->mMeshes[index];
      bool has_triangles = false;
      for (unsigned f = 0; f < mesh->mNumFaces && !has_triangles; ++f)
        has_triangles = mesh->mFaces[f].mNumIndices >= 3;
      if (!has_triangles) continue;
      PlacedMesh p;
      p.mesh_index = index;
      p.stored.resize(mesh->mNumVertices);
      for (unsigned v = 0; v < mesh->mNumVertices; ++v)
        p.stored[v] = {mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z};
      const std::size_t k = placed.size();
      if (k < meshes.size() && meshes[k]->positions.size() == mesh->mNumVertices) {
        const Mesh& ours = *meshes[k];
        aiMatrix4x4 inverse = world;
        inverse.Inverse();
        p.moved.assign(mesh->mNumVertices, 0);
        p.local.resize(mesh->mNumVertices);
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
          const aiVector3D target(static_cast<ai_real>(ours.positions[v][0]),
                                  static_cast<ai_real>(ours.positions[v][1]),
                                  static_cast<ai_real>(ours.positions[v][2]));
          if (world * mesh->mVertices[v] == target) continue;
          const aiVector3D local = inverse * target;
          p.moved[v] = 1;
          p.local[v] = {local[0], local[1], local[2]};
        }
      }
      placed.push_back(std::move(p));
    }
    if (patch_in_place(placed)) return "";
  }
  std::size_t next = 0;
  std::vector<std::uint8_t> done(scene->mNumMeshes, 0);
  for (const auto& [index, world] : instances) {
    aiMesh& mesh = *scene->mMeshes[index];
    bool has_triangles = false;
    for (unsigned f = 0; f < mesh.mNumFaces && !has_triangles; ++f)
      has_triangles = mesh.mFaces[f].mNumIndices >= 3;
    if (!has_triangles) continue;
    if (next >= meshes.size()) fail(output, "mesh count changed while writing");
    const Mesh& ours = *meshes[next++];
    if (done[index]) continue;  // an instanced mesh keeps the positions of its first instance
    done[index] = 1;
    if (ours.positions.size() != mesh.mNumVertices) fail(output, "vertex count changed while writing");
    aiMatrix4x4 inverse = world;
    inverse.Inverse();
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D world_point(static_cast<ai_real>(ours.positions[v][0]),
                                   static_cast<ai_real>(ours.positions[v][1]),
                                   static_cast<ai_real>(ours.positions[v][2]));
      const aiVector3D back = world * mesh.mVertices[v];
      // Unmoved vertices keep their stored value exactly (no round trip through the transform).
      if (back == world_point) continue;
      mesh.mVertices[v] = inverse * world_point;
    }
  }
  keep_texture_paths(*const_cast<aiScene*>(scene), input, final_folder);
  Assimp::Exporter exporter;
  const std::string format = export_format(exporter, extension_of(output), input);
  if (format.empty()) fail(output, "no writer for the format ." + extension_of(output));
  // The importer owns the scene; only unnamed nodes get a name (X names them by pointer).
  name_unnamed_nodes(format, *const_cast<aiScene*>(scene));
  if (exporter.Export(scene, format, output) != AI_SUCCESS) {
    std::string why = exporter.GetErrorString();
    for (char& c : why)
      if (c == '\n') c = ' ';
    fail(output, "export failed: " + why);
  }
  return format;
}

bool carried(const std::string& input, Carried& out) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(input, 0);
  if (scene == nullptr) return false;
  count_carried(*scene, out);
  return true;
}

std::vector<ExporterInfo> exporters() {
  std::vector<ExporterInfo> out;
  Assimp::Exporter exporter;
  for (std::size_t i = 0; i < exporter.GetExportFormatCount(); ++i) {
    const aiExportFormatDesc* d = exporter.GetExportFormatDescription(i);
    out.push_back({d->id, d->fileExtension, d->description});
  }
  return out;
}

}  // namespace untangle::assimp_module
