// `pfill contacts PARTICLES [MESH] [--gap G] -o OUT [--pairs PAIRS.csv]`:
// the contact network of any particle file (the pairs within a gap, and
// with a mesh the spheres touching its surface), written as the particles
// with their contacts (PLY edges, VTP lines, LAMMPS bonds, coordination in
// every format) and/or a CSV of the contacts. Also the helpers `pfill fill
// --contacts` uses (cli/contact_options.hpp).
#include <cstdio>
#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>
#include <unordered_map>

#include "cli/commands.hpp"
#include "cli/contact_options.hpp"
#include "cli/format.hpp"
#include "cli/mesh_argument.hpp"
#include "cli/path_checks.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/error.hpp"

namespace pfill::cli {

void add_contact_options(CLI::App* cmd, ContactArgs& a, bool with_flag, const std::string& details_group) {
  if (with_flag)
    cmd->add_flag("--contacts", a.contacts,
                  "Find the contact network of the final particles: the output gets each sphere's coordination "
                  "and the pairs (PLY edge elements, VTP lines, LAMMPS Bonds with atom_style hybrid sphere bond), "
                  "the report a \"contacts\" section");
  cmd->add_option("--contact-gap,--gap", a.gap,
                  "Spheres touch when their gap is at most this fraction of the smaller radius")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->group(details_group);
  cmd->add_option("--pairs", a.pairs,
                  "Write the contacts as CSV: a,b,gap,x,y,z,nx,ny,nz (particle ids; b = 0 for the wall, "
                  "with the surface point and its outward normal)")
      ->group(details_group);
}

ContactResult find_and_write_contacts(const ContactArgs& a, const ParticleSet& particles, const Boundary* boundary) {
  ContactResult r;
  r.network = std::make_unique<ContactNetwork>(find_contacts(particles, a.gap));
  if (boundary) find_wall_contacts(*r.network, particles, *boundary);
  r.report = contacts_report_json(*r.network, particles, boundary);
  if (!a.pairs.empty()) write_contacts_csv(particles, *r.network, a.pairs);
  return r;
}

nlohmann::ordered_json verify_pairs(const ParticleSet& particles, const std::string& path, double gap,
                                    std::vector<std::string>& misses) {
  std::ifstream in(path);
  if (!in) throw Error("cannot read '" + path + "' (--pairs): no such file, or no permission");
  std::unordered_map<uint64_t, uint32_t> index;
  for (size_t i = 0; i < particles.size(); ++i) index[particles.id(i)] = static_cast<uint32_t>(i);
  std::string line;
  std::getline(in, line);
  if (line.rfind("a,b,gap", 0) != 0) throw Error("'" + path + "': not a contacts CSV (its header is not a,b,gap,...)");
  size_t listed = 0, outside = 0, unknown = 0, row = 1;
  double worst = -1e300;  // the largest gap over the smaller radius
  while (std::getline(in, line)) {
    ++row;
    if (line.empty()) continue;
    std::istringstream fields(line);
    std::string a_text, b_text;
    std::getline(fields, a_text, ',');
    std::getline(fields, b_text, ',');
    uint64_t a = 0, b = 0;
    try {
      a = std::stoull(a_text), b = std::stoull(b_text);
    } catch (const std::exception&) {
      throw Error("'" + path + "' line " + std::to_string(row) + ": not two particle ids");
    }
    if (b == 0) continue;  // a wall contact
    ++listed;
    const auto ia = index.find(a), ib = index.find(b);
    if (ia == index.end() || ib == index.end()) {
      ++unknown;
      continue;
    }
    const double ra = particles.radii[ia->second], rb = particles.radii[ib->second];
    const double g = length(particles.positions[ib->second] - particles.positions[ia->second]) - ra - rb;
    const double rmin = std::min(ra, rb);
    worst = std::max(worst, g / rmin);
    if (g > gap * rmin + 1e-6 * (ra + rb)) ++outside;  // float positions in a PLY: rounding
  }
  if (unknown) misses.push_back(std::to_string(unknown) + " listed pairs name particle ids not in the file");
  if (outside)
    misses.push_back(std::to_string(outside) + " of " + std::to_string(listed) + " listed pairs are farther apart than " +
                     num(100 * gap, 3) + "% of the smaller radius");
  return {{"pairs_file", path}, {"listed", listed}, {"gap_fraction", gap}, {"largest_gap", listed ? worst : 0.0},
          {"beyond_gap", outside}, {"unknown_ids", unknown}, {"found", find_contacts(particles, gap).pairs.size()}};
}

void print_contacts_line(std::FILE* out, const ContactNetwork& n, bool with_wall) {
  std::fprintf(out, "  contacts        %s pairs (gap <= %s of the smaller radius), mean coordination %.2f%s\n",
               thousands(n.pairs.size()).c_str(), (num(100 * n.gap_fraction, 3) + "%").c_str(),
               n.mean_coordination(),
               with_wall ? (", " + thousands(n.wall.size()) + " spheres at the wall").c_str() : "");
}

void add_contacts_command(CLI::App& app) {
  struct Args {
    std::string particles, mesh, output, report;
    double radius = 0;
    bool json = false;
    ContactArgs contacts;
  };
  auto a = std::make_shared<Args>();
  a->contacts.contacts = true;
  CLI::App* cmd = app.add_subcommand(
      "contacts", "The contact network of a particle file: touching pairs (and with a mesh the spheres at its surface)");
  cmd->add_option("particles", a->particles, "Particle file (.ply .glb .csv .vtp .data .xyzr)")->required();
  cmd->add_option("mesh", a->mesh, "Mesh file or built-in shape: adds the spheres touching its surface");
  cmd->add_option("-o,--output", a->output,
                  "The particles with their contacts: .ply (edge elements), .vtp (lines), .data (LAMMPS bonds), "
                  ".csv/.xyzr/.glb (coordination)");
  cmd->add_option("--radius", a->radius, "Radius for particle files that have none");
  cmd->add_option("--report", a->report, "Write the network's figures as JSON to this file (- : standard output)");
  cmd->add_flag("--json", a->json, "Print the figures as JSON on standard output");
  add_contact_options(cmd, a->contacts, false);
  cmd->callback([a]() {
    if (a->output.empty() && a->contacts.pairs.empty() && a->report.empty() && !a->json)
      throw Error("say what to write: -o PARTICLES (with their contacts), --pairs PAIRS.csv, --report or --json");
    refuse_clashing_paths({{"the particles", a->particles}, {"the mesh", a->mesh}},
                          {{"-o", a->output}, {"--pairs", a->contacts.pairs}, {"--report", a->report}});
    if (!a->output.empty()) particle_format_from_path(a->output);
    ParticleReadOptions ro;
    ro.default_radius = a->radius;
    ParticleAttributes attributes;  // a shell's kinds, normals and areas go on into -o
    ro.attributes = &attributes;
    const ParticleSet particles = read_particles(a->particles, ro);
    std::unique_ptr<Boundary> boundary;
    Mesh mesh;
    if (!a->mesh.empty()) {
      mesh = load_mesh_argument(a->mesh);
      boundary = std::make_unique<Boundary>(mesh);
    }
    const ContactResult r = find_and_write_contacts(a->contacts, particles, boundary.get());
    if (!a->output.empty()) {
      ParticleWriteOptions wo;
      wo.contacts = r.network.get();
      wo.attributes = &attributes;
      if (boundary) wo.box = mesh.bounds();
      write_particles(particles, a->output, wo);
    }
    nlohmann::ordered_json j{{"particles_file", a->particles}, {"contacts", r.report}};
    if (!a->mesh.empty()) j["mesh"] = mesh.source;
    const std::string text = j.dump(2) + "\n";
    if (!a->report.empty() && a->report != "-") write_file_atomically(a->report, [&](AtomicFile& f) { f.write(text); });
    if (a->json || a->report == "-") {
      std::fputs(text.c_str(), stdout);
      return;
    }
    std::printf("%s: %s spheres\n", a->particles.c_str(), thousands(particles.size()).c_str());
    print_contacts_line(stdout, *r.network, boundary != nullptr);
    if (!a->output.empty()) std::printf("  written         %s\n", a->output.c_str());
    if (!a->contacts.pairs.empty()) std::printf("  pairs           %s\n", a->contacts.pairs.c_str());
  });
}

}  // namespace pfill::cli
