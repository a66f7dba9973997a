// glTF to glTF (and .glb to .glb) by patching positions in copies of the input's buffers (issue 22
// §2).
#include "io/write_gltf_in_place.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "untangle/error.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::string read_file(const fs::path& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool external(const std::string& uri) {
  return uri.rfind("data:", 0) != 0 && uri.find("://") == std::string::npos && !uri.empty();
}

// glTF 2 refers by index into arrays, glTF 1 by id into objects.
Json* lookup(Json& collection, const Json& ref) {
  if (collection.is_array() && ref.is_number_unsigned() && ref.get<std::size_t>() < collection.size())
    return &collection[ref.get<std::size_t>()];
  if (collection.is_object() && ref.is_string() && collection.contains(ref.get<std::string>()))
    return &collection[ref.get<std::string>()];
  return nullptr;
}

// A key for a reference (index or id), to keep per-buffer and per-accessor state in a map.
std::string key_of(const Json& ref) { return ref.is_string() ? ref.get<std::string>() : ref.dump(); }

// The external buffers of the file, in file order, as (reference key, uri).
std::vector<std::pair<std::string, std::string>> external_buffers(const Json& j) {
  std::vector<std::pair<std::string, std::string>> out;
  const auto it = j.find("buffers");
  if (it == j.end()) return out;
  std::size_t index = 0;
  for (auto b = it->begin(); b != it->end(); ++b, ++index) {
    const std::string key = it->is_array() ? std::to_string(index) : b.key();
    if (b->is_object() && b->contains("uri") && (*b)["uri"].is_string() &&
        external((*b)["uri"].get<std::string>()))
      out.emplace_back(key, (*b)["uri"].get<std::string>());
  }
  return out;
}

std::vector<std::string> buffer_names(std::size_t count, const std::string& stem) {
  std::vector<std::string> names;
  for (std::size_t k = 0; k < count; ++k)
    names.push_back(count == 1 ? stem + ".bin" : stem + "_" + std::to_string(k) + ".bin");
  return names;
}

// A position accessor: where its floats are.
struct Positions {
  Json* json = nullptr;
  std::string buffer;  // key of its buffer
  std::size_t start = 0, stride = 12, count = 0;
};

float float_at(const std::string& bytes, std::size_t offset) {
  float f;
  std::memcpy(&f, bytes.data() + offset, 4);
  return f;
}

std::uint32_t u32_at(const std::string& bytes, std::size_t offset) {
  std::uint32_t u;
  std::memcpy(&u, bytes.data() + offset, 4);
  return u;
}

void put_u32(std::string& bytes, std::size_t offset, std::uint32_t u) {
  std::memcpy(bytes.data() + offset, &u, 4);
}

// Where the chunks of a binary glTF 2 file are: the 12-byte header (magic, version 2, length), the
// JSON chunk, then the BIN chunk if any (each chunk: length, type, data). False for anything else
// (glTF 1.0's KHR_binary_glTF, a truncated or inconsistent file).
struct GlbLayout {
  std::size_t json_at = 0, json_length = 0;  // the JSON chunk's data
  std::size_t bin_at = 0, bin_length = 0;    // the BIN chunk's data (length 0: none)
};

bool parse_glb(const std::string& file, GlbLayout& g) {
  constexpr std::uint32_t kJson = 0x4E4F534A, kBin = 0x004E4942;
  if (file.size() < 20 || file.compare(0, 4, "glTF") != 0 || u32_at(file, 4) != 2 ||
      u32_at(file, 8) != file.size())
    return false;
  bool first = true;
  for (std::size_t at = 12; at < file.size();) {
    if (file.size() - at < 8) return false;
    const std::size_t length = u32_at(file, at), type = u32_at(file, at + 4), data = at + 8;
    if (length > file.size() - data) return false;
    if (first && type != kJson) return false;
    if (first) {
      g.json_at = data;
      g.json_length = length;
    } else if (type == kBin && g.bin_length == 0) {
      g.bin_at = data;
      g.bin_length = length;
    }
    first = false;
    at = data + length;
  }
  return !first;
}

bool is_glb(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".glb";
}

// The JSON of a .gltf or .glb file and, for a .glb, its layout and BIN chunk.
struct GltfFile {
  std::string bytes;
  Json json;
  bool binary = false;
  GlbLayout layout;
  std::string bin;
};

