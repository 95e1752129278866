// Refusing output paths that would overwrite an input or another output:
// paths are compared resolved (symbolic links, "..", hard links), not as
// strings, so `-o ./same.glb` cannot replace the mesh `same.glb`.
#pragma once
#include <string>
#include <vector>

namespace pfill::cli {

struct NamedPath {
  std::string role;  ///< how the user gave it: "the mesh", "-o", "--report", ...
  std::string path;  ///< empty: not given (skipped)
};

/// Throws pfill::Error naming both options when an output names an input or
/// another output. `frames`, when given, is a folder of frame_*.ply files:
/// no input or output may be one of them.
void refuse_clashing_paths(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs,
                           const NamedPath& frames = {});

}  // namespace pfill::cli
