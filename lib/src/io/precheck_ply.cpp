// The PLY precheck: every count of the header known to fit in the file before assimp reads it.
//
// assimp 5.2 loops forever on a PLY header without `end_header`, crashes on a damaged one, and
// sizes its arrays by the header's element counts and by each list's count without comparing
// them with the file. The header is parsed here and the body walked (binary: by byte counts;
// ASCII: one element per line), so that every count is known to fit in the file before assimp
// allocates anything.
#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "io/prechecks.h"
#include "untangle/error.h"

namespace untangle {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw Error(ExitCode::kUnreadableInput, path, message);
}

template <class T>
bool parse_number(std::string_view token, T& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size() && !token.empty();
}

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

}  // namespace

void precheck_ply(const std::string& path, std::uint64_t size) {
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

}  // namespace untangle
