// Reading meshes through assimp: world-space triangles, vertex order kept, polygons fanned.
#include "untangle/read_meshes.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <pthread.h>

#include <algorithm>
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <new>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

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
// The library never prints (STYLE.md): while an importer runs the standard streams go nowhere.
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

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

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


template <class T>
bool parse_number(std::string_view token, T& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size() && !token.empty();
}

// Splits off the next token of blanks-separated text.
std::string_view next_token(std::string_view& s) {
  std::size_t k = 0;
  while (k < s.size() && (s[k] == ' ' || s[k] == '\t' || s[k] == '\r')) ++k;
  std::size_t n = k;
  while (n < s.size() && s[n] != ' ' && s[n] != '\t' && s[n] != '\r') ++n;
  const std::string_view token = s.substr(k, n - k);
  s.remove_prefix(n);
  return token;
}

// ----- PLY: checked here before assimp sees it -----
//
// assimp 5.2 loops forever on a PLY header without `end_header`, crashes on a damaged one, and
// sizes its arrays by the header's element counts and by each list's count without comparing
// them with the file. The header is parsed here and the body walked (binary: by byte counts;
// ASCII: one element per line), so that every count is known to fit in the file before assimp
// allocates anything.

struct PlyProperty {
  bool list = false;
  std::size_t size = 0;       // scalar: bytes of the value; list: bytes of the count
  bool count_signed = false;  // list: whether the count type is signed
  std::size_t item_size = 0;  // list: bytes of each item
};

struct PlyElement {
  std::string name;
  unsigned long long count = 0;
  std::vector<PlyProperty> properties;
};

// Bytes of a PLY scalar type; 0 for a name PLY does not define.
std::size_t ply_type_size(std::string_view type) {
  for (std::string_view t : {"char", "uchar", "int8", "uint8"})
    if (type == t) return 1;
  for (std::string_view t : {"short", "ushort", "int16", "uint16"})
    if (type == t) return 2;
  for (std::string_view t : {"int", "uint", "int32", "uint32", "float", "float32"})
    if (type == t) return 4;
  for (std::string_view t : {"double", "float64"})
    if (type == t) return 8;
  return 0;
}

bool ply_type_is_integer(std::string_view type) {
  return type != "float" && type != "float32" && type != "double" && type != "float64";
}

bool ply_type_is_signed(std::string_view type) {
  return type == "char" || type == "int8" || type == "short" || type == "int16" || type == "int" ||
         type == "int32";
}

// Sequential reading through a fixed buffer: skipping and reading the small count of a list cost
// no system call per element.
class ChunkReader {
 public:
  ChunkReader(std::ifstream& in, std::uint64_t begin, std::uint64_t size)
      : in_(in), pos_(begin), size_(size) {}

  std::uint64_t remaining() const { return size_ - pos_; }

  bool skip(std::uint64_t n) {
    if (n > remaining()) return false;
    pos_ += n;
    return true;
  }

  bool read(unsigned char* out, std::size_t n) {
    if (n > remaining()) return false;
    if (pos_ < buffer_begin_ || pos_ + n > buffer_begin_ + buffer_.size()) {
      buffer_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(kChunk, remaining())));
      in_.clear();
      in_.seekg(static_cast<std::streamoff>(pos_));
      in_.read(reinterpret_cast<char*>(buffer_.data()),
               static_cast<std::streamsize>(buffer_.size()));
      if (in_.gcount() != static_cast<std::streamsize>(buffer_.size())) return false;
      buffer_begin_ = pos_;
    }
    std::memcpy(out, buffer_.data() + (pos_ - buffer_begin_), n);
    pos_ += n;
    return true;
  }

 private:
  static constexpr std::uint64_t kChunk = 1 << 20;
  std::ifstream& in_;
  std::uint64_t pos_;
  std::uint64_t size_;
  std::vector<unsigned char> buffer_;
  std::uint64_t buffer_begin_ = 0;
};

