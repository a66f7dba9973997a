// The checks a mesh file passes before assimp reads it, one file per format (precheck_*.cpp).
#pragma once

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace untangle {

// assimp 5.2 believes what a file claims: counts, lengths and nesting size its allocations and
// its recursion before anything is compared with the file. Each precheck reads as much of the
// file (of `size` bytes) as it takes to know that what it claims fits, and throws
// Error(kUnreadableInput) naming what does not.

// PLY: the header parsed and the body walked, so that every element count and list size is known
// to fit in the file.
void precheck_ply(const std::string& path, std::uint64_t size);

// Binary glTF: the chunk lengths of the header, then the JSON chunk as precheck_gltf checks it.
// A file without the GLB magic is left to assimp.
void precheck_glb(const std::string& path, std::uint64_t size);

// glTF JSON: nesting, node hierarchy depth and the sizes its accessors claim.
void precheck_gltf(const std::string& path, std::uint64_t size);

// The OFF variants assimp reads (COFF, NOFF, ...): the header's counts against the size.
void precheck_off(const std::string& path, std::uint64_t size);

// Every precheck that applies to a file assimp is about to read, by its extension (with the dot,
// lower case) and by its first bytes: for every ReadFile of an input, the reader's and the
// writer's (read_meshes.cpp).
void precheck_for_assimp(const std::string& path, const std::string& extension,
                         std::uint64_t size);

// ----- shared by the prechecks and the reader -----

inline std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// The extension of `path` in lower case, without the dot: "obj", "gltf" ("" when none).
inline std::string extension_of(const std::string& path) {
  std::string ext = lower(std::filesystem::path(path).extension().string());
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  return ext;
}

// Splits off the next token of blanks-separated text.
inline std::string_view next_token(std::string_view& s) {
  std::size_t k = 0;
  while (k < s.size() && (s[k] == ' ' || s[k] == '\t' || s[k] == '\r')) ++k;
  std::size_t n = k;
  while (n < s.size() && s[n] != ' ' && s[n] != '\t' && s[n] != '\r') ++n;
  const std::string_view token = s.substr(k, n - k);
  s.remove_prefix(n);
  return token;
}

// The first bytes of the file, for telling formats apart when the extension does not.
inline std::string file_start(const std::string& path, std::size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes(n, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(n));
  bytes.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return bytes;
}

// Arithmetic on counts read from files: saturates instead of wrapping.
inline std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) {
  return a > UINT64_MAX - b ? UINT64_MAX : a + b;
}
inline std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b) {
  return b != 0 && a > UINT64_MAX / b ? UINT64_MAX : a * b;
}

}  // namespace untangle
