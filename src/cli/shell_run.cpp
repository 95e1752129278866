// `pfill fill --shell` (cli/shell_run.hpp).
#include "cli/shell_run.hpp"

#include <chrono>

#include "cli/format.hpp"
#include "cli/number_checks.hpp"
#include "cli/shell_report.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_diagnostics.hpp"

namespace pfill::cli {

void add_shell_options(CLI::App* cmd, ShellArgs& a, const std::string& details_group) {
  cmd->add_flag("--shell", a.shell,
                "Also boundary particles on the surface (as `pfill surface`), in the same output with a kind "
                "attribute (0 inner, 1 boundary; LAMMPS atom types 1 and 2) and each boundary particle's nx ny "
                "nz and area; the inner fill is kept clear of them by a wall moved in by their radius (the summary's "
                "metrics are the inner fill's)")
      ->group(details_group);
  cmd->add_option("--shell-radius", a.radius, "Radius of the boundary particles (default: the fill's radius)")
      ->check(positive_number())
      ->group(details_group);
}

ShellRun::ShellRun(const ShellArgs& a, const Mesh& mesh, FillOptions& o) : boundary_(mesh) {
  if (o.radii)  // the shell's spacing and the inset wall are one radius's
    throw Error("--shell takes equal spheres only: leave out --radii (or fill without --shell)");
  if (o.radius <= 0) {
    const MeshDiagnostics d = diagnose(mesh);
    o.radius = fill_radius_for_count(d.volume(), d.surface_area, o.count, o.max_overlap, o.rest_distance);
    o.count = 0;
  }
  inner_radius_ = o.radius;
  shell_radius_ = a.radius > 0 ? a.radius : o.radius;
  max_overlap_ = o.max_overlap;
  fill_mesh_ = inset_mesh(mesh, shell_radius_, boundary_.inward_oriented());
}

void ShellRun::join(FillResult& r) {
  const auto start = std::chrono::steady_clock::now();
  SurfaceSamplingOptions so;
  so.radius = shell_radius_;
  so.seed = 1;
  const SurfaceSamples shell = sample_surface(boundary_, so);
  seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stats_ = measure_shell(boundary_, shell.positions, shell_radius_);
  joined_ = join_shell(r.particles, shell, max_overlap_);
  r.particles = joined_.particles;
  // The fill's warnings are about the mesh it filled: the one moved in.
  for (std::string& w : r.warnings) w = "--shell (the inner fill ran in the mesh moved in by the shell's radius): " + w;
}

nlohmann::ordered_json ShellRun::report() const {
  nlohmann::ordered_json j{{"inner", joined_.inner},
                           {"inner_removed", joined_.removed},
                           {"inner_radius", inner_radius_},
                           {"shell_radius", shell_radius_},
                           {"seconds", seconds_}};
  j["shell"] = shell_json(stats_);
  return j;
}

void ShellRun::print(std::FILE* out) const {
  std::fprintf(out, "  with the shell  %s inner + %s boundary particles (kind 0 / 1); %s inner removed against the shell\n",
               thousands(joined_.inner).c_str(), thousands(stats_.count).c_str(), thousands(joined_.removed).c_str());
  print_shell(out, stats_);
}

}  // namespace pfill::cli