// Walks a binary body: every element and list must fit in the bytes that follow the header.
void check_ply_binary_body(const std::string& path, std::ifstream& in, std::uint64_t begin,
                           std::uint64_t size, bool big_endian,
                           const std::vector<PlyElement>& elements) {
  ChunkReader body(in, begin, size);
  for (const PlyElement& e : elements) {
    std::uint64_t fixed = 0;
    bool has_list = false;
    for (const PlyProperty& p : e.properties) {
      fixed += p.size;
      has_list = has_list || p.list;
    }
    // Checked before the walk: even a property-less element costs assimp memory per instance.
    if (e.count > body.remaining() / std::max<std::uint64_t>(fixed, 1)) {
      fail(path, "PLY header claims " + std::to_string(e.count) + " '" + e.name +
                     "' elements, more than the file (" + std::to_string(size) + " bytes) holds");
    }
    if (!has_list) {
      body.skip(e.count * fixed);
      continue;
    }
    for (unsigned long long k = 0; k < e.count; ++k) {
      for (const PlyProperty& p : e.properties) {
        if (!p.list) {
          if (!body.skip(p.size))
            fail(path, "file ends inside '" + e.name + "' element " + std::to_string(k) +
                           " (truncated?)");
          continue;
        }
        unsigned char bytes[8] = {};
        if (!body.read(bytes, p.size))
          fail(path,
               "file ends inside '" + e.name + "' element " + std::to_string(k) + " (truncated?)");
        if (big_endian) std::reverse(bytes, bytes + p.size);
        std::uint64_t count = 0;
        for (std::size_t b = p.size; b-- > 0;) count = (count << 8) | bytes[b];
        if (p.count_signed && (bytes[p.size - 1] & 0x80) != 0)
          fail(path, "'" + e.name + "' element " + std::to_string(k) + " has a negative list size");
        if (count > body.remaining() / p.item_size)
          fail(path, "'" + e.name + "' element " + std::to_string(k) + " claims a list of " +
                         std::to_string(count) + " values, more than the file holds");
        body.skip(count * p.item_size);
      }
    }
  }
}

// Walks an ASCII body, one element per (non-blank) line as assimp reads it: there must be a line
// for every element, and every list may claim no more values than its line holds.
void check_ply_ascii_body(const std::string& path, std::ifstream& in, std::size_t header_lines,
                          std::uint64_t size, const std::vector<PlyElement>& elements) {
  std::uint64_t remaining = size - static_cast<std::uint64_t>(in.tellg());
  std::string text;
  std::size_t number = header_lines;
  for (const PlyElement& e : elements) {
    // Each element takes a line with at least one character and a newline.
    if (e.count > remaining / 2 + 1) {
      fail(path, "PLY header claims " + std::to_string(e.count) + " '" + e.name +
                     "' elements, more than the file (" + std::to_string(size) + " bytes) holds");
    }
    for (unsigned long long k = 0; k < e.count; ++k) {
      std::string_view line;
      do {
        if (!std::getline(in, text))
          fail(path, "file ends after " + std::to_string(k) + " of " + std::to_string(e.count) +
                         " '" + e.name + "' elements (truncated?)");
        ++number;
        line = text;
      } while (line.find_first_not_of(" \t\r") == std::string_view::npos);
      for (const PlyProperty& p : e.properties) {
        // A short line is read by assimp with zeros for the missing values (Blender writes such
        // files): only lists, which size allocations, must fit in their line.
        const std::string_view value = next_token(line);
        if (value.empty()) break;
        if (!p.list) continue;
        unsigned long long count = 0;
        if (!parse_number(value, count))
          fail(path, "line " + std::to_string(number) + ": malformed list size '" +
                         std::string(value.substr(0, 20)) + "'");
        for (unsigned long long c = 0; c < count; ++c) {
          if (next_token(line).empty())
            fail(path, "line " + std::to_string(number) + ": list claims " + std::to_string(count) +
                           " values, the line holds fewer");
        }
      }
    }
  }
}

