// The glTF and GLB prechecks: nesting and claimed sizes checked before assimp reads the file.
#include <algorithm>
#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/prechecks.h"
#include "untangle/error.h"

namespace untangle {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw Error(ExitCode::kUnreadableInput, path, message);
}

// assimp parses glTF JSON with a recursive parser and builds the node graph recursively: deep
// nesting or a long chain of nodes overflows the stack. The limits are far above real glTF, whose
// JSON nests about ten levels deep and whose node chains (skeletons) rarely pass a hundred.
constexpr int kMaxJsonDepth = 256;
constexpr std::size_t kMaxNodeDepth = 1000;

// Deepest nesting of arrays and objects in JSON text (strings skipped), stopping past `limit`.
int json_depth(std::string_view text, int limit) {
  int depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > limit) break;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

// Length of the longest chain of `nodes[i].children` (glTF 2.0; glTF 1.0 names nodes by strings
// and is left to assimp). Iterative; a cycle counts as deep.
std::size_t gltf_node_depth(const nlohmann::json& document) {
  const auto nodes = document.find("nodes");
  if (nodes == document.end() || !nodes->is_array()) return 0;
  const std::size_t n = nodes->size();
  std::vector<std::size_t> depth(n, 0);  // 0: not reached yet
  std::size_t deepest = 0;
  for (std::size_t root = 0; root < n; ++root) {
    if (depth[root] != 0) continue;
    std::vector<std::size_t> stack{root};
    depth[root] = 1;
    while (!stack.empty()) {
      const std::size_t at = stack.back();
      stack.pop_back();
      deepest = std::max(deepest, depth[at]);
      if (deepest > kMaxNodeDepth) return deepest;
      const nlohmann::json& node = (*nodes)[at];
      if (!node.is_object()) continue;
      const auto children = node.find("children");
      if (children == node.end() || !children->is_array()) continue;
      for (const nlohmann::json& child : *children) {
        if (!child.is_number_unsigned()) continue;
        const auto c = child.get<std::uint64_t>();
        if (c >= n || depth[c] > depth[at]) continue;
        depth[c] = depth[at] + 1;
        stack.push_back(static_cast<std::size_t>(c));
      }
    }
  }
  return deepest;
}

// A member that should be an unsigned number, or `fallback` when it is absent or of another type
// (assimp rejects wrong types with its own message).
std::uint64_t unsigned_member(const nlohmann::json& object, const char* key,
                              std::uint64_t fallback) {
  const auto it = object.find(key);
  return it != object.end() && it->is_number_unsigned() ? it->get<std::uint64_t>() : fallback;
}

// Bytes of a glTF component type (5120 BYTE ... 5126 FLOAT), 0 if unknown.
std::uint64_t gltf_component_bytes(std::uint64_t type) {
  switch (type) {
    case 5120:
    case 5121:
      return 1;
    case 5122:
    case 5123:
      return 2;
    case 5125:
    case 5126:
      return 4;
    default:
      return 0;
  }
}

