// PNG files of the current OpenGL frame, written through io::AtomicFile so a
// failed write never leaves a partial image.
#pragma once

#include <string>

namespace carom::viewer {

// Reads the framebuffer (width x height, bottom-up) and writes it as PNG.
void writeFramePng(const std::string& path, int width, int height);

}  // namespace carom::viewer
