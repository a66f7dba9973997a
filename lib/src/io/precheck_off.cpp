// The OFF precheck: the header counts of the variants assimp reads (COFF, NOFF, ...) must fit.
#include <cstdint>
#include <string>

#include "io/prechecks.h"
#include "untangle/error.h"

namespace untangle {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw Error(ExitCode::kUnreadableInput, path, message);
}

}  // namespace

// assimp allocates the header's vertex and face counts at once. Like our own OFF reader, require
// that they can fit: a vertex line has at least "0 0 0\n", a face line at least "0\n". assimp
// reads the header as a character stream, not as lines or tokens: blanks, line ends and # comment
// lines, the optional prefixes ST, C, N, 4 and n, then OFF, directly followed by the counts if no
// blank separates them ("OFF3 1 0" claims 3 vertices), a dimension after nOFF, and counts as
// 32-bit numbers that wrap on overflow. The header is read here exactly the same way: any looser
// reading can pass counts other than the ones assimp allocates.
void precheck_off(const std::string& path, std::uint64_t size) {
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

}  // namespace untangle
