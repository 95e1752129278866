// `pfill fill --shell`: the inner fill runs in the mesh moved in by the
// shell's radius, then the boundary particles join it in one output with a
// `kind` attribute (include/pfill/shell_fill.hpp). src/cli/shell_run.cpp.
#pragma once
#include <cstdio>
#include <memory>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "pfill/boundary.hpp"
#include "pfill/fill.hpp"
#include "pfill/shell_fill.hpp"

namespace pfill::cli {

struct ShellArgs {
  bool shell = false;
  double radius = 0;  ///< the shell particles' radius; 0: the fill's
};

/// Adds --shell and --shell-radius (in `details_group`) to `cmd`.
void add_shell_options(CLI::App* cmd, ShellArgs& args, const std::string& details_group = "Options");

class ShellRun {
 public:
  /// Picks the inner radius (options.radius, or the one options.count gives
  /// in `mesh`) and sets it in `options`; builds the inset mesh to fill.
  ShellRun(const ShellArgs& args, const Mesh& mesh, FillOptions& options);
  const Mesh& fill_mesh() const { return fill_mesh_; }
  /// Samples the shell and replaces result.particles by inner + shell.
  void join(FillResult& result);
  const ParticleAttributes& attributes() const { return joined_.attributes; }
  nlohmann::ordered_json report() const;
  void print(std::FILE* out) const;

 private:
  Boundary boundary_;
  Mesh fill_mesh_;
  double inner_radius_ = 0, shell_radius_ = 0, max_overlap_ = 0, seconds_ = 0;
  ShellFill joined_;
  ShellStats stats_;
};

}  // namespace pfill::cli
