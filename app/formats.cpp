// `untangle formats`: the lists of untangle/formats.h, printed like `assimp listexport`.
#include "formats.h"

#include <cstdio>
#include <string>
#include <vector>

#include "untangle/formats.h"

namespace untangle::app {

int run_formats() {
  auto print = [](const char* title, const std::vector<FileFormat>& formats) {
    std::printf("%s\n", title);
    for (const FileFormat& f : formats) std::printf("  %-8s %s\n", f.extension.c_str(), f.description.c_str());
  };
  print("read (info, check, fix; --obstacle):", readable_formats());
  print("write (fix -o, --output-dir; the extension chooses the format):", writable_formats());
  return 0;
}

}  // namespace untangle::app