bool read_gltf(const std::string& path, GltfFile& f) {
  bool ok = false;
  f.bytes = read_file(path, ok);
  if (!ok) return false;
  f.binary = is_glb(path);
  if (!f.binary) {
    f.json = Json::parse(f.bytes, nullptr, false);
    return true;
  }
  if (!parse_glb(f.bytes, f.layout)) return false;
  f.json = Json::parse(f.bytes.substr(f.layout.json_at, f.layout.json_length), nullptr, false);
  f.bin = f.bytes.substr(f.layout.bin_at, f.layout.bin_length);
  return true;
}

bool collect_positions(GltfFile& f, const fs::path& input_folder,
                       std::vector<std::pair<std::string, std::string>>& listed,
                       std::map<std::string, std::string>& buffers, std::vector<Positions>& accessors);

// The file's external buffers and the position accessors of its primitives, or false when they
// are not all float32 VEC3 in external buffers (then only assimp's exporter writes it).
// With `bin` (a .glb's BIN chunk), the positions must lie in that chunk (buffer 0, without a URI);
// the file's external buffers are then neither read nor listed.
bool collect_positions(Json& j, const fs::path& input_folder, const std::string* bin,
                       std::vector<std::pair<std::string, std::string>>& listed,
                       std::map<std::string, std::string>& buffers, std::vector<Positions>& accessors) {
  bool ok = false;
  if (j.is_discarded() || !j.is_object() || !j.contains("meshes") || !j.contains("accessors") ||
      !j.contains("bufferViews"))
    return false;
  const bool version1 = !(j.contains("asset") && j["asset"].contains("version") &&
                          j["asset"]["version"].is_string() &&
                          j["asset"]["version"].get<std::string>().rfind("2", 0) == 0);
  if (bin != nullptr) {
    if (version1 || !j.contains("buffers") || !j["buffers"].is_array() || j["buffers"].empty() ||
        !j["buffers"][0].is_object() || j["buffers"][0].contains("uri"))
      return false;
    buffers["0"] = *bin;
  } else {
    listed = external_buffers(j);
  }
  for (const auto& [key, uri] : listed) {
    buffers[key] = read_file(input_folder / uri, ok);
    if (!ok) return false;
  }

  // The position accessors of every primitive, in file order.
  std::map<std::string, std::size_t> accessor_index;
  for (auto& mesh : j["meshes"]) {
    if (!mesh.contains("primitives")) continue;
    for (auto& primitive : mesh["primitives"]) {
      if (!primitive.contains("attributes") || !primitive["attributes"].contains("POSITION")) continue;
      const Json& ref = primitive["attributes"]["POSITION"];
      if (accessor_index.count(key_of(ref))) continue;
      Json* a = lookup(j["accessors"], ref);
      if (a == nullptr || a->contains("sparse") || !a->contains("bufferView")) return false;
      if (a->value("componentType", 0) != 5126 || a->value("type", "") != "VEC3") return false;
      Json* view = lookup(j["bufferViews"], (*a)["bufferView"]);
      if (view == nullptr || !view->contains("buffer")) return false;
      Positions p;
      p.json = a;
      p.buffer = key_of((*view)["buffer"]);
      if (!buffers.count(p.buffer)) return false;  // embedded: re-encoding is not done here
      const std::size_t stride = version1 ? a->value("byteStride", std::size_t{0})
                                          : view->value("byteStride", std::size_t{0});
      p.stride = stride == 0 ? 12 : stride;
      p.start = view->value("byteOffset", std::size_t{0}) + a->value("byteOffset", std::size_t{0});
      p.count = a->value("count", std::size_t{0});
      const std::string& bytes = buffers[p.buffer];
      if (p.count > 0 && (p.stride < 12 || p.start + (p.count - 1) * p.stride + 12 > bytes.size()))
        return false;
      accessor_index[key_of(ref)] = accessors.size();
      accessors.push_back(p);
    }
  }

  return !accessors.empty();
}

bool collect_positions(GltfFile& f, const fs::path& input_folder,
                       std::vector<std::pair<std::string, std::string>>& listed,
                       std::map<std::string, std::string>& buffers, std::vector<Positions>& accessors) {
  return collect_positions(f.json, input_folder, f.binary ? &f.bin : nullptr, listed, buffers,
                           accessors);
}