void check_ply(const std::string& path, std::uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open for reading");
  std::string text;
  std::size_t number = 0;
  bool ascii = false, big_endian = false;
  std::vector<PlyElement> elements;
  bool ended = false;
  while (!ended && std::getline(in, text)) {
    ++number;
    const std::string where = "line " + std::to_string(number) + ": ";
    for (char c : text) {
      const auto u = static_cast<unsigned char>(c);
      if (u < 0x20 && c != '\t' && c != '\r')
        fail(path, where + "binary data in the PLY header (corrupt, or the header is truncated)");
    }
    std::string_view line(text);
    const std::string_view keyword = next_token(line);
    if (number == 1) {
      if (lower(std::string(keyword)) != "ply") fail(path, where + "not a PLY file");
      continue;
    }
    if (number == 2) {
      const std::string_view format = next_token(line);
      if (keyword != "format") fail(path, where + "PLY header lacks its format line");
      if (format == "ascii") {
        ascii = true;
      } else if (format == "binary_big_endian") {
        big_endian = true;
      } else if (format != "binary_little_endian") {
        fail(path, where + "unknown PLY format '" + std::string(format.substr(0, 40)) + "'");
      }
      continue;
    }
    if (keyword == "end_header") {
      ended = next_token(line).empty();
      if (!ended) fail(path, where + "malformed end_header line");
    } else if (keyword == "element") {
      PlyElement e;
      e.name = std::string(next_token(line).substr(0, 40));
      if (e.name.empty() || !parse_number(next_token(line), e.count))
        fail(path, where + "malformed element line");
      elements.push_back(std::move(e));
    } else if (keyword == "property") {
      if (elements.empty()) fail(path, where + "property before any element");
      PlyProperty p;
      std::string_view type = next_token(line);
      if (type == "list") {
        p.list = true;
        const std::string_view count_type = next_token(line);
        type = next_token(line);
        p.size = ply_type_size(count_type);
        p.count_signed = ply_type_is_signed(count_type);
        p.item_size = ply_type_size(type);
        if (!ascii && (p.size == 0 || p.item_size == 0 || !ply_type_is_integer(count_type)))
          fail(path, where + "malformed list property");
      } else {
        p.size = ply_type_size(type);
        if (!ascii && p.size == 0)
          fail(path, where + "unknown property type '" + std::string(type.substr(0, 40)) + "'");
      }
      if (next_token(line).empty()) fail(path, where + "property without a name");
      elements.back().properties.push_back(p);
    }
    // comment, obj_info and anything else: skipped, as assimp does.
  }
  if (!ended) fail(path, "PLY header has no end_header line (truncated or corrupt)");
  if (ascii) {
    check_ply_ascii_body(path, in, number, size, elements);
  } else {
    check_ply_binary_body(path, in, static_cast<std::uint64_t>(in.tellg()), size, big_endian,
                          elements);
  }
}

// ----- glTF: nesting and chunk sizes checked before assimp sees them -----
//
// assimp parses glTF JSON with a recursive parser and builds the node graph recursively: a file
// of a million '[' or a chain of 30,000 nodes overflows the stack. Real glTF JSON nests about ten
// levels deep and node chains (skeletons) rarely pass a hundred.
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

