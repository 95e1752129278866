// Image decoding for mesh textures, through stb_image compiled here with
// internal linkage (so it cannot clash with another copy in the program).
#include <memory>

#include "mesh/load_support.hpp"
#include "pfill/error.hpp"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO  // we read files ourselves, so errors name them
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace pfill::detail {

Texture decode_image(const uint8_t* bytes, size_t size, const std::string& name) {
  if (size == 0 || size > static_cast<size_t>(INT32_MAX))
    throw Error(name + ": texture image is empty or too large to decode");
  int width = 0, height = 0, channels = 0;
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(bytes, static_cast<int>(size), &width, &height, &channels, 4), stbi_image_free);
  if (!pixels || width <= 0 || height <= 0)
    throw Error(name + ": texture image cannot be decoded (" +
                std::string(stbi_failure_reason() ? stbi_failure_reason() : "unknown reason") +
                "); use PNG or JPEG");
  Texture texture;
  texture.width = width;
  texture.height = height;
  texture.rgba.assign(pixels.get(), pixels.get() + static_cast<size_t>(width) * height * 4);
  texture.name = name;
  return texture;
}

Texture decode_image_file(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  return decode_image(bytes.data(), bytes.size(), path);
}

}  // namespace pfill::detail
