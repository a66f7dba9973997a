// Version of untangle and of the libraries it was built with.
#pragma once

#include <string>

namespace untangle {

// "untangle X.Y.Z" followed by one line each for CGAL, assimp and Eigen.
std::string version_text();

// "X.Y.Z", the version of untangle alone (as in every JSON report's `untangle_version`).
std::string untangle_version();

}  // namespace untangle
