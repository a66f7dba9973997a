// Fixed values for the clock readings, temporary paths and pointers in exported files.
#include "io/deterministic_export.h"

#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "untangle/error.h"

namespace untangle {
namespace {

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_all(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.flush();
  if (!out) throw Error(ExitCode::kOutputNotWritten, path, "write failed");
}

// FBX's CreationTimeStamp block: Year, Month, Day, Hour, Minute, Second, Millisecond.
std::string fixed_fbx_clock(const std::string& text) {
  const std::size_t start = text.find("CreationTimeStamp:");
  if (start == std::string::npos) return text;
  const std::size_t end = text.find('}', start);
  if (end == std::string::npos) return text;
  static const std::regex field(R"((Year|Month|Day|Hour|Minute|Second|Millisecond): *-?[0-9]+)");
  std::string block = text.substr(start, end - start);
  std::string out;
  std::size_t last = 0;
  for (auto it = std::sregex_iterator(block.begin(), block.end(), field); it != std::sregex_iterator(); ++it) {
    const std::string name = (*it)[1].str();
    const char* value = name == "Year" ? "1970" : (name == "Month" || name == "Day") ? "1" : "0";
    out.append(block, last, static_cast<std::size_t>(it->position()) - last);
    out += name + ": " + value;
    last = static_cast<std::size_t>(it->position() + it->length());
  }
  out.append(block, last, std::string::npos);
  return text.substr(0, start) + out + text.substr(end);
}

// assbin: a 44-byte header "ASSIMP.binary-dump.<asctime>", then five 32-bit fields, then the
// source path in a zero-padded field of 256 bytes.
void fix_assbin(std::string& data, const std::string& path, const std::string& final_name) {
  const std::string magic = "ASSIMP.binary-dump.";
  if (data.size() < 64 + 256 || data.compare(0, magic.size(), magic) != 0) return;
  std::memset(&data[magic.size()], 0, 44 - magic.size());
  std::string name = final_name.substr(0, 255);
  name.resize(256, '\0');
  if (data.compare(64, path.size(), path) == 0 || data[64] != '\0') data.replace(64, 256, name);
}

}  // namespace

void finish_deterministic_export(const std::string& format_id, const std::string& path,
                                 const std::string& final_name) {
  if (format_id == "collada") {
    static const std::regex created(R"(<(created|modified)>[^<]*</(created|modified)>)");
    write_all(path, std::regex_replace(read_all(path), created, "<$1>1970-01-01T00:00:00</$2>"));
  } else if (format_id == "fbxa") {
    write_all(path, fixed_fbx_clock(read_all(path)));
  } else if (format_id == "assbin") {
    std::string data = read_all(path);
    fix_assbin(data, path, final_name);
    write_all(path, data);
  }
}

}  // namespace untangle
