// Writers: OBJ by rewriting v lines in place; other formats through assimp's exporter.
#include "untangle/write_meshes.h"

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <cstring>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "io/deterministic_export.h"
#include "io/prechecks.h"
#include "io/read_off.h"
#include "io/verified_exports.h"
#include "io/write_gltf_in_place.h"
#include "io/write_off.h"
#include "untangle/error.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;

std::string extension_of(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  return ext;
}

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw Error(ExitCode::kOutputNotWritten, path, message);
}

void append_number(std::string& out, double value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  out.append(buffer.data(), result.ptr);
}

// Rewrites the v lines whose position changed; every other byte is copied.
std::string rewrite_obj(const std::string& input, const Mesh& mesh) {
  std::ifstream in(input, std::ios::binary);
  if (!in) fail(input, "cannot re-open the input to copy it");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  std::string out;
  out.reserve(text.size() + text.size() / 8);
  std::size_t vertex = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    end = end == std::string::npos ? text.size() : end + 1;
    std::size_t k = pos;
    while (k < end && (text[k] == ' ' || text[k] == '\t')) ++k;
    const bool is_vertex = k + 1 < end && text[k] == 'v' && (text[k + 1] == ' ' || text[k + 1] == '\t');
    if (!is_vertex) {
      out.append(text, pos, end - pos);
      pos = end;
      continue;
    }
    // Parse the three coordinates to see whether this vertex moved, and where they end.
    std::size_t cursor = k + 1;
    Vec3 old{};
    for (double& c : old) {
      while (cursor < end && (text[cursor] == ' ' || text[cursor] == '\t')) ++cursor;
      std::size_t token_end = cursor;
      while (token_end < end && text[token_end] != ' ' && text[token_end] != '\t' &&
             text[token_end] != '\r' && text[token_end] != '\n')
        ++token_end;
      const char* first = text.data() + cursor;
      if (*first == '+') ++first;
      std::from_chars(first, text.data() + token_end, c);
      cursor = token_end;
    }
    if (vertex >= mesh.positions.size()) fail(input, "vertex count changed while writing");
    const Vec3& p = mesh.positions[vertex++];
    if (p == old) {
      out.append(text, pos, end - pos);
    } else {
      out.append(text, pos, k - pos);
      out += "v ";
      append_number(out, p[0]);
      out += ' ';
      append_number(out, p[1]);
      out += ' ';
      append_number(out, p[2]);
      out.append(text, cursor, end - cursor);  // w, vertex colours and the line ending stay
    }
    pos = end;
  }
  return out;
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

void write_with_assimp(const std::string& input, const std::string& output,
                       const std::string& final_folder, const std::vector<const Mesh*>& meshes) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(input, 0);
  if (scene == nullptr || scene->mRootNode == nullptr) fail(output, "cannot re-read " + input);
  std::vector<std::pair<unsigned, aiMatrix4x4>> instances;
  collect_nodes(*scene->mRootNode, aiMatrix4x4(), instances);
  const std::string in_ext = extension_of(input), out_ext = extension_of(output);
  if ((in_ext == "gltf" || in_ext == "glb") && in_ext == out_ext) {
    // The instances read_meshes returns: those with triangles.
    std::vector<MeshInstance> placed;
    for (const auto& [index, world] : instances) {
      if (index >= scene->mNumMeshes) fail(output, "cannot re-read " + input);
      const aiMesh* mesh = scene->mMeshes[index];
      bool has_triangles = false;
      for (unsigned f = 0; f < mesh->mNumFaces && !has_triangles; ++f)
        has_triangles = mesh->mFaces[f].mNumIndices >= 3;
      if (has_triangles) placed.emplace_back(mesh, world);
    }
    if (write_gltf_in_place(input, output, final_folder, placed, meshes)) return;
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
  prepare_deterministic_export(format, *const_cast<aiScene*>(scene));
  if (exporter.Export(scene, format, output) != AI_SUCCESS) {
    std::string why = exporter.GetErrorString();
    for (char& c : why)
      if (c == '\n') c = ' ';
    fail(output, "export failed: " + why);
  }
  finish_deterministic_export(format, output, fs::path(output).filename().string());
}

// Animations and skins as the file states them: a glTF lists them in its JSON (assimp's glTF 1.0
// importer reads neither), other formats as assimp imports them.
struct Carried {
  std::size_t animations = 0, skins = 0, textures = 0;
};

std::size_t json_count(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it == j.end() || !(it->is_array() || it->is_object()) ? 0 : it->size();
}

Carried carried_by(const aiScene& scene) {
  Carried c;
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
  return c;
}