// Arithmetic on counts read from files: saturates instead of wrapping.
std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) {
  return a > UINT64_MAX - b ? UINT64_MAX : a + b;
}
std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b) {
  return b != 0 && a > UINT64_MAX / b ? UINT64_MAX : a * b;
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
//   allocated at its full count: one of 300 million elements in a 1 KB file took 23 GB;
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

// A binary glTF: a 12-byte header, then chunks (version 2) or one JSON block (version 1), each
// with its length; assimp allocates what they claim.
void check_glb(const std::string& path, std::uint64_t size) {
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

void check_gltf(const std::string& path, std::uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  check_gltf_json(path, text.str(), size);
}

// Runs `work` on a thread with a large stack and hands back its result or its exception.
// assimp's importers, its validation and aiNode's destructor recurse once per level of nesting in
// the file; the usual 8 MB hold about 15,000 levels of glTF nodes, and a hostile file needs only
// a few bytes per level. The stack is reserved address space, touched only as deep as used.
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

// ----- OFF variants read by assimp (COFF, NOFF, ...): counts checked against the size -----

// The first bytes of the file, for telling formats apart when the extension does not.
std::string file_start(const std::string& path, std::size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes(n, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(n));
  bytes.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return bytes;
}

// assimp allocates the header's vertex and face counts at once. Like our own OFF reader, require
// that they can fit: a vertex line has at least "0 0 0\n", a face line at least "0\n". assimp
// reads the header as a character stream, not as lines or tokens: blanks, line ends and # comment
// lines, the optional prefixes ST, C, N, 4 and n, then OFF, directly followed by the counts if no
// blank separates them ("OFF3 1 0" claims 3 vertices), a dimension after nOFF, and counts as
// 32-bit numbers that wrap on overflow. The header is read here exactly the same way: a looser
// reading once let "OFF333...3\n4 4 6" pass as 4 vertices, and assimp allocated 17 GB (found by
// fuzzing).
void check_off_counts(const std::string& path, std::uint64_t size) {
  constexpr std::size_t kHeaderBytes = std::size_t{1} << 20;
  const std::string text = file_start(path, kHeaderBytes);
  // assimp converts UTF-16 and UTF-32 text before parsing; such OFF files do not occur in practice.
  if (text.compare(0, 2, "\xFF\xFE") == 0 || text.compare(0, 2, "\xFE\xFF") == 0 ||
      text.compare(0, 4, std::string("\0\0\xFE\xFF", 4)) == 0)
    fail(path, "OFF file in UTF-16 or UTF-32; untangle reads OFF as ASCII or UTF-8");
  std::size_t pos = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // assimp drops the BOM
  auto at = [&](std::size_t k) { return pos + k < text.size() ? text[pos + k] : '\0'; };
  auto skip_blanks = [&] {  // assimp's NextToken
    for (;;) {
      while (at(0) == ' ' || at(0) == '\t' || at(0) == '\r' || at(0) == '\n') ++pos;
      if (at(0) != '#') return;
      while (pos < text.size() && at(0) != '\n' && at(0) != '\r') ++pos;
    }
  };
  auto number = [&] {  // assimp's strtoul10
    std::uint32_t value = 0;
    for (; at(0) >= '0' && at(0) <= '9'; ++pos)
      value = value * 10 + static_cast<std::uint32_t>(at(0) - '0');
    return std::uint64_t{value};
  };
  skip_blanks();
  if (at(0) == 'S' && at(1) == 'T') pos += 2;
  if (at(0) == 'C') ++pos;
  if (at(0) == 'N') ++pos;
  if (at(0) == '4') ++pos;
  const bool has_dimension = at(0) == 'n';
  if (has_dimension) ++pos;
  if (at(0) == 'O' && at(1) == 'F' && at(2) == 'F') pos += 3;
  skip_blanks();
  if (has_dimension) {
    number();
    skip_blanks();
  }
  const std::uint64_t nv = number();
  skip_blanks();
  const std::uint64_t nf = number();
  if (pos >= text.size() && text.size() < size)
    fail(path, "OFF header longer than " + std::to_string(kHeaderBytes) + " bytes");
  if (nv > size || nf > size || 6 * nv + 2 * nf > size + 1)
    fail(path, "header claims " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                   " faces, more than the file (" + std::to_string(size) + " bytes) can hold");
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

std::vector<Mesh> read_with_assimp(const std::string& path, Role role, const std::string& extension,
                                   std::uint64_t size) {
  Assimp::Importer importer;
  const std::string start = file_start(path, 16);
  // The checks go by content, not only by extension: when the importer of a known extension
  // refuses a file, assimp tries every importer on its content, so a PLY file named .glb reaches
  // the PLY importer (which looped forever on it without end_header: found by fuzzing). The one
  // exception is .stl: the STL importer takes every .stl file, and a binary STL's free 80-byte
  // header may start with anything.
  const bool stl = extension == ".stl";
  if (extension == ".ply" || (!stl && lower(start.substr(0, 3)) == "ply")) {
    check_ply(path, size);
  }
  if (extension == ".glb" || (!stl && start.compare(0, 4, "glTF") == 0)) {
    check_glb(path, size);
  } else if (extension == ".gltf") {
    check_gltf(path, size);
  }
  std::string_view first(start);
  const std::string keyword = lower(std::string(next_token(first)));
  // "off" anywhere in the first word: assimp also takes "OFF3" (counts glued to it) for OFF.
  if (extension == ".off" || (!stl && keyword.find("off") != std::string::npos)) {
    check_off_counts(path, size);
  }

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
    for (std::string& group : mesh.group_names) group = valid_utf8(group);
  }
  return meshes;
}

}  // namespace untangle