// The bounds of an accessor's positions as stored.
void bounds_of(const Positions& p, const std::string& bytes, std::array<float, 3>& lo,
               std::array<float, 3>& hi) {
  for (std::size_t v = 0; v < p.count; ++v) {
    for (int c = 0; c < 3; ++c) {
      const float f = float_at(bytes, p.start + v * p.stride + 4 * c);
      lo[c] = v == 0 ? f : std::min(lo[c], f);
      hi[c] = v == 0 ? f : std::max(hi[c], f);
    }
  }
}

// Whether a JSON array holds exactly these three float values.
bool holds(const Json& array, const std::array<float, 3>& values) {
  if (!array.is_array() || array.size() != 3) return false;
  for (int c = 0; c < 3; ++c)
    if (!array[c].is_number() || static_cast<float>(array[c].get<double>()) != values[c]) return false;
  return true;
}

// Relative URIs of `kinds` (images, shaders, buffers) made valid from `final_folder` (they name
// the input's files); whether any changed.
bool repoint_uris(Json& j, const fs::path& input_folder, const std::string& final_folder,
                  const std::vector<const char*>& kinds) {
  std::error_code ec;
  const fs::path from = fs::absolute(input_folder, ec);
  const fs::path to = fs::absolute(final_folder, ec);
  bool changed = false;
  for (const char* kind : kinds) {
    if (!j.contains(kind)) continue;
    for (auto& item : j[kind]) {
      if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
      const std::string uri = item["uri"].get<std::string>();
      if (!external(uri) || fs::path(uri).is_absolute()) continue;
      const fs::path moved = (from / uri).lexically_normal().lexically_relative(to.lexically_normal());
      if (moved.empty() || moved.generic_string() == uri) continue;
      item["uri"] = moved.generic_string();
      changed = true;
    }
  }
  return changed;
}

}  // namespace

bool can_patch_gltf(const std::string& input) {
  GltfFile f;
  if (!read_gltf(input, f)) return false;
  std::vector<std::pair<std::string, std::string>> listed;
  std::map<std::string, std::string> buffers;
  std::vector<Positions> accessors;
  return collect_positions(f, fs::path(input).parent_path(), listed, buffers, accessors);
}

std::vector<std::string> buffers_of_output(const std::string& input, const std::string& output) {
  std::ifstream in(input, std::ios::binary);
  const Json j = Json::parse(in, nullptr, false);
  const std::size_t count = j.is_object() ? external_buffers(j).size() : 0;
  const fs::path target(output);
  std::vector<std::string> out;
  for (const std::string& name : buffer_names(std::max<std::size_t>(count, 1), target.stem().string()))
    out.push_back((target.parent_path() / name).string());
  return out;
}

