// The functions of the assimp module behind io/assimp_module.h's Interface (one each).
#pragma once

#include <string>
#include <vector>

#include "io/assimp_module.h"

namespace untangle::assimp_module {

std::vector<Mesh> read(const std::string& path, Role role);  // read.cpp
std::string write(const std::string& input, const std::string& output,
                  const std::string& final_folder, const std::vector<const Mesh*>& meshes,
                  const PatchInPlace& patch_in_place);  // write.cpp
bool carried(const std::string& input, Carried& out);   // write.cpp
std::vector<ExporterInfo> exporters();                  // write.cpp
std::vector<ImporterInfo> importers();                  // entry.cpp
std::string assimp_version();                           // entry.cpp

}  // namespace untangle::assimp_module
