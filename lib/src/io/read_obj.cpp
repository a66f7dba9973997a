// OBJ reading: v and f lines in file order; everything else is ignored for analysis.
#include "io/read_obj.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string_view>

#include "untangle/error.h"

namespace untangle {
namespace {

[[noreturn]] void fail(const std::string& path, std::size_t line, const std::string& message) {
  throw Error(ExitCode::kUnreadableInput, path, "line " + std::to_string(line) + ": " + message);
}

void skip_space(std::string_view& s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
}

std::string_view next_token(std::string_view& s) {
  skip_space(s);
  std::size_t n = 0;
  while (n < s.size() && s[n] != ' ' && s[n] != '\t' && s[n] != '\r') ++n;
  std::string_view token = s.substr(0, n);
  s.remove_prefix(n);
  return token;
}

bool parse_double(std::string_view token, double& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

}  // namespace

Mesh read_obj(const std::string& path, Role role) {
  // The whole file in one read, then split at '\n' in place (as getline would split it).
  std::string text;
  {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw Error(ExitCode::kUnreadableInput, path, "cannot open for reading");
    const std::streamoff size = in.tellg();
    if (size < 0) throw Error(ExitCode::kUnreadableInput, path, "read error");
    text.resize(static_cast<std::size_t>(size));
    in.seekg(0);
    if (!in.read(text.data(), size)) throw Error(ExitCode::kUnreadableInput, path, "read error");
  }
  Mesh mesh;
  mesh.path = path;
  mesh.role = role;
  std::size_t number = 0;
  std::vector<long long> corners;
  std::size_t faces_total = 0;
  std::size_t short_faces = 0;  // `f` lines with one or two corners: skipped, kept in the output
  std::string object;  // the name of the last `o` line
  const char* const end_of_text = text.data() + text.size();
  for (const char* at = text.data(); at < end_of_text;) {
    const char* newline = static_cast<const char*>(std::memchr(at, '\n', end_of_text - at));
    const char* line_end = newline != nullptr ? newline : end_of_text;
    std::string_view line(at, static_cast<std::size_t>(line_end - at));
    at = newline != nullptr ? newline + 1 : end_of_text;
    ++number;
    const std::string_view keyword = next_token(line);
    if (keyword == "v") {
      Vec3 p{};
      for (double& c : p) {
        if (!parse_double(next_token(line), c)) fail(path, number, "malformed vertex");
        if (!std::isfinite(c)) fail(path, number, "vertex has a NaN or infinite coordinate");
      }
      mesh.positions.push_back(p);
    } else if (keyword == "f") {
      corners.clear();
      for (std::string_view token = next_token(line); !token.empty(); token = next_token(line)) {
        const std::string_view index = token.substr(0, token.find('/'));
        long long value = 0;
        const auto [end, ec] = std::from_chars(index.data(), index.data() + index.size(), value);
        if (ec != std::errc() || end != index.data() + index.size() || value == 0) {
          fail(path, number, "malformed face");
        }
        // Negative indices count back from the last vertex read so far.
        const long long resolved =
            value > 0 ? value - 1 : static_cast<long long>(mesh.positions.size()) + value;
        if (resolved < 0 || resolved >= static_cast<long long>(mesh.positions.size())) {
          fail(path, number, "face refers to vertex " + std::string(index) + " but only " +
                                 std::to_string(mesh.positions.size()) + " are defined before it");
        }
        corners.push_back(resolved);
      }
      if (corners.size() == 0) fail(path, number, "face without corners");
      if (corners.size() < 3) ++short_faces;
      for (std::size_t c = 2; c < corners.size(); ++c) {
        mesh.triangles.push_back({static_cast<std::uint32_t>(corners[0]),
                                  static_cast<std::uint32_t>(corners[c - 1]),
                                  static_cast<std::uint32_t>(corners[c])});
        mesh.polygon.push_back(static_cast<std::uint32_t>(faces_total));
        if (!mesh.group_names.empty()) {
          mesh.triangle_group.push_back(static_cast<std::uint32_t>(mesh.group_names.size() - 1));
        }
      }
      ++faces_total;
    } else if (keyword == "o" || keyword == "g") {
      skip_space(line);
      std::string name(line);
      while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
      if (mesh.name.empty()) mesh.name = name;
      // Triangles before the first group belong to an unnamed one.
      if (mesh.group_names.empty() && !mesh.triangles.empty()) {
        mesh.group_names.emplace_back();
        mesh.group_objects.emplace_back();
        mesh.triangle_group.assign(mesh.triangles.size(), 0);
      }
      if (keyword == "o") object = name;
      mesh.group_names.push_back(name);
      mesh.group_objects.push_back(object);
    }
  }
  mesh.source_faces = faces_total;
  if (short_faces > 0) {
    mesh.warnings.push_back(std::to_string(short_faces) + (short_faces == 1 ? " face" : " faces") +
                            " with fewer than 3 corners skipped (their lines are kept in the "
                            "output)");
  }
  if (mesh.triangles.empty()) {
    throw Error(ExitCode::kUnreadableInput, path,
                "no triangles (" + std::to_string(mesh.positions.size()) +
                    " vertices, 0 faces); untangle needs surface meshes");
  }
  return mesh;
}

}  // namespace untangle
