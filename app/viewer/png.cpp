#include "app/viewer/png.h"

#include <cstdint>
#include <vector>

#include <stb/stb_image_write.h>

#include "app/viewer/gl.h"
#include <carom/files.h>

namespace carom::viewer {

void writeFramePng(const std::string& path, int width, int height) {
    std::vector<std::uint8_t> pixels(std::size_t(width) * height * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    io::AtomicFile file(path);
    auto write = [](void* context, void* data, int size) {
        static_cast<io::AtomicFile*>(context)->stream().write(static_cast<const char*>(data), size);
    };
    stbi_flip_vertically_on_write(1);  // OpenGL rows run bottom-up
    stbi_write_png_to_func(write, &file, width, height, 4, pixels.data(), width * 4);
    file.commit();
}

}  // namespace carom::viewer
