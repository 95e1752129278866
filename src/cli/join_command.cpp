// `pfill join -o OUT PART...`: the parts of a fill's output that its MPI
// ranks wrote one each (`pfill fill --engine lammps -o out.%r.csv`, each
// rank the particles of its LAMMPS sub-domain) joined into one file, in the
// order of the particles' ids (docs/lammps_engine.md "Output per rank").
#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/path_checks.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"

namespace pfill::cli {
namespace {

/// Every part's particles in one set, by id; an id in two parts (or a part
/// without ids) is an error: the parts of one fill hold each particle once.
ParticleSet join_parts(const std::vector<std::string>& parts) {
  ParticleSet all;
  std::map<uint64_t, std::string> seen;
  bool with_colours = false, with_velocities = false;
  for (const std::string& path : parts) {
    const ParticleSet p = read_particles(path);
    if (p.empty()) continue;
    if (!p.has_ids()) throw Error("join: " + path + " has no particle ids; join the parts of one fill (-o out.%r.csv)");
    if (all.empty()) with_colours = p.has_colours(), with_velocities = p.has_velocities();
    if (p.has_colours() != with_colours || p.has_velocities() != with_velocities)
      throw Error("join: " + path + " differs from " + parts.front() +
                  " in its columns (colours, velocities); join the parts of one fill");
    for (size_t i = 0; i < p.size(); ++i) {
      const auto [at, fresh] = seen.emplace(p.ids[i], path);
      if (!fresh)
        throw Error("join: particle id " + std::to_string(p.ids[i]) + " is in both " + at->second + " and " + path +
                    "; join the parts of one fill only");
      all.positions.push_back(p.positions[i]);
      all.radii.push_back(p.radii[i]);
      all.ids.push_back(p.ids[i]);
      if (with_colours) all.colours.push_back(p.colours[i]);
      if (with_velocities) all.velocities.push_back(p.velocities[i]);
    }
  }
  return in_id_order(all);
}

}  // namespace

void add_join_command(CLI::App& app) {
  struct Args {
    std::vector<std::string> parts;
    std::string output, attribute_names = "pfill";
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "join", "Join the files a fill wrote one per MPI rank (fill --engine lammps -o out.%r.csv) into one, by id");
  cmd->add_option("parts", a->parts, "The parts (.ply .glb .csv .vtp .data .xyzr), e.g. out.*.csv")->required();
  cmd->add_option("-o,--output", a->output, "The joined file; format from the extension")->required();
  cmd->add_option("--attribute-names", a->attribute_names, "PLY and CSV attribute names: pfill or houdini (as fill's)")
      ->check(CLI::IsMember({"pfill", "houdini"}));
  cmd->callback([a]() {
    particle_format_from_path(a->output);  // an unknown extension fails before any part is read
    std::vector<NamedPath> inputs;
    for (const std::string& part : a->parts) inputs.push_back({"a part", part});
    refuse_clashing_paths(inputs, {{"-o", a->output}});  // -o must not overwrite a part
    ParticleWriteOptions wo;
    wo.names = parse_attribute_names(a->attribute_names);
    write_particles(join_parts(a->parts), a->output, wo);
  });
}

}  // namespace pfill::cli
