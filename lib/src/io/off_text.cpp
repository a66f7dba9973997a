// OFF text as lines of tokens: loading, line splitting, the header and its element counts.
#include "io/off_text.h"

#include <fstream>
#include <sstream>

namespace untangle::off {

std::string load(const std::string& path, ExitCode code) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(code, path, "cannot open for reading");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool LineReader::next(Line& line) {
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
      while (k < end && text_[k] != ' ' && text_[k] != '\t' && text_[k] != '\r' && text_[k] != '#')
        ++k;
      line.tokens.emplace_back(text_.data() + start, k - start);
      line.token_end.push_back(k);
    }
    pos_ = end + 1;
    if (!line.tokens.empty()) return true;
  }
  return false;
}

[[noreturn]] void fail_at(ExitCode code, const std::string& path, std::size_t line,
                          const std::string& message) {
  throw Error(code, path, "line " + std::to_string(line) + ": " + message);
}

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

void next_element(LineReader& reader, Line& line, const std::string& path, ExitCode code) {
  if (!reader.next(line)) fail_at(code, path, reader.line_number(), "file ends early (truncated?)");
}

}  // namespace untangle::off
