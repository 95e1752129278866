// `pfill check PARTICLES MESH`: the metrics of a fill for any particle file,
// so pfill's output can be compared with other tools'.
#include <iostream>
#include <optional>

#include "cli/commands.hpp"
#include "cli/contact_options.hpp"
#include "cli/mesh_argument.hpp"
#include "cli/metrics_report.hpp"
#include "cli/number_checks.hpp"
#include "cli/shell_report.hpp"
#include "pfill/boundary.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/fill_settings.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/radius_distribution.hpp"
#include "pfill/shapes.hpp"

namespace pfill::cli {

void add_check_command(CLI::App& app) {
  struct Args {
    std::string particles, mesh;
    double radius = 0;
    double tolerance = 0.01;
    bool json = false;
    bool shell = false;  // also the figures of the boundary particles (those on the surface)
    std::string pairs;   // a contacts CSV to verify
    double gap = kDefaultContactGap;
    // Thresholds (negative: not checked); a miss exits with kExitThresholdMissed.
    double min_inside = -1, max_overlap = -1, min_packing = -1;
    std::string radii, radii_by = "number";  // a size distribution to compare the radii with
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("check", "Measure a particle file against a mesh: packing, containment, overlaps");
  cmd->add_option("particles", a->particles, "Particle file (.ply .glb .csv .vtp .data .xyzr)")->required();
  cmd->add_option("mesh", a->mesh, "Mesh file, or a built-in shape name (torus, sphere, cube)")->required();
  cmd->add_option("--radius", a->radius, "Radius for particle files that have none")->check(positive_number());
  cmd->add_option("--tolerance", a->tolerance, "Allowed crossing of the surface, as a fraction of r (0..1)")
      ->check(number_in(0, 1))
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Write the metrics as JSON on standard output");
  cmd->add_option("--pairs", a->pairs,
                  "A contacts CSV (fill --pairs): exit 3 unless every listed pair is within --contact-gap");
  cmd->add_option("--contact-gap", a->gap, "The gap --pairs lists, a fraction of the smaller radius")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_flag("--shell", a->shell,
                "Also the figures of the boundary particles (`pfill surface`, `fill --shell`: those of kind 1 where "
                "the file has a kind, else those whose centre lies within half their radius of the surface): "
                "nearest-neighbour spacing and coverage");
  cmd->add_option("--radii", a->radii,
                  "A size distribution (as `fill --radii`) to compare the file's radii with, scaled to their mean "
                  "(so a SPEC of relative radii compares too): shares per class, KS distance");
  cmd->add_option("--radii-by", a->radii_by, "What discrete:... fractions are: number (default) or volume");
  cmd->add_option("--min-inside", a->min_inside,
                  "Exit with status 3 unless at least this share of the spheres (0..1) lies inside")
      ->check(number_in(0, 1));
  cmd->add_option("--max-overlap", a->max_overlap,
                  "Exit with status 3 if any pair overlaps by more than this fraction of r (of the smaller radius)")
      ->check(number_in(0, 2));
  cmd->add_option("--min-packing", a->min_packing,
                  "Exit with status 3 unless the packing fraction is at least this")
      ->check(number_in(0, 1));
  cmd->callback([a]() {
    ParticleReadOptions ro;
    ro.default_radius = a->radius;
    ParticleAttributes attributes;  // kinds (fill --shell) tell the shell apart
    ro.attributes = &attributes;
    ParticleSet particles = read_particles(a->particles, ro);
    Mesh mesh = load_mesh_argument(a->mesh);
    // Measured about the mesh's centre, as the fill works: far from the
    // origin (1e9) the ray tracer's single precision would lose the surface.
    struct {
      Mesh mesh;
      ParticleSet particles;
    } in_place;  // for --shell: (p - c) + c is not always p
    if (a->shell) in_place = {mesh, particles};
    const Vec3 centre = mesh.bounds().centre();
    for (Vec3& p : mesh.positions) p -= centre;
    for (Vec3& p : particles.positions) p -= centre;
    const Boundary boundary(mesh);
    MetricsOptions mo;
    mo.containment_tolerance = a->tolerance;
    const PackingMetrics m = measure_packing(boundary, diagnose(mesh).volume(), particles, mo);
    std::optional<ShellStats> shell;
    if (a->shell) {
      // Where the particles are, as `fill --shell` and `pfill surface`
      // measure them: the same file then gives the same figures (and the
      // least covered point is the file's).
      shell = measure_shell_of(Boundary(in_place.mesh), in_place.particles, &attributes);
    }
    std::optional<RadiusDistribution> sizes;
    std::optional<DistributionFit> fit;
    if (!a->radii.empty()) {
      try {
        sizes = RadiusDistribution::parse(a->radii, parse_fraction_basis(a->radii_by));
      } catch (const Error& e) {
        throw CLI::ValidationError("check", with_flags(e.what()));
      }
      double mean = 0;
      for (double r : particles.radii) mean += r;
      if (!particles.radii.empty()) sizes = sizes->scaled(mean / static_cast<double>(particles.radii.size()) / sizes->mean());
      fit = compare_distribution(*sizes, particles.radii);
    }
    std::vector<std::string> misses;
    nlohmann::ordered_json pairs;
    if (!a->pairs.empty()) pairs = verify_pairs(particles, a->pairs, a->gap, misses);
    if (a->min_inside >= 0 && m.contained_share < a->min_inside)
      misses.push_back(num(100 * m.contained_share, 4) + "% of the spheres lie inside, below --min-inside " +
                       num(100 * a->min_inside, 4) + "%");
    if (a->max_overlap >= 0 && m.max_overlap > a->max_overlap)
      misses.push_back("the largest overlap is " + num(100 * m.max_overlap, 4) + "% of r, above --max-overlap " +
                       num(100 * a->max_overlap, 4) + "%");
    if (a->min_packing >= 0 && m.packing_fraction < a->min_packing)
      misses.push_back("the packing fraction is " + num(m.packing_fraction, 4) + ", below --min-packing " +
                       num(a->min_packing, 4));
    if (a->json) {
      nlohmann::ordered_json j{{"particles_file", a->particles}, {"mesh", mesh.source}};
      j["metrics"] = metrics_json(m);
      if (shell) j["shell"] = shell_json(*shell);
      if (fit) j["radii"] = radii_json(*sizes, *fit);
      if (!pairs.is_null()) j["contacts"] = pairs;
      j["passed"] = misses.empty();
      j["failures"] = misses;
      std::cout << j.dump(2) << "\n";
    } else {
      std::printf("%s in %s\n", a->particles.c_str(), mesh.source.c_str());
      print_metrics(stdout, m);
      if (fit) print_radii_fit(stdout, *sizes, *fit);
      if (shell) print_shell(stdout, *shell);
      if (!pairs.is_null())
        std::printf("  contacts        %s listed pairs, %s beyond the gap (largest gap %.4f of the smaller radius); %s found here\n",
                    thousands(pairs["listed"].get<size_t>()).c_str(), thousands(pairs["beyond_gap"].get<size_t>()).c_str(),
                    pairs["largest_gap"].get<double>(), thousands(pairs["found"].get<size_t>()).c_str());
    }
    std::fflush(stdout);
    for (const std::string& miss : misses) std::fprintf(stderr, "pfill check: FAILED: %s\n", miss.c_str());
    if (!misses.empty()) throw ExitStatus{kExitThresholdMissed};
  });
}

}  // namespace pfill::cli