// Bytes of one element of an accessor (component bytes times SCALAR 1 ... MAT4 16), 0 if unknown.
std::uint64_t gltf_element_bytes(const nlohmann::json& accessor) {
  const auto type = accessor.find("type");
  if (type == accessor.end() || !type->is_string()) return 0;
  const std::uint64_t component =
      gltf_component_bytes(unsigned_member(accessor, "componentType", 0));
  const std::string& name = type->get_ref<const std::string&>();
  const std::pair<const char*, std::uint64_t> kTypes[] = {
      {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT2", 4}, {"MAT3", 9}, {"MAT4", 16}};
  for (const auto& [type_name, components] : kTypes) {
    if (name == type_name) return component * components;
  }
  return 0;
}

// What assimp 5.2 believes in a glTF 2.0 file without comparing it with the data:
// - an accessor without a buffer view (all zeros, optionally patched by a sparse part) is
//   allocated at its full count, however small the file;
// - a sparse part is copied by its count and offsets, read past its buffer views when they lie;
// - every use of an accessor by a primitive or a morph target is a copy, so a small file that
//   uses one large accessor thousands of times expands without bound.
// Counts must fit in the file's data; sparse parts in their views; and copies made by reuse stay
// under kMaxGltfCopyBytes on top of the data itself.
constexpr std::uint64_t kMaxGltfCopyBytes = std::uint64_t{2} << 30;

void check_gltf_accessors(const std::string& path, const nlohmann::json& document,
                          std::uint64_t file_bytes) {
  const auto accessors = document.find("accessors");
  if (accessors == document.end() || !accessors->is_array()) return;  // glTF 1.0: assimp's
  const auto views = document.find("bufferViews");
  const auto buffers = document.find("buffers");
  std::uint64_t data = file_bytes;
  if (buffers != document.end() && buffers->is_array()) {
    for (const nlohmann::json& b : *buffers) {
      if (b.is_object()) data = saturating_add(data, unsigned_member(b, "byteLength", 0));
    }
  }
  // The byte length of the buffer view a `bufferView` member names, or UINT64_MAX if unknown.
  auto view_bytes = [&](const nlohmann::json& object) -> std::uint64_t {
    const std::uint64_t index = unsigned_member(object, "bufferView", UINT64_MAX);
    if (views == document.end() || !views->is_array() || index >= views->size()) return UINT64_MAX;
    const nlohmann::json& view = (*views)[index];
    return view.is_object() ? unsigned_member(view, "byteLength", UINT64_MAX) : UINT64_MAX;
  };
  const std::size_t n = accessors->size();
  std::vector<std::uint64_t> bytes(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const nlohmann::json& a = (*accessors)[i];
    if (!a.is_object()) continue;
    const std::string name = "accessor " + std::to_string(i);
    const std::uint64_t count = unsigned_member(a, "count", 0);
    const std::uint64_t element = gltf_element_bytes(a);
    bytes[i] = saturating_mul(count, std::max<std::uint64_t>(element, 1));
    if (!a.contains("bufferView") && count > data) {
      fail(path, name + " claims " + std::to_string(count) +
                     " elements with no data behind them, more than the file holds");
    }
    const auto sparse = a.find("sparse");
    if (sparse == a.end() || !sparse->is_object()) continue;
    const std::uint64_t sparse_count = unsigned_member(*sparse, "count", 0);
    if (sparse_count > count) {
      fail(path, name + ": its sparse part claims " + std::to_string(sparse_count) +
                     " elements, more than its " + std::to_string(count));
    }
    const auto indices = sparse->find("indices");
    const auto values = sparse->find("values");
    const std::pair<nlohmann::json::const_iterator, std::uint64_t> parts[] = {
        {indices, indices != sparse->end() && indices->is_object()
                      ? gltf_component_bytes(unsigned_member(*indices, "componentType", 0))
                      : 0},
        {values, element}};
    for (const auto& [part, size] : parts) {
      if (part == sparse->end() || !part->is_object() || size == 0) continue;
      const std::uint64_t view = view_bytes(*part);
      const std::uint64_t offset = unsigned_member(*part, "byteOffset", 0);
      if (view != UINT64_MAX &&
          (offset > view || saturating_mul(sparse_count, size) > view - offset)) {
        fail(path, name + ": its sparse part reaches past its buffer view");
      }
    }
  }
  // Copies made by reuse: every reference costs the accessor's bytes, the first is the data.
  std::uint64_t referenced = 0, distinct = 0;
  std::vector<bool> used(n, false);
  auto use = [&](const nlohmann::json& reference) {
    if (!reference.is_number_unsigned()) return;
    const auto index = reference.get<std::uint64_t>();
    if (index >= n) return;
    referenced = saturating_add(referenced, bytes[index]);
    if (!used[index]) distinct = saturating_add(distinct, bytes[index]);
    used[index] = true;
  };
  auto use_all = [&](const nlohmann::json& attributes) {
    if (!attributes.is_object()) return;
    for (const nlohmann::json& reference : attributes) use(reference);
  };
  const auto meshes = document.find("meshes");
  if (meshes == document.end() || !meshes->is_array()) return;
  for (const nlohmann::json& mesh : *meshes) {
    const auto primitives = mesh.is_object() ? mesh.find("primitives") : mesh.end();
    if (!mesh.is_object() || primitives == mesh.end() || !primitives->is_array()) continue;
    for (const nlohmann::json& primitive : *primitives) {
      if (!primitive.is_object()) continue;
      if (const auto a = primitive.find("attributes"); a != primitive.end()) use_all(*a);
      if (const auto i = primitive.find("indices"); i != primitive.end()) use(*i);
      const auto targets = primitive.find("targets");
      if (targets == primitive.end() || !targets->is_array()) continue;
      for (const nlohmann::json& target : *targets) use_all(target);
    }
  }
  if (referenced - distinct > kMaxGltfCopyBytes) {
    fail(path, "meshes use the same accessors over and over: " + std::to_string(referenced) +
                   " bytes in all for " + std::to_string(distinct) +
                   " bytes of data; refused above " + std::to_string(kMaxGltfCopyBytes >> 30) +
                   " GiB of copies");
  }
}

void check_gltf_json(const std::string& path, std::string_view text, std::uint64_t file_bytes) {
  if (json_depth(text, kMaxJsonDepth) > kMaxJsonDepth)
    fail(path, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                   " levels; not a glTF file, or corrupt");
  const nlohmann::json document = nlohmann::json::parse(text, nullptr, false, true);
  if (document.is_discarded()) fail(path, "malformed JSON (truncated or corrupt glTF)");
  if (!document.is_object()) fail(path, "not a glTF file (the JSON is not an object)");
  check_gltf_accessors(path, document, file_bytes);
  if (gltf_node_depth(document) > kMaxNodeDepth)
    fail(path, "node hierarchy deeper than " + std::to_string(kMaxNodeDepth) +
                   " levels, or cyclic; corrupt glTF");
}

std::uint32_t little_u32(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t k = 4; k-- > 0;) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
  return v;
}

}  // namespace

