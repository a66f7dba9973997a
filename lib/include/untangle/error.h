// The one error type of untangle: a failure kind (mapped to an exit code), the file, a message.
#pragma once

#include <stdexcept>
#include <string>

namespace untangle {

// Exit codes of the CLI: part of its interface, listed in the man page (EXIT STATUS).
// "Intersections remain" is a result, not an error, but it has its own code so that pipelines can
// branch on it.
enum class ExitCode : int {
  kOk = 0,            // success: written and intersection-free, or `check` found nothing
  kInternal = 1,      // a bug or an unexpected library failure
  kUsage = 2,         // bad command line
  kUnreadableInput = 3,
  kOutputNotWritten = 4,
  kIntersecting = 5,  // intersections found (check) or remaining (fix)
  kDistorted = 6,     // fix: intersection-free, but a mesh's shape beyond the quality bounds
};

// Thrown for bad input, I/O failure and refused overwrites. `what()` is the full one-line message
// ("body.obj: no triangles (0 faces); untangle needs surface meshes"); `path()` the file concerned.
class Error : public std::runtime_error {
 public:
  Error(ExitCode code, std::string path, const std::string& message)
      : std::runtime_error(path.empty() ? message : path + ": " + message),
        code_(code),
        path_(std::move(path)) {}

  ExitCode code() const { return code_; }
  const std::string& path() const { return path_; }

 private:
  ExitCode code_;
  std::string path_;
};

}  // namespace untangle
