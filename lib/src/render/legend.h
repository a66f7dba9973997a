// The legend's box: its size is known before drawing, so that cameras can leave room for it.
#pragma once

#include <cstddef>

namespace untangle::render {

// The legend's glyph scale in a picture of width x height: 2 from 800 pixels on, else 1.
inline int legend_scale(int width, int height) { return (width < height ? width : height) >= 800 ? 2 : 1; }

// Pixels from the picture's top to the bottom of a legend of `lines` lines (0 without lines),
// the margin below it included.
inline int legend_bottom(std::size_t lines, int width, int height) {
  if (lines == 0) return 0;
  const int scale = legend_scale(width, height);
  return 4 * scale + 4 * scale + 12 * scale * static_cast<int>(lines) + 4 * scale + 4 * scale;
}

}  // namespace untangle::render