// A binary glTF: a 12-byte header, then chunks (version 2) or one JSON block (version 1), each
// with its length; assimp allocates what they claim.
void precheck_glb(const std::string& path, std::uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  std::string header(20, '\0');
  in.read(header.data(), 20);
  if (in.gcount() < 12 || header.compare(0, 4, "glTF") != 0) return;  // not GLB: assimp decides
  if (in.gcount() < 20) fail(path, "GLB header cut short (truncated)");
  const std::uint32_t version = little_u32(header, 4);
  const std::uint64_t json_length = little_u32(header, 12);
  if (json_length > size - 20)
    fail(path, "GLB header claims " + std::to_string(json_length) +
                   " bytes of JSON, the file has " + std::to_string(size) +
                   " (truncated or corrupt)");
  if (version == 2 && json_length + 20 + 8 <= size) {
    std::string chunk(8, '\0');
    in.seekg(static_cast<std::streamoff>(20 + json_length));
    in.read(chunk.data(), 8);
    const std::uint64_t bin_length = little_u32(chunk, 0);
    if (in.gcount() == 8 && bin_length > size - 28 - json_length)
      fail(path, "GLB header claims " + std::to_string(bin_length) +
                     " bytes of binary data, more than the file holds (truncated or corrupt)");
  }
  std::string json(static_cast<std::size_t>(json_length), '\0');
  in.seekg(20);
  in.read(json.data(), static_cast<std::streamsize>(json_length));
  if (static_cast<std::uint64_t>(in.gcount()) != json_length)
    fail(path, "cannot read the GLB JSON");
  check_gltf_json(path, json, size);
}

void precheck_gltf(const std::string& path, std::uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  check_gltf_json(path, text.str(), size);
}

}  // namespace untangle
