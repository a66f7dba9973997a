// Reading plain OFF: a header, a vertex list and a face list, one element per line.
#include "io/read_off.h"

#include <cmath>
#include <fstream>
#include <vector>

#include "io/off_text.h"
#include "untangle/error.h"

namespace untangle {

using off::fail_at;
using off::Line;
using off::LineReader;
using off::load;
using off::next_element;
using off::parse;
using off::parse_header;

bool is_plain_off(const std::string& path) {
  // Only the first word matters: read it byte by byte rather than as a string of unbounded size
  // (a large file without whitespace must not be loaded whole just to be told apart).
  std::ifstream in(path, std::ios::binary);
  char c = 0;
  while (in.get(c) && (c == ' ' || c == '\t' || c == '\r' || c == '\n')) {
  }
  if (!in || c != 'O') return false;
  if (!in.get(c) || c != 'F') return false;
  if (!in.get(c) || c != 'F') return false;
  return !in.get(c) || c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

Mesh read_off(const std::string& path, Role role) {
  constexpr ExitCode kCode = ExitCode::kUnreadableInput;
  const std::string text = load(path, kCode);
  LineReader reader(text);
  std::size_t nv = 0, nf = 0;
  parse_header(reader, path, kCode, text.size(), nv, nf);
  Mesh mesh;
  mesh.path = path;
  mesh.role = role;
  mesh.positions.reserve(nv);
  Line line;
  for (std::size_t i = 0; i < nv; ++i) {
    next_element(reader, line, path, kCode);
    Vec3 p{};
    if (line.tokens.size() < 3) fail_at(kCode, path, line.number, "malformed vertex");
    for (int k = 0; k < 3; ++k) {
      if (!parse(line.tokens[k], p[k])) fail_at(kCode, path, line.number, "malformed vertex");
      if (!std::isfinite(p[k]))
        fail_at(kCode, path, line.number, "vertex has a NaN or infinite coordinate");
    }
    mesh.positions.push_back(p);
  }
  std::vector<std::uint32_t> corners;
  for (std::size_t f = 0; f < nf; ++f) {
    next_element(reader, line, path, kCode);
    std::size_t count = 0;
    // The corner count is checked against the tokens present before anything is sized by it.
    if (!parse(line.tokens[0], count) || count > line.tokens.size() - 1)
      fail_at(kCode, path, line.number, "malformed face");
    corners.resize(count);
    for (std::size_t c = 0; c < count; ++c) {
      long long index = 0;
      if (!parse(line.tokens[c + 1], index)) fail_at(kCode, path, line.number, "malformed face");
      if (index < 0 || static_cast<unsigned long long>(index) >= nv)
        fail_at(kCode, path, line.number,
                "face refers to vertex " + std::to_string(index) + " but the file has " +
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
    throw Error(kCode, path,
                "no triangles (" + std::to_string(nf) + " faces); untangle needs surface meshes");
  return mesh;
}

}  // namespace untangle
