#include "cli/path_checks.hpp"

#include <filesystem>

#include "pfill/error.hpp"

namespace fs = std::filesystem;

namespace pfill::cli {
namespace {

fs::path resolved(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
  return ec ? fs::absolute(path).lexically_normal() : p;
}

bool same_file(const std::string& a, const std::string& b) {
  if (resolved(a) == resolved(b)) return true;
  std::error_code ec;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);  // hard links
}

// A frame_*.ply file inside the frames folder, which --frames fills.
bool in_frames(const std::string& path, const std::string& frames) {
  const fs::path p = resolved(path);
  return p == resolved(frames) ||
         (p.parent_path() == resolved(frames) && p.filename().string().rfind("frame_", 0) == 0);
}

std::string quoted(const NamedPath& p) { return p.role + " '" + p.path + "'"; }

}  // namespace

void refuse_clashing_paths(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs,
                           const NamedPath& frames) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    const NamedPath& out = outputs[i];
    if (out.path.empty()) continue;
    for (const NamedPath& in : inputs)
      if (!in.path.empty() && same_file(out.path, in.path))
        throw Error(quoted(out) + " is " + quoted(in) + ": it would be overwritten; write to another file");
    for (size_t j = 0; j < i; ++j)
      if (!outputs[j].path.empty() && same_file(out.path, outputs[j].path))
        throw Error(quoted(out) + " and " + quoted(outputs[j]) + " name the same file; give each its own");
    if (!frames.path.empty() && in_frames(out.path, frames.path))
      throw Error(quoted(out) + " lies in the " + frames.role + " folder '" + frames.path +
                  "', whose frame files the fill writes; write it elsewhere");
  }
  if (!frames.path.empty())
    for (const NamedPath& in : inputs)
      if (!in.path.empty() && in_frames(in.path, frames.path))
        throw Error(quoted(in) + " lies in the " + frames.role + " folder '" + frames.path +
                    "', whose frame files the fill overwrites; choose another folder");
}

}  // namespace pfill::cli
