// Rewriting a plain OFF file: only the coordinates of moved vertices change.
#include "io/write_off.h"

#include <array>
#include <charconv>

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