std::string counted(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

std::string export_loss(const std::string& input, const std::string& output) {
  const std::string in = extension_of(input), out = extension_of(output);
  if (in == "obj" && out == "obj") return "";
  if (in == "off" && out == "off") return "";
  if ((in == "gltf" || in == "glb") && in == out && can_patch_gltf(input)) return "";
  // Checked as the reader checks it: a hostile file is refused (exit 3) before assimp sizes its
  // allocations by what the file claims.
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(input, ec);
  if (ec) return "";  // unreadable: reading it reports why
  precheck_for_assimp(input, "." + in, size);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(input, 0);
  if (scene == nullptr) return "";  // unreadable: reading it reports why
  const Carried imported = carried_by(*scene);
  Carried in_file = imported;
  if (in == "gltf" || in == "glb") {
    std::ifstream file(input, std::ios::binary);
    nlohmann::json j;
    if (in == "gltf") {
      j = nlohmann::json::parse(file, nullptr, false);
    } else {
      // GLB: a 12-byte header, then the JSON chunk (length, type, data).
      std::string head(20, '\0');
      file.read(head.data(), 20);
      std::uint32_t length = 0;
      std::memcpy(&length, head.data() + 12, 4);
      std::string text(std::min<std::uint32_t>(length, 1u << 28), '\0');
      file.read(text.data(), static_cast<std::streamsize>(text.size()));
      j = nlohmann::json::parse(text, nullptr, false);
    }
    if (j.is_object()) {
      in_file.animations = std::max(imported.animations, json_count(j, "animations"));
      in_file.skins = std::max(imported.skins, json_count(j, "skins"));
    }
  }
  const bool animated = out == "gltf" || out == "glb" || out == "dae" || out == "fbx" ||
                        out == "assbin" || out == "x";
  const bool textured = out != "ply" && out != "stl";
  std::vector<std::string> lost;
  const std::size_t animations = in_file.animations - (animated ? imported.animations : 0);
  const std::size_t skins = in_file.skins - (animated ? imported.skins : 0);
  if (animations > 0) lost.push_back(counted(animations, "animation", "animations"));
  if (skins > 0) lost.push_back(counted(skins, "skin", "skins"));
  if (!textured && imported.textures > 0) lost.push_back(counted(imported.textures, "texture", "textures"));
  std::string text;
  for (const std::string& l : lost) text += (text.empty() ? "" : ", ") + l;
  return text;
}

bool can_write(const std::string& output) {
  const std::string ext = extension_of(output);
  if (ext == "obj" || ext == "off") return true;
  if (!is_verified_export(ext)) return false;
  Assimp::Exporter exporter;
  return !export_format(exporter, ext).empty();
}

std::vector<std::string> side_files_of_output(const std::string& input, const std::string& output) {
  const fs::path target(output);
  const std::string stem = target.stem().string();
  const std::string ext = extension_of(output);
  std::vector<std::string> side;
  if (ext == "obj" && extension_of(input) != "obj") side.push_back((target.parent_path() / (stem + ".mtl")).string());
  if (ext == "gltf") side.push_back((target.parent_path() / (stem + ".bin")).string());
  // glTF to glTF keeps the input's buffers, one file each (write_gltf_in_place).
  if (ext == "gltf" && extension_of(input) == "gltf")
    for (const std::string& b : buffers_of_output(input, output))
      if (std::find(side.begin(), side.end(), b) == side.end()) side.push_back(b);
  return side;
}

std::function<Vec3(const Vec3&)> output_rounding(const std::string& output) {
  if (extension_of(output) == "obj" || extension_of(output) == "off") return {};
  return [](const Vec3& p) {
    return Vec3{static_cast<double>(static_cast<float>(p[0])), static_cast<double>(static_cast<float>(p[1])),
                static_cast<double>(static_cast<float>(p[2]))};
  };
}

void write_meshes(const std::string& input, const std::string& output,
                  const std::vector<const Mesh*>& meshes) {
  const fs::path target(output);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) fail(output, "folder " + folder.string() + " does not exist");
  // Write into a private temporary folder next to the output (formats such as glTF write side
  // files), then move every file into place.
  std::mt19937_64 rng(std::random_device{}());
  const fs::path temp = folder / (".untangle-tmp-" + std::to_string(rng()));
  if (!fs::create_directory(temp, ec)) fail(output, "cannot create a temporary folder in " + folder.string());
  struct Cleanup {
    fs::path path;
    ~Cleanup() {
      std::error_code e;
      fs::remove_all(path, e);
    }
  } cleanup{temp};
  const fs::path staged = temp / target.filename();
  if (extension_of(input) == "obj" && extension_of(output) == "obj" && meshes.size() == 1) {
    const std::string text = rewrite_obj(input, *meshes.front());
    std::ofstream file(staged, std::ios::binary);
    file << text;
    file.flush();
    if (!file) fail(output, "write failed");
  } else if (extension_of(input) == "off" && extension_of(output) == "off" && meshes.size() == 1 &&
             is_plain_off(input)) {
    const std::string text = rewrite_off(input, *meshes.front());
    std::ofstream file(staged, std::ios::binary);
    file << text;
    file.flush();
    if (!file) fail(output, "write failed");
  } else if (extension_of(output) == "off") {
    fail(output, "OFF is written only from a plain OFF input");
  } else {
    write_with_assimp(input, staged.string(), folder.string(), meshes);
  }
  // Every staged file is checked before the first one is moved: a file the exporter made that
  // the caller could not foresee (side_files_of_output) never replaces an existing one.
  std::vector<fs::path> staged_files;
  for (const auto& entry : fs::directory_iterator(temp)) staged_files.push_back(entry.path());
  std::sort(staged_files.begin(), staged_files.end());
  const std::vector<std::string> side = side_files_of_output(input, output);
  for (const fs::path& file : staged_files) {
    const fs::path destination = folder / file.filename();
    if (file.filename() == target.filename()) continue;
    bool foreseen = false;
    for (const std::string& s : side) foreseen = foreseen || fs::path(s).filename() == file.filename();
    if (!foreseen && fs::exists(fs::symlink_status(destination, ec)))
      fail(output, "the writer also made " + destination.string() + ", which exists; nothing was replaced");
  }
  for (const fs::path& file : staged_files) {
    fs::rename(file, folder / file.filename(), ec);
    if (ec) fail(output, "cannot move the written file into place: " + ec.message());
  }
}

}  // namespace untangle