bool write_gltf_in_place(const std::string& input, const std::string& staged,
                         const std::string& final_folder,
                         const std::vector<assimp_module::PlacedMesh>& instances,
                         const std::vector<const Mesh*>& meshes) {
  GltfFile file;
  if (!read_gltf(input, file)) return false;
  Json& j = file.json;
  const fs::path input_folder = fs::path(input).parent_path();
  std::vector<std::pair<std::string, std::string>> listed;
  std::map<std::string, std::string> buffers;  // key -> bytes: external ones, or a .glb's BIN
  std::vector<Positions> accessors;
  if (!collect_positions(file, input_folder, listed, buffers, accessors)) return false;

  // Each instance's mesh is the accessor holding exactly its vertices (assimp copies them as
  // stored); an accessor not yet taken is preferred, so that equal copies map one to one.
  if (instances.size() != meshes.size()) return false;
  std::vector<std::size_t> of_instance;
  std::vector<std::uint8_t> taken(accessors.size(), 0);
  std::map<std::size_t, std::size_t> of_mesh;  // the file's mesh index -> accessor
  for (const assimp_module::PlacedMesh& mesh : instances) {
    if (of_mesh.count(mesh.mesh_index)) {
      of_instance.push_back(of_mesh[mesh.mesh_index]);
      continue;
    }
    std::size_t found = accessors.size();
    for (std::size_t a = 0; a < accessors.size(); ++a) {
      const Positions& p = accessors[a];
      if (p.count != mesh.stored.size() || (found < accessors.size() && taken[a])) continue;
      const std::string& bytes = buffers[p.buffer];
      bool same = true;
      for (std::size_t v = 0; v < p.count && same; ++v) {
        for (int c = 0; c < 3 && same; ++c) {
          const float stored = float_at(bytes, p.start + v * p.stride + 4 * c);
          same = std::memcmp(&stored, &mesh.stored[v][c], 4) == 0;
        }
      }
      if (!same) continue;
      found = a;
      if (!taken[a]) break;
    }
    if (found == accessors.size()) return false;
    taken[found] = 1;
    of_mesh[mesh.mesh_index] = found;
    of_instance.push_back(found);
  }

  // Moved vertices written back; the first instance to move a vertex decides it (an accessor
  // shared by several primitives or placed by several nodes is one set of positions).
  std::vector<std::vector<std::uint8_t>> written(accessors.size());
  std::vector<std::uint8_t> changed(accessors.size(), 0);
  for (std::size_t k = 0; k < instances.size(); ++k) {
    const assimp_module::PlacedMesh& mesh = instances[k];
    const Mesh& ours = *meshes[k];
    Positions& p = accessors[of_instance[k]];
    if (ours.positions.size() != p.count || mesh.moved.size() != p.count) return false;
    std::vector<std::uint8_t>& done = written[of_instance[k]];
    done.resize(p.count, 0);
    std::string& bytes = buffers[p.buffer];
    for (std::size_t v = 0; v < p.count; ++v) {
      if (done[v] || !mesh.moved[v]) continue;
      done[v] = 1;
      changed[of_instance[k]] = 1;
      for (int c = 0; c < 3; ++c) {
        const float f = mesh.local[v][c];
        std::memcpy(bytes.data() + p.start + v * p.stride + 4 * c, &f, 4);
      }
    }
  }
  bool json_changed = false;
  for (std::size_t a = 0; a < accessors.size(); ++a) {
    Positions& p = accessors[a];
    if (!changed[a] || p.count == 0) continue;
    Json& json = *p.json;
    if (!json.contains("min") && !json.contains("max")) continue;
    std::array<float, 3> lo{}, hi{};
    bounds_of(p, buffers[p.buffer], lo, hi);
    if (holds(json["min"], lo) && holds(json["max"], hi)) continue;
    json["min"] = {lo[0], lo[1], lo[2]};
    json["max"] = {hi[0], hi[1], hi[2]};
    json_changed = true;
  }

  if (file.binary) {
    // A .glb: its bytes with the BIN chunk's positions patched. The JSON chunk is kept byte for
    // byte unless bounds or relative URIs had to change; then it is written again (compact,
    // padded with spaces to 4 bytes as the format asks) and the header's length follows.
    // External buffers of a .glb hold no positions (collect_positions): they are named, not copied.
    json_changed = repoint_uris(j, input_folder, final_folder, {"images", "shaders", "buffers"}) ||
                   json_changed;
    std::string out = file.bytes;
    out.replace(file.layout.bin_at, file.layout.bin_length, buffers["0"]);
    if (json_changed) {
      std::string text = j.dump(-1, ' ', false, Json::error_handler_t::replace);
      text.append((4 - text.size() % 4) % 4, ' ');
      if (out.size() - file.layout.json_length + text.size() > 0xffffffffu) return false;
      out.replace(file.layout.json_at, file.layout.json_length, text);
      put_u32(out, file.layout.json_at - 8, static_cast<std::uint32_t>(text.size()));
      put_u32(out, 8, static_cast<std::uint32_t>(out.size()));
    }
    std::ofstream glb(staged, std::ios::binary);
    glb << out;
    glb.flush();
    if (!glb) throw Error(ExitCode::kOutputNotWritten, staged, "write failed");
    return true;
  }

  // The buffers beside the output, and every other relative URI made valid from its folder.
  const fs::path out(staged);
  const std::vector<std::string> names = buffer_names(listed.size(), out.stem().string());
  for (std::size_t k = 0; k < listed.size(); ++k) {
    Json* buffer = lookup(j["buffers"], j["buffers"].is_array() ? Json(std::stoul(listed[k].first))
                                                                : Json(listed[k].first));
    (*buffer)["uri"] = names[k];
    std::ofstream file(out.parent_path() / names[k], std::ios::binary);
    file << buffers[listed[k].first];
    file.flush();
    if (!file) throw Error(ExitCode::kOutputNotWritten, staged, "write failed");
  }
  repoint_uris(j, input_folder, final_folder, {"images", "shaders"});
  std::ofstream gltf(staged, std::ios::binary);
  gltf << j.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
  gltf.flush();
  if (!gltf) throw Error(ExitCode::kOutputNotWritten, staged, "write failed");
  return true;
}

}  // namespace untangle
