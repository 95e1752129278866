// File checks and small conversions shared by the mesh readers.
#include "mesh/load_support.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sys/stat.h>

#include "pfill/error.hpp"

namespace pfill::detail {

void require_readable_file(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0)
    throw Error(path + ": cannot open the file (" + std::strerror(errno) + "); check the path");
  if (S_ISDIR(info.st_mode)) throw Error(path + ": is a folder, not a mesh file");
  // A FIFO would block the open (or be read once and then found empty):
  // pfill reads each mesh several times, so only regular files will do.
  if (!S_ISREG(info.st_mode))
    throw Error(path + ": is not a regular file (a FIFO, socket or device); save the mesh to a file first");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the file for reading (" + std::strerror(errno) + ")");
  if (info.st_size == 0) throw Error(path + ": the file is empty; re-export the mesh");
}

std::vector<uint8_t> read_file_bytes(const std::string& path) {
  require_readable_file(path);
  std::ifstream in(path, std::ios::binary);
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw Error(path + ": cannot read the file size");
  in.seekg(0, std::ios::beg);
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size))
    throw Error(path + ": reading the file failed after " + std::to_string(in.gcount()) + " bytes");
  return bytes;
}

std::string folder_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string lower_extension(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace pfill::detail
