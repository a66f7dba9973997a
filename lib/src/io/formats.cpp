// The format lists of `untangle formats`, from assimp's registered importers and exporters (as
// the assimp module lists them).
#include "untangle/formats.h"

#include <algorithm>
#include <map>
#include <sstream>

#include "io/assimp_module.h"
#include "io/verified_exports.h"
#include "untangle/error.h"

namespace untangle {

std::vector<FileFormat> readable_formats() {
  std::map<std::string, std::string> by_extension;
  by_extension["obj"] = "Wavefront OBJ (read by untangle: one mesh per file, vertices in file order)";
  by_extension["off"] = "Object File Format (plain OFF read by untangle; COFF, NOFF, ... through assimp)";
  for (const assimp_module::ImporterInfo& d :
       assimp_module::get("", ExitCode::kUnreadableInput).importers()) {
    std::istringstream extensions(d.extensions);
    std::string ext;
    while (extensions >> ext) {
      std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
      if (!ext.empty()) by_extension.emplace(ext, d.name + " (assimp)");
    }
  }
  std::vector<FileFormat> out;
  for (const auto& [ext, description] : by_extension) out.push_back({ext, description});
  return out;
}

std::vector<FileFormat> writable_formats() {
  std::map<std::string, std::string> by_extension;
  by_extension["obj"] = "Wavefront OBJ (an OBJ input: its text with the moved v lines rewritten; "
                        "other inputs through assimp, with a .mtl side file)";
  by_extension["off"] = "Object File Format (from a plain OFF input only: its text with the moved "
                        "vertices rewritten)";
  for (const assimp_module::ExporterInfo& d :
       assimp_module::get("", ExitCode::kUnreadableInput).exporters()) {
    const std::string& ext = d.extension;
    if (!is_verified_export(ext)) continue;
    std::string description = d.description + " (assimp)";
    if (ext == "gltf") description += ", with a .bin side file";
    if (ext == "fbx") description = "Autodesk FBX, ASCII (assimp; assimp 5.2 cannot read back its binary FBX)";
    if (ext == "ply" || ext == "stl") description += ", binary when the input is binary " + ext;
    by_extension.emplace(ext, description);
  }
  std::vector<FileFormat> out;
  for (const auto& [ext, description] : by_extension) out.push_back({ext, description});
  return out;
}

}  // namespace untangle
