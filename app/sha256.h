// SHA-256 (FIPS 180-4) of a file, for the input hashes `untangle batch` records and --resume compares.
#pragma once

#include <string>

namespace untangle::app {

// The lower-case hex SHA-256 of `bytes`.
std::string sha256_hex(const std::string& bytes);

// The lower-case hex SHA-256 of the file at `path`; throws Error(kUnreadableInput) naming it when
// it cannot be read.
std::string sha256_of_file(const std::string& path);

}  // namespace untangle::app
