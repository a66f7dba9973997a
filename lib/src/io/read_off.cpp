// OFF: a header, a vertex list and a face list, one element per line.
#include "io/read_off.h"

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>
#include <vector>

#include "untangle/error.h"

namespace untangle {
namespace {

std::string load(const std::string& path, ExitCode code) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(code, path, "cannot open for reading");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The file as lines of tokens, comments and blank lines dropped; each keeps its byte range.
struct Line {
  std::size_t number = 0;
  std::size_t begin = 0, end = 0;  // bytes of the line, newline excluded
  std::vector<std::string_view> tokens;
  std::vector<std::size_t> token_end;  // byte offset just past each token
};

std::vector<Line> split(const std::string& text) {
  std::vector<Line> lines;
  std::size_t pos = 0, number = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++number;
    Line line;
    line.number = number;
    line.begin = pos;
    line.end = end;
    std::size_t k = pos;
    while (k < end && text[k] != '#') {
      while (k < end && (text[k] == ' ' || text[k] == '\t' || text[k] == '\r')) ++k;
      if (k >= end || text[k] == '#') break;
      const std::size_t start = k;
      while (k < end && text[k] != ' ' && text[k] != '\t' && text[k] != '\r' && text[k] != '#') ++k;
      line.tokens.emplace_back(text.data() + start, k - start);
      line.token_end.push_back(k);
    }
    if (!line.tokens.empty()) lines.push_back(std::move(line));
    pos = end + 1;
  }
  return lines;
}

template <class T>
bool parse(std::string_view token, T& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

// Header and counts; returns the index of the first vertex line.
std::size_t parse_header(const std::vector<Line>& lines, const std::string& path, std::size_t bytes,
                         std::size_t& vertices, std::size_t& faces) {
  auto fail = [&](std::size_t n, const std::string& m) -> std::size_t {
    throw Error(ExitCode::kUnreadableInput, path, "line " + std::to_string(n) + ": " + m);
  };
  if (lines.empty() || lines[0].tokens[0] != "OFF") return fail(1, "not an OFF file");
  std::size_t at = 0;
  std::vector<std::string_view> counts(lines[0].tokens.begin() + 1, lines[0].tokens.end());
  if (counts.empty()) {
    if (lines.size() < 2) return fail(lines[0].number, "missing element counts");
    at = 1;
    counts = lines[1].tokens;
  }
  long long nv = 0, nf = 0;
  if (counts.size() < 2 || !parse(counts[0], nv) || !parse(counts[1], nf) || nv < 0 || nf < 0)
    return fail(lines[at].number, "malformed element counts");
  // Every element needs a line of at least a few bytes: larger counts cannot be in this file.
  if (static_cast<unsigned long long>(nv) + static_cast<unsigned long long>(nf) > bytes / 2)
    return fail(lines[at].number, "header claims " + std::to_string(nv) + " vertices and " +
                                      std::to_string(nf) + " faces, more than the file can hold");
  vertices = static_cast<std::size_t>(nv);
  faces = static_cast<std::size_t>(nf);
  if (lines.size() < at + 1 + vertices + faces)
    return fail(lines.back().number, "file ends early (truncated?)");
  return at + 1;
}

}  // namespace

bool is_plain_off(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string word;
  in >> word;
  return word == "OFF";
}

Mesh read_off(const std::string& path, Role role) {
  const std::string text = load(path, ExitCode::kUnreadableInput);
  const std::vector<Line> lines = split(text);
  std::size_t nv = 0, nf = 0;
  const std::size_t first = parse_header(lines, path, text.size(), nv, nf);
  auto fail = [&](std::size_t n, const std::string& m) {
    throw Error(ExitCode::kUnreadableInput, path, "line " + std::to_string(n) + ": " + m);
  };
  Mesh mesh;
  mesh.path = path;
  mesh.role = role;
  mesh.positions.reserve(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const Line& line = lines[first + i];
    Vec3 p{};
    if (line.tokens.size() < 3) fail(line.number, "malformed vertex");
    for (int k = 0; k < 3; ++k) {
      if (!parse(line.tokens[k], p[k])) fail(line.number, "malformed vertex");
      if (!std::isfinite(p[k])) fail(line.number, "vertex has a NaN or infinite coordinate");
    }
    mesh.positions.push_back(p);
  }
  for (std::size_t f = 0; f < nf; ++f) {
    const Line& line = lines[first + nv + f];
    std::size_t count = 0;
    if (!parse(line.tokens[0], count) || line.tokens.size() < count + 1) fail(line.number, "malformed face");
    std::vector<std::uint32_t> corners(count);
    for (std::size_t c = 0; c < count; ++c) {
      long long index = 0;
      if (!parse(line.tokens[c + 1], index)) fail(line.number, "malformed face");
      if (index < 0 || static_cast<std::size_t>(index) >= nv)
        fail(line.number, "face refers to vertex " + std::to_string(index) + " but the file has " +
                              std::to_string(nv) + " vertices");
      corners[c] = static_cast<std::uint32_t>(index);
    }
    for (std::size_t c = 2; c < count; ++c) {
      mesh.triangles.push_back({corners[0], corners[c - 1], corners[c]});
      mesh.polygon.push_back(static_cast<std::uint32_t>(f));
    }
  }
  mesh.source_faces = nf;
  if (mesh.triangles.empty())
    throw Error(ExitCode::kUnreadableInput, path,
                "no triangles (" + std::to_string(nf) + " faces); untangle needs surface meshes");
  return mesh;
}

std::string rewrite_off(const std::string& input, const Mesh& mesh) {
  const std::string text = load(input, ExitCode::kOutputNotWritten);
  const std::vector<Line> lines = split(text);
  std::size_t nv = 0, nf = 0;
  std::size_t first = 0;
  try {
    first = parse_header(lines, input, text.size(), nv, nf);
  } catch (const Error& e) {
    throw Error(ExitCode::kOutputNotWritten, input, e.what());
  }
  if (nv != mesh.positions.size()) throw Error(ExitCode::kOutputNotWritten, input, "vertex count changed");
  std::string out;
  std::size_t copied = 0;
  for (std::size_t i = 0; i < nv; ++i) {
    const Line& line = lines[first + i];
    Vec3 old{};
    for (int k = 0; k < 3; ++k) parse(line.tokens[k], old[k]);
    if (old == mesh.positions[i]) continue;
    const std::size_t start = static_cast<std::size_t>(line.tokens[0].data() - text.data());
    out.append(text, copied, start - copied);
    for (int k = 0; k < 3; ++k) {
      std::array<char, 32> buffer{};
      const auto r = std::to_chars(buffer.data(), buffer.data() + buffer.size(), mesh.positions[i][k]);
      if (k > 0) out += ' ';
      out.append(buffer.data(), r.ptr);
    }
    copied = line.token_end[2];
  }
  out.append(text, copied, std::string::npos);
  return out;
}

}  // namespace untangle
