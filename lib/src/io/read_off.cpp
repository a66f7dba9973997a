// OFF: a header, a vertex list and a face list, one element per line.
#include "io/read_off.h"

#include <array>
#include <charconv>
#include <cmath>
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

// One line of tokens, comments dropped, with the byte offset just past each token.
struct Line {
  std::size_t number = 0;
  std::vector<std::string_view> tokens;
  std::vector<std::size_t> token_end;
};

// Walks the text one line at a time, skipping blank and comment-only lines. Nothing is kept for
// lines already passed, so memory stays proportional to the file size, not to its line count
// (a file of a billion two-byte lines must not cost a billion line records).
class LineReader {
 public:
  explicit LineReader(const std::string& text) : text_(text) {}

  // The next line with at least one token, or false at the end of the text.
  bool next(Line& line) {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string::npos) end = text_.size();
      ++number_;
      line.number = number_;
      line.tokens.clear();
      line.token_end.clear();
      std::size_t k = pos_;
      while (k < end && text_[k] != '#') {
        while (k < end && (text_[k] == ' ' || text_[k] == '\t' || text_[k] == '\r')) ++k;
        if (k >= end || text_[k] == '#') break;
        const std::size_t start = k;
        while (k < end && text_[k] != ' ' && text_[k] != '\t' && text_[k] != '\r' &&
               text_[k] != '#')
          ++k;
        line.tokens.emplace_back(text_.data() + start, k - start);
        line.token_end.push_back(k);
      }
      pos_ = end + 1;
      if (!line.tokens.empty()) return true;
    }
    return false;
  }

  // The number of the last line looked at (1-based; 0 before the first).
  std::size_t line_number() const { return number_; }

 private:
  const std::string& text_;
  std::size_t pos_ = 0, number_ = 0;
};

template <class T>
bool parse(std::string_view token, T& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

[[noreturn]] void fail_at(ExitCode code, const std::string& path, std::size_t line,
                          const std::string& message) {
  throw Error(code, path, "line " + std::to_string(line) + ": " + message);
}

// Reads the header and the element counts; the reader is left before the first vertex line.
void parse_header(LineReader& reader, const std::string& path, ExitCode code, std::size_t bytes,
                  std::size_t& vertices, std::size_t& faces) {
  Line line;
  if (!reader.next(line) || line.tokens[0] != "OFF") fail_at(code, path, 1, "not an OFF file");
  std::vector<std::string_view> counts(line.tokens.begin() + 1, line.tokens.end());
  if (counts.empty()) {
    if (!reader.next(line)) fail_at(code, path, reader.line_number(), "missing element counts");
    counts = line.tokens;
  }
  unsigned long long nv = 0, nf = 0;
  if (counts.size() < 2 || !parse(counts[0], nv) || !parse(counts[1], nf))
    fail_at(code, path, line.number, "malformed element counts");
  // Before anything is allocated: a vertex line holds at least "0 0 0" and a newline, a face
  // line at least one number and a newline (the last line may lack its newline). Larger counts
  // cannot be in this file, whatever it holds.
  if (nv > bytes || nf > bytes || 6 * nv + 2 * nf > bytes + 1)
    fail_at(code, path, line.number,
            "header claims " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                " faces, more than the file (" + std::to_string(bytes) + " bytes) can hold");
  vertices = static_cast<std::size_t>(nv);
  faces = static_cast<std::size_t>(nf);
}

// The next element line, or an error naming the last line read when the file ends early.
void next_element(LineReader& reader, Line& line, const std::string& path, ExitCode code) {
  if (!reader.next(line)) fail_at(code, path, reader.line_number(), "file ends early (truncated?)");
}

}  // namespace

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

std::string rewrite_off(const std::string& input, const Mesh& mesh) {
  constexpr ExitCode kCode = ExitCode::kOutputNotWritten;
  const std::string text = load(input, kCode);
  LineReader reader(text);
  std::size_t nv = 0, nf = 0;
  parse_header(reader, input, kCode, text.size(), nv, nf);
  if (nv != mesh.positions.size()) throw Error(kCode, input, "vertex count changed");
  std::string out;
  std::size_t copied = 0;
  Line line;
  for (std::size_t i = 0; i < nv; ++i) {
    next_element(reader, line, input, kCode);
    if (line.tokens.size() < 3) fail_at(kCode, input, line.number, "malformed vertex");
    Vec3 old{};
    for (int k = 0; k < 3; ++k) parse(line.tokens[k], old[k]);
    if (old == mesh.positions[i]) continue;
    const std::size_t start = static_cast<std::size_t>(line.tokens[0].data() - text.data());
    out.append(text, copied, start - copied);
    for (int k = 0; k < 3; ++k) {
      std::array<char, 32> buffer{};
      const auto r =
          std::to_chars(buffer.data(), buffer.data() + buffer.size(), mesh.positions[i][k]);
      if (k > 0) out += ' ';
      out.append(buffer.data(), r.ptr);
    }
    copied = line.token_end[2];
  }
  out.append(text, copied, std::string::npos);
  return out;
}

}  // namespace untangle
