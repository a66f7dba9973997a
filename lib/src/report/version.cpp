// Version text: the tool and the versions of the libraries compiled in.
#include "untangle/version.h"

#include <CGAL/version.h>
#include <Eigen/Core>
#include <assimp/version.h>

namespace untangle {

std::string untangle_version() { return UNTANGLE_VERSION; }

std::string version_text() {
  std::string text = std::string("untangle ") + UNTANGLE_VERSION + "\n";
  text += std::string("CGAL ") + CGAL_VERSION_STR + "\n";
  text += "assimp " + std::to_string(aiGetVersionMajor()) + "." +
          std::to_string(aiGetVersionMinor()) + "." + std::to_string(aiGetVersionPatch()) + "\n";
  text += "Eigen " + std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) +
          "." + std::to_string(EIGEN_MINOR_VERSION);
  return text;
}

}  // namespace untangle
