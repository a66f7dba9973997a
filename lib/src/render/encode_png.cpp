// PNG encoding of a picture with stb_image_write (Debian libstb-dev), compiled in here so that the
// bytes depend neither on the system's zlib nor on the machine.
#include <string>

#include "untangle/render.h"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

namespace untangle {

namespace {

void append(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             static_cast<std::size_t>(size));
}

}  // namespace

std::string encode_png(const RgbImage& image) {
  std::string bytes;
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * 3) {
    return bytes;
  }
  stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.pixels.data(),
                         image.width * 3);
  return bytes;
}

}  // namespace untangle
