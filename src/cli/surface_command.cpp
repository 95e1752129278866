// `pfill surface MESH (-r R | -n N) -o shell.ply`: boundary particles on the
// surface at spacing 2R (include/pfill/surface_sampling.hpp), each with its
// outward normal and area, and the shell's figures. Also the shell's JSON
// that `pfill check --shell` and `pfill fill --shell` print.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/format.hpp"
#include "cli/mesh_argument.hpp"
#include "cli/number_checks.hpp"
#include "cli/path_checks.hpp"
#include "cli/shell_report.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/boundary.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/surface_sampling.hpp"

namespace pfill::cli {

nlohmann::ordered_json shell_json(const ShellStats& s) {
  return {{"particles", s.count},
          {"spacing", s.spacing},
          {"nearest_mean", s.nn_mean},
          {"nearest_min", s.nn_min},
          {"nearest_max", s.nn_max},
          {"share_within_15_percent", s.share_within_15},
          {"closer_than_0.8_spacing", s.closer_than_08},
          {"coverage", s.coverage},
          {"coverage_over_r", s.coverage_over_r},
          {"least_covered_point", {s.least_covered.x, s.least_covered.y, s.least_covered.z}},
          {"surface_points", s.surface_points},
          {"largest_off_surface", s.largest_off_surface}};
}

void print_shell(std::FILE* out, const ShellStats& s) {
  std::fprintf(out, "  shell           %s particles at spacing 2R = %s\n", thousands(s.count).c_str(),
               num(s.spacing).c_str());
  std::fprintf(out, "  nearest         mean %.4f, min %.4f, max %.4f of 2R; %.1f%% within +-15%% of 2R, %s closer than 0.8 x 2R\n",
               s.nn_mean / s.spacing, s.nn_min / s.spacing, s.nn_max / s.spacing, 100 * s.share_within_15,
               thousands(s.closer_than_08).c_str());
  std::fprintf(out, "  coverage        every surface point within %.3f R of a particle (%s points; a hexagonal layer: 1.155 R)\n",
               s.coverage_over_r, thousands(s.surface_points).c_str());
}

ShellStats measure_shell_of(const Boundary& boundary, const ParticleSet& particles,
                            const ParticleAttributes* attributes) {
  const bool kinds = attributes && attributes->has_kinds();
  std::vector<Vec3> on_surface;
  double radius = 0, smallest = HUGE_VAL, largest = 0;
  for (size_t i = 0; i < particles.size(); ++i)
    if (kinds ? attributes->kinds[i] == static_cast<uint8_t>(ParticleKind::Boundary)
              : boundary.closest(particles.positions[i]).distance <= 0.5 * particles.radii[i]) {
      on_surface.push_back(particles.positions[i]);
      radius += particles.radii[i];
      smallest = std::min(smallest, particles.radii[i]);
      largest = std::max(largest, particles.radii[i]);
    }
  if (on_surface.empty())
    throw Error(kinds ? "--shell: the file marks no particle as boundary (kind 1)"
                      : "--shell: no particle lies on the surface (within half its radius)");
  // One radius (a shell's): that radius itself, so the figures equal those
  // `fill --shell` and `pfill surface` print (a mean differs in the last bits).
  return measure_shell(boundary, on_surface, smallest == largest ? smallest : radius / on_surface.size());
}

double surface_radius_for_count(const Mesh& mesh, size_t count) {
  return pfill::surface_radius_for_count(diagnose(mesh).surface_area, count);
}

void add_surface_command(CLI::App& app) {
  struct Args {
    std::string mesh, output, report;
    double radius = 0;
    size_t count = 0;
    SurfaceSamplingOptions options;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "surface", "Boundary particles on a mesh's surface at spacing 2R, each with its normal and area (SPH walls)");
  cmd->add_option("mesh", a->mesh, "Mesh file, or a built-in shape name (torus, sphere, cube)")->required();
  cmd->add_option("-o,--output", a->output,
                  "Output file (.ply .csv .vtp .glb .data .xyzr), with nx ny nz and area per particle "
                  "(default MESH_surface.ply here)");
  cmd->add_option("-r,--radius", a->radius, "Particle radius R (spacing 2R)")->check(positive_number());
  cmd->add_option("-n,--count", a->count, "About this many particles (picks R from the surface area)")
      ->check(whole_number(1, 100000000));
  cmd->add_option("--seed", a->options.seed, "Random seed")->capture_default_str();
  cmd->add_option("--relax", a->options.relax_iterations, "Tangential relaxation rounds")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str();
  cmd->add_option("--report", a->report, "Write the shell's figures as JSON to this file (- : standard output)");
  cmd->add_flag("--json", a->json, "Print the figures as JSON on standard output");
  cmd->callback([a, cmd]() {
    if ((cmd->count("--radius") > 0) == (cmd->count("--count") > 0))
      throw Error("give -r (the radius; spacing 2R) or -n (about how many particles), one of them");
    if (a->output.empty())
      a->output = (is_builtin_shape(a->mesh) ? a->mesh : fs_stem(a->mesh)) + "_surface.ply";
    refuse_clashing_paths({{"the mesh", a->mesh}}, {{"-o", a->output}, {"--report", a->report}});
    particle_format_from_path(a->output);
    const Mesh mesh = load_mesh_argument(a->mesh);
    a->options.radius = a->radius > 0 ? a->radius : surface_radius_for_count(mesh, a->count);
    const auto start = std::chrono::steady_clock::now();
    const Boundary boundary(mesh);
    const auto built = std::chrono::steady_clock::now();
    const SurfaceSamples samples = sample_surface(boundary, a->options);
    const auto done = std::chrono::steady_clock::now();
    // The boundary (Embree scene, inside/outside) apart: a fill builds it too, with its field.
    const double boundary_seconds = std::chrono::duration<double>(built - start).count();
    const double sampling_seconds = std::chrono::duration<double>(done - built).count();
    const double seconds = boundary_seconds + sampling_seconds;
    ParticleSet particles;
    particles.positions = samples.positions;
    particles.radii.assign(samples.positions.size(), samples.radius);
    ParticleAttributes attributes;
    attributes.normals = samples.normals;
    attributes.areas = samples.areas;
    ParticleWriteOptions wo;
    wo.attributes = &attributes;
    wo.box = mesh.bounds();
    write_particles(particles, a->output, wo);
    const ShellStats stats = measure_shell(boundary, samples.positions, samples.radius);
    nlohmann::ordered_json j{{"mesh", mesh.source}, {"output", a->output}, {"radius", samples.radius},
                             {"surface_area", samples.surface_area}, {"seconds", seconds},
                             {"boundary_seconds", boundary_seconds}, {"sampling_seconds", sampling_seconds}};
    j["shell"] = shell_json(stats);
    const std::string text = j.dump(2) + "\n";
    if (!a->report.empty() && a->report != "-") write_file_atomically(a->report, [&](AtomicFile& f) { f.write(text); });
    if (a->json || a->report == "-") {
      std::fputs(text.c_str(), stdout);
      return;
    }
    std::printf("%s -> %s  (radius %s, surface area %s, %.2fs: boundary %.2fs, sampling %.2fs)\n",
                mesh.source.c_str(), a->output.c_str(), num(samples.radius).c_str(), num(samples.surface_area).c_str(),
                seconds, boundary_seconds, sampling_seconds);
    print_shell(stdout, stats);
  });
}

}  // namespace pfill::cli
