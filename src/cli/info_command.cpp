// `pfill info MESH`: what a mesh is made of and whether it can be filled.
#include <cmath>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/format.hpp"
#include "cli/mesh_argument.hpp"
#include "pfill/count_rule.hpp"
#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/fill_settings.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/shapes.hpp"

namespace pfill::cli {
namespace {

struct InfoOptions {
  std::string mesh_path;
  std::string builtin;
  bool json = false;
  std::string radii, radii_by = "number";
  std::optional<RadiusDistribution> sizes;  ///< --radii, parsed
};

const size_t kCounts[] = {1000, 10000, 100000, 1000000};

/// The radius `pfill fill -n count` chooses at its defaults (the count
/// rule); with --radii, the mean radius of the distribution so scaled.
/// --radii scaled as `pfill fill -n count --radii` scales it.
RadiusDistribution sizes_for(const MeshDiagnostics& d, size_t count, const RadiusDistribution& sizes) {
  return sizes.scaled(fill_scale_for_count(d.volume(), d.surface_area, count, sizes, FillOptions{}.max_overlap));
}

double radius_for(const MeshDiagnostics& d, size_t count, const std::optional<RadiusDistribution>& sizes) {
  const FillOptions defaults;
  if (sizes) return sizes_for(d, count, *sizes).mean();
  return fill_radius_for_count(d.volume(), d.surface_area, count, defaults.max_overlap) / defaults.rest_distance;
}

/// The radii of the scaled distribution, "0.01..0.02 (mean 0.015)".
std::string radii_for(const MeshDiagnostics& d, size_t count, const RadiusDistribution& sizes) {
  const RadiusDistribution s = sizes_for(d, count, sizes);
  return num(s.min_radius()) + ".." + num(s.max_radius()) + " (mean " + num(s.mean()) + ")";
}

// What a fill will do with a mesh that is not a clean closed surface.
std::vector<std::string> warnings(const MeshDiagnostics& d) {
  std::vector<std::string> w;
  if (d.boundary_edges > 0)
    w.push_back("the mesh is open (" + thousands(d.boundary_loops) + " holes, " + thousands(d.boundary_edges) +
                " boundary edges): a fill decides inside by a majority vote of several rays and keeps particles "
                "away from the surface it has, but particles may escape near the holes; close them for a "
                "reliable fill");
  if (d.non_manifold_edges > 0)
    w.push_back(thousands(d.non_manifold_edges) +
                " non-manifold edges: inside/outside may be ambiguous near them; repair the mesh for a reliable fill");
  if (d.inside_out())
    w.push_back("the mesh is inside-out (negative volume): a fill will reverse its orientation and go on");
  if (d.misoriented_edges > 0)
    w.push_back(thousands(d.misoriented_edges) +
                " edges join triangles of opposite winding that pfill could not turn to agree (a non-orientable "
                "surface?): the volume, and a radius from a count, are unreliable; repair the mesh");
  if (d.overlapping())
    w.push_back(std::string(d.components > 1 ? "parts intersect or lie inside one another" : "the surface intersects itself") +
                " (some region is enclosed " + (d.winding->min_winding < 0 ? "inside out" : "twice") +
                "): a fill fills the union, inside = a non-zero winding number; the volume given is the "
                "union's, estimated along " + thousands(d.winding->rays) + " rays (the parts' volumes sum to " +
                num(std::fabs(d.signed_volume)) + ")");
  if (d.degenerate_triangles > 0)
    w.push_back(thousands(d.degenerate_triangles) + " degenerate (zero-area) triangles: harmless for a fill");
  return w;
}

nlohmann::ordered_json to_json(const std::string& name, const MeshDiagnostics& d,
                               const std::optional<RadiusDistribution>& sizes) {
  nlohmann::ordered_json radii = nlohmann::ordered_json::array();
  for (size_t n : kCounts) {
    const double r = radius_for(d, n, sizes);
    const double gain = sizes ? sizes->rcp_gain() : 0;
    radii.push_back({{"count", n},
                     {"radius", r},
                     {"packing_fraction", r > 0 ? expected_packing(FillOptions{}.max_overlap, d.surface_area * r / d.volume()) + gain : 0.0}});
    if (sizes) {
      const RadiusDistribution s = sizes->scaled(r / sizes->mean());
      radii.back()["min_radius"] = s.min_radius();
      radii.back()["max_radius"] = s.max_radius();
    }
  }
  return {
      {"mesh", name},
      {"vertices", d.vertices},
      {"triangles", d.triangles},
      {"bounds", {{"min", {d.bounds.lo.x, d.bounds.lo.y, d.bounds.lo.z}},
                  {"max", {d.bounds.hi.x, d.bounds.hi.y, d.bounds.hi.z}},
                  {"diagonal", d.bounds.diagonal()}}},
      {"components", d.components},
      {"edges", d.edges},
      {"boundary_edges", d.boundary_edges},
      {"holes", d.boundary_loops},
      {"non_manifold_edges", d.non_manifold_edges},
      {"misoriented_edges", d.misoriented_edges},
      {"watertight", d.watertight()},
      {"parts_overlap", d.overlapping()},
      {"degenerate_triangles", d.degenerate_triangles},
      {"signed_volume", d.signed_volume},
      {"volume", d.volume()},
      {"inside_out", d.inside_out()},
      {"surface_area", d.surface_area},
      {"genus", d.genus ? nlohmann::ordered_json(*d.genus) : nlohmann::ordered_json(nullptr)},
      {"radius_for_count", radii},
      {"warnings", warnings(d)},
  };
}

void print_text(const std::string& name, const MeshDiagnostics& d, const std::optional<RadiusDistribution>& sizes) {
  auto row = [](const char* key, const std::string& value) {
    std::printf("  %-13s %s\n", key, value.c_str());
  };
  std::printf("%s\n", name.c_str());
  row("vertices", thousands(d.vertices));
  row("triangles", thousands(d.triangles));
  const Vec3 s = d.bounds.size();
  row("bounds", "[" + num(d.bounds.lo.x) + ", " + num(d.bounds.lo.y) + ", " + num(d.bounds.lo.z) + "] .. [" +
                    num(d.bounds.hi.x) + ", " + num(d.bounds.hi.y) + ", " + num(d.bounds.hi.z) + "]");
  row("size", num(s.x) + " x " + num(s.y) + " x " + num(s.z) + "  (diagonal " + num(d.bounds.diagonal()) + ")");
  row("components", thousands(d.components));
  row("watertight", d.watertight() ? "yes" : "no: " + thousands(d.boundary_edges) + " boundary edges in " +
                                                 thousands(d.boundary_loops) + " holes, " +
                                                 thousands(d.non_manifold_edges) + " non-manifold edges");
  row("degenerate", thousands(d.degenerate_triangles) + " triangles");
  if (d.overlapping())
    row("overlap", d.components > 1 ? "parts intersect (the volume is their union's)"
                                    : "the surface intersects itself (the volume is what it encloses)");
  row("volume", num(d.volume()) + (d.inside_out() ? "  (inside-out: negative signed volume)" : "  (outward oriented)") +
                    (d.boundary_loops ? "  estimated with the holes capped" : ""));
  row("area", num(d.surface_area));
  row("genus", d.genus ? std::to_string(*d.genus) : "- (not closed)");
  if (sizes) {
    std::printf("  radii for about N particles of %s (as `pfill fill -n N --radii` scales them):\n",
                sizes->describe().c_str());
    for (size_t n : kCounts)
      std::printf("  %13s %s\n", thousands(static_cast<unsigned long long>(n)).c_str(), radii_for(d, n, *sizes).c_str());
    return;
  }
  std::printf("  radius for about N particles (as `pfill fill -n N` chooses it):\n");
  for (size_t n : kCounts)
    std::printf("  %13s %s\n", thousands(static_cast<unsigned long long>(n)).c_str(), num(radius_for(d, n, sizes)).c_str());
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto opts = std::make_shared<InfoOptions>();
  CLI::App* cmd = app.add_subcommand("info", "Report a mesh's size, topology, volume and fitting radii");
  cmd->add_option("mesh", opts->mesh_path,
                  "Mesh file (glTF/GLB, OBJ, STL, PLY, OFF, SMF, ...) or a built-in shape name (torus, sphere, cube)");
  cmd->add_option("--builtin", opts->builtin, "Use a built-in shape instead of a file (torus, sphere, cube)");
  cmd->add_flag("--json", opts->json, "Write the report as JSON on standard output");
  cmd->add_option("--radii", opts->radii, "A size distribution (as `pfill fill --radii`): the radii for each count");
  cmd->add_option("--radii-by", opts->radii_by, "What discrete:... fractions are: number (default) or volume");
  cmd->callback([opts]() {
    if (opts->mesh_path.empty() == opts->builtin.empty())
      throw CLI::ValidationError("info", "give either a mesh file or --builtin NAME");
    const Mesh mesh = opts->builtin.empty() ? load_mesh_argument(opts->mesh_path) : make_builtin(opts->builtin);
    if (!opts->radii.empty()) {
      try {
        opts->sizes = RadiusDistribution::parse(opts->radii, parse_fraction_basis(opts->radii_by));
      } catch (const Error& e) {
        throw CLI::ValidationError("info", with_flags(e.what()));
      }
    }
    const MeshDiagnostics d = diagnose(mesh);
    if (opts->json) {
      std::cout << to_json(mesh.source, d, opts->sizes).dump(2) << "\n";
    } else {
      print_text(mesh.source, d, opts->sizes);
    }
    if (mesh.turned_faces > 0)
      std::cerr << "pfill: warning: the winding was inconsistent: " << thousands(mesh.turned_faces)
                << " faces were turned to agree with their neighbours (a fill does the same)\n";
    for (const std::string& w : warnings(d)) std::cerr << "pfill: warning: " << w << "\n";
  });
}

}  // namespace pfill::cli
