// The one place where a run's written files are checked against its read files (issue 22 §1).
#include "output_plan.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "untangle/error.h"
#include "untangle/write_meshes.h"

namespace untangle::app {
namespace {

namespace fs = std::filesystem;

std::string lower_extension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

std::string beside(const std::string& file, const std::string& name) {
  const fs::path folder = fs::path(file).parent_path();
  return (folder / name).string();
}

// The material libraries an OBJ names (`mtllib a.mtl b.mtl`), relative to its folder.
void obj_side_files(const std::string& path, std::vector<std::string>& out) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  while (std::getline(in, line)) {
    std::size_t k = line.find_first_not_of(" \t");
    if (k == std::string::npos || line.compare(k, 6, "mtllib") != 0) continue;
    std::istringstream names(line.substr(k + 6));
    std::string name;
    while (names >> name) out.push_back(beside(path, name));
  }
}

// The buffers and images a glTF names by URI (not the embedded `data:` ones), relative to it.
void gltf_side_files(const std::string& path, std::vector<std::string>& out) {
  std::ifstream in(path, std::ios::binary);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return;  // the reader reports what is wrong with it
  for (const char* key : {"buffers", "images"}) {
    const auto it = j.find(key);
    if (it == j.end()) continue;
    // glTF 2 lists them in arrays, glTF 1 in objects keyed by id; both iterate over the values.
    for (const auto& item : *it) {
      if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
      const std::string uri = item["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0 || uri.find("://") != std::string::npos) continue;
      out.push_back(beside(path, uri));
    }
  }
}

// Identity of a file: device and inode when it exists (symlinks followed, so hard links and
// symlinks to one file are one file), else its absolute path with `..` and symlinked folders
// resolved.
struct FileIdentity {
  bool exists = false;
  dev_t device = 0;
  ino_t inode = 0;
  fs::path path;
};

FileIdentity identify(const std::string& path) {
  FileIdentity id;
  struct stat s {};
  if (::stat(path.c_str(), &s) == 0) {
    id.exists = true;
    id.device = s.st_dev;
    id.inode = s.st_ino;
  }
  std::error_code ec;
  id.path = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) id.path = fs::absolute(path, ec).lexically_normal();
  return id;
}

bool same_file(const FileIdentity& a, const FileIdentity& b) {
  if (a.exists && b.exists) return a.device == b.device && a.inode == b.inode;
  return a.path == b.path;
}

[[noreturn]] void refuse(const std::string& message) {
  throw Error(ExitCode::kOutputNotWritten, "", message);
}

}  // namespace

void add_read(const std::string& path, const std::string& label, std::vector<PlannedFile>& out) {
  out.push_back({path, label + " " + path});
  std::vector<std::string> side;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    return;  // a pipe is read once, by the reader, and fails there
  const std::string ext = lower_extension(path);
  if (ext == ".obj") obj_side_files(path, side);
  if (ext == ".gltf") gltf_side_files(path, side);
  for (const std::string& s : side)
    out.push_back({s, "the side file " + s + " of " + label + " " + path});
}

std::vector<PlannedFile> files_read(const CommonOptions& o) {
  std::vector<PlannedFile> read;
  for (const std::string& p : o.inputs) add_read(p, "the input", read);
  for (const std::string& p : o.obstacles) add_read(p, "the obstacle", read);
  for (const std::string& p : o.pin_files) add_read(p, "the pin file", read);
  return read;
}

std::vector<PlannedFile> files_written(const CommonOptions& o,
                                       const std::vector<std::string>& outputs) {
  std::vector<PlannedFile> written;
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    written.push_back({outputs[k], "output " + outputs[k]});
    if (k >= o.inputs.size()) continue;
    for (const std::string& side : side_files_of_output(o.inputs[k], outputs[k]))
      written.push_back({side, "side file " + side + " of output " + outputs[k]});
  }
  if (!o.report.empty() && o.report != "-") written.push_back({o.report, "--report " + o.report});
  if (!o.contours.empty() && o.contours != "-")
    written.push_back({o.contours, "--contours " + o.contours});
  if (!o.preview_png.empty())
    written.push_back({o.preview_png, "--preview picture " + o.preview_png});
  return written;
}

void check_written_files(const CommonOptions& o, const std::vector<std::string>& outputs) {
  if (o.report == "-" && o.contours == "-")
    refuse("--report - and --contours - cannot both be stdout; write one of them to a file");
  // Nothing written (a `check` without --report or --contours files): nothing to compare the
  // files read against, and finding an OBJ's side files reads it through once more.
  const std::vector<PlannedFile> written = files_written(o, outputs);
  if (written.empty()) return;
  check_planned(files_read(o), written, o.overwrite);
}

void check_planned(const std::vector<PlannedFile>& read, const std::vector<PlannedFile>& written,
                   bool overwrite) {
  std::vector<FileIdentity> read_ids, written_ids;
  for (const auto& f : read) read_ids.push_back(identify(f.path));
  for (const auto& f : written) written_ids.push_back(identify(f.path));
  for (std::size_t w = 0; w < written.size(); ++w) {
    const PlannedFile& file = written[w];
    for (std::size_t r = 0; r < read.size(); ++r) {
      if (same_file(written_ids[w], read_ids[r]))
        refuse(file.label + " is " + read[r].label + "; untangle never overwrites what it reads");
    }
    for (std::size_t v = 0; v < w; ++v) {
      if (same_file(written_ids[w], written_ids[v]))
        refuse(file.label + " is also " + written[v].label + "; each file is written once");
    }
    const fs::path target(file.path);
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
      refuse(file.label + ": folder " + folder.string() + " does not exist");
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
      refuse(file.label + ": folder " + folder.string() + " is not writable");
    if (fs::is_directory(target, ec)) refuse(file.label + " is a folder");
    // A dangling symlink exists too: the rename into place would replace it.
    if (fs::exists(fs::symlink_status(target, ec)) && !overwrite)
      refuse(file.label + " exists; pass --overwrite to replace it");
  }
}

}  // namespace untangle::app
