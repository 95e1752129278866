// PNG output through stb_image_write. The implementation is compiled here,
// static (STB_IMAGE_WRITE_STATIC), so it cannot clash with the stb symbols
// that Debian's libtinygltf pulls in from libstb.
#include <string>

#include "pfill/atomic_file.hpp"
#include "pfill/error.hpp"
#include "pfill/render.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace pfill {
namespace {

void append_bytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<size_t>(size));
}

}  // namespace

void write_png(const Image& image, const std::filesystem::path& path) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<size_t>(image.width) * image.height * 3)
    throw Error("cannot write '" + path.string() + "': the image is empty or its size does not match its pixels");
  std::string png;
  if (!stbi_write_png_to_func(append_bytes, &png, image.width, image.height, 3, image.rgb.data(),
                              image.width * 3))
    throw Error("cannot write '" + path.string() + "': PNG encoding failed");
  write_file_atomically(path, [&](AtomicFile& file) { file.write(png); });
}

}  // namespace pfill
