// Version text: the tool and the versions of the libraries compiled in.
#include "untangle/version.h"

#include <CGAL/version.h>
#include <Eigen/Core>

#include "io/assimp_module.h"
#include "untangle/error.h"

namespace untangle {

std::string untangle_version() { return UNTANGLE_VERSION; }

std::string version_text() {
  std::string text = std::string("untangle ") + UNTANGLE_VERSION + "\n";
  text += std::string("CGAL ") + CGAL_VERSION_STR + "\n";
  // The version of the libassimp the module is linked against: this loads the module.
  try {
    text += "assimp " + assimp_module::get("", ExitCode::kInternal).assimp_version() + "\n";
  } catch (const Error& e) {
    text += std::string("assimp unknown (") + e.what() + ")\n";
  }
  text += "Eigen " + std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) +
          "." + std::to_string(EIGEN_MINOR_VERSION);
  return text;
}

}  // namespace untangle
