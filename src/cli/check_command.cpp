// `pfill check PARTICLES MESH`: the metrics of a fill for any particle file,
// so pfill's output can be compared with other tools'.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/metrics_report.hpp"
#include "pfill/boundary.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/shapes.hpp"

namespace pfill::cli {

void add_check_command(CLI::App& app) {
  struct Args {
    std::string particles, mesh;
    double radius = 0;
    double tolerance = 0.01;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("check", "Measure a particle file against a mesh: packing, containment, overlaps");
  cmd->add_option("particles", a->particles, "Particle file (.ply, .csv)")->required();
  cmd->add_option("mesh", a->mesh, "Mesh file, or a built-in shape name (torus, sphere, cube)")->required();
  cmd->add_option("--radius", a->radius, "Radius for particle files that have none");
  cmd->add_option("--tolerance", a->tolerance, "Allowed crossing of the surface, as a fraction of r")
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Write the metrics as JSON on standard output");
  cmd->callback([a]() {
    ParticleReadOptions ro;
    ro.default_radius = a->radius;
    const ParticleSet particles = read_particles(a->particles, ro);
    bool builtin = false;
    for (const std::string& n : builtin_shape_names()) builtin = builtin || n == a->mesh;
    const Mesh mesh = builtin ? make_builtin(a->mesh) : load_mesh(a->mesh);
    const Boundary boundary(mesh);
    MetricsOptions mo;
    mo.containment_tolerance = a->tolerance;
    const PackingMetrics m = measure_packing(boundary, diagnose(mesh).volume(), particles, mo);
    if (a->json) {
      nlohmann::ordered_json j{{"particles_file", a->particles}, {"mesh", mesh.source}};
      j["metrics"] = metrics_json(m);
      std::cout << j.dump(2) << "\n";
    } else {
      std::printf("%s in %s\n", a->particles.c_str(), mesh.source.c_str());
      print_metrics(stdout, m);
    }
  });
}

}  // namespace pfill::cli
