// OFF text as lines of tokens, shared by the OFF reader and the OFF rewriter.
#pragma once

#include <charconv>
#include <cstddef>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "untangle/error.h"

// The reader (read_off) and the rewriter (rewrite_off) must parse the same text the same way: a
// file the reader accepted is rewritten token for token. Errors are thrown with the caller's
// exit code: unreadable input for the reader, output not written for the rewriter.
namespace untangle::off {

// The whole file; Error(code) if it cannot be opened.
std::string load(const std::string& path, ExitCode code);

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
  bool next(Line& line);

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
                          const std::string& message);

// Reads the header and the element counts; the reader is left before the first vertex line.
void parse_header(LineReader& reader, const std::string& path, ExitCode code, std::size_t bytes,
                  std::size_t& vertices, std::size_t& faces);

// The next element line, or an error naming the last line read when the file ends early.
void next_element(LineReader& reader, Line& line, const std::string& path, ExitCode code);

}  // namespace untangle::off
