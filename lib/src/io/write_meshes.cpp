// Writers: OBJ and OFF by rewriting v lines in place; glTF by patching its buffers; other formats
// through the assimp module's exporter (io/assimp_module.h), loaded only then.
#include "untangle/write_meshes.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <cstring>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "io/assimp_module.h"
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

// Animations and skins as the file states them: a glTF lists them in its JSON (assimp's glTF 1.0
// importer reads neither), other formats as assimp imports them.
using Carried = assimp_module::Carried;

// Re-imports `input` in the module, puts the positions in and exports (or patches a glTF in
// place), then fixes what the exporter wrote that does not come from the scene.
void write_with_assimp(const std::string& input, const std::string& output,
                       const std::string& staged, const std::string& final_folder,
                       const std::vector<const Mesh*>& meshes) {
  const assimp_module::Interface& module = assimp_module::get(output, ExitCode::kOutputNotWritten);
  const std::string format = module.write(
      input, staged, final_folder, meshes,
      [&](const std::vector<assimp_module::PlacedMesh>& placed) {
        return write_gltf_in_place(input, staged, final_folder, placed, meshes);
      });
  if (!format.empty()) finish_deterministic_export(format, staged, fs::path(staged).filename().string());
}

std::size_t json_count(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it == j.end() || !(it->is_array() || it->is_object()) ? 0 : it->size();
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
  Carried imported;
  if (!assimp_module::get(input, ExitCode::kUnreadableInput).carried(input, imported))
    return "";  // unreadable: reading it reports why
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
  for (const assimp_module::ExporterInfo& e :
       assimp_module::get(output, ExitCode::kOutputNotWritten).exporters())
    if (e.extension == ext) return true;
  return false;
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
    write_with_assimp(input, output, staged.string(), folder.string(), meshes);
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
