// Whole-file reading for the particle readers, with errors that name the file.
#pragma once
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "pfill/error.hpp"

namespace pfill {

inline std::string read_file_bytes(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw Error("cannot read '" + path.string() + "': no such file");
  if (std::filesystem::is_directory(path, ec))
    throw Error("cannot read '" + path.string() + "': it is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path.string() + "': cannot open it (check permissions)");
  std::string bytes;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw Error("cannot read '" + path.string() + "': cannot tell its size");
  bytes.resize(static_cast<size_t>(size));
  in.seekg(0);
  if (size > 0 && !in.read(&bytes[0], size))
    throw Error("cannot read '" + path.string() + "': read failed");
  return bytes;
}

}  // namespace pfill
