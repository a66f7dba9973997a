// The assimp module's entry point: the interface table the library checks and calls
// (io/assimp_module.h).
#include <assimp/importerdesc.h>
#include <assimp/version.h>

#include <assimp/Importer.hpp>

#include "functions.h"

namespace untangle::assimp_module {

std::vector<ImporterInfo> importers() {
  std::vector<ImporterInfo> out;
  Assimp::Importer importer;
  for (std::size_t i = 0; i < importer.GetImporterCount(); ++i) {
    const aiImporterDesc* d = importer.GetImporterInfo(i);
    if (d == nullptr || d->mFileExtensions == nullptr) continue;
    out.push_back({d->mName != nullptr ? d->mName : "", d->mFileExtensions});
  }
  return out;
}

std::string assimp_version() {
  return std::to_string(aiGetVersionMajor()) + "." + std::to_string(aiGetVersionMinor()) + "." +
         std::to_string(aiGetVersionPatch());
}

}  // namespace untangle::assimp_module

extern "C" __attribute__((visibility("default"))) const untangle::assimp_module::Interface*
untangle_assimp_interface() {
  using namespace untangle::assimp_module;
  static const Interface table = [] {
    Interface t = interface_of_this_build();
    t.assimp_version = &assimp_version;
    t.read = &read;
    t.write = &write;
    t.carried = &carried;
    t.importers = &importers;
    t.exporters = &exporters;
    return t;
  }();
  return &table;
}
