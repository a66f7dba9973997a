// Version of untangle and of the libraries it was built with.
#pragma once

#include <string>

namespace untangle {

// "untangle X.Y.Z" followed by one line each for CGAL, assimp and Eigen. The assimp line loads
// the assimp module (io/assimp_module.h): "assimp 5.2.5", or "assimp unknown (why)" when it
// cannot be loaded.
std::string version_text();

// "X.Y.Z", the version of untangle alone (as in every JSON report's `untangle_version`).
std::string untangle_version();

}  // namespace untangle
