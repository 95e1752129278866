// `pfill fill [MESH] -o OUT [options]`: the main job. Without a mesh it
// fills a built-in shape and writes into the current folder.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/format.hpp"
#include "cli/mesh_argument.hpp"
#include "cli/metrics_report.hpp"
#include "cli/number_checks.hpp"
#include "cli/path_checks.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/fill_report.hpp"
#include "pfill/lammps.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/render.hpp"
#include "pfill/shapes.hpp"

namespace fs = std::filesystem;

namespace pfill::cli {
namespace {

struct FillArgs {
  std::string mesh;
  std::string builtin = "torus";
  std::string output;
  std::string report;
  std::string preview;
  std::string frames;
  uint64_t frame_every = 500;
  std::string birth;
  std::string exponents = "12,6";
  std::string stop = "blocked";
  std::string colour;
  std::string birth_speed;
  std::string engine = "opencl";      // --engine: opencl or lammps (docs/lammps_engine.md)
  bool spheres = false;
  bool velocities = false;
  bool quiet = false;
  bool verbose = false;               // the fill's own choices (FillOptions::log) on stderr
  bool json = false;                  // the summary as JSON on stdout
  std::string attribute_names = "pfill";
  double density = 1.0;               // LAMMPS .data
  FillOptions options;
};

// One updating line on a terminal, a plain line every few seconds otherwise.
class ProgressPrinter {
 public:
  explicit ProgressPrinter(bool quiet) : quiet_(quiet), tty_(isatty(STDERR_FILENO) != 0) {}
  ~ProgressPrinter() { end_line(); }

  void operator()(const FillProgress& p) {
    if (quiet_) return;
    const auto now = std::chrono::steady_clock::now();
    const double since = std::chrono::duration<double>(now - last_).count();
    if (p.phase == phase_ && since < (tty_ ? 0.2 : 5.0)) return;
    const bool new_phase = p.phase != phase_;
    phase_ = p.phase;
    last_ = now;
    if (p.phase == "field") {  // nothing to count yet
      if (new_phase) std::fprintf(stderr, "pfill: building the signed distance field\n");
      return;
    }
    if (new_phase && !tty_) std::fprintf(stderr, "pfill: %s\n", p.phase.c_str());
    char line[256];
    std::snprintf(line, sizeof line, "%-7s %9s particles (~%s when full)  KE %-9.3g pairs %-6u %7.0f steps/s  %5.0fs%s%s",
                  p.phase.c_str(), thousands(p.particles).c_str(), thousands(p.target).c_str(), p.kinetic_energy,
                  p.colliding_pairs, p.steps_per_second, p.elapsed,
                  p.remaining >= 0 ? ("  ~" + num(p.remaining, 2) + "s left").c_str() : "",
                  p.peak_memory > 0 ? ("  peak " + thousands(p.peak_memory >> 20) + " MiB").c_str() : "");
    if (tty_) {
      std::fprintf(stderr, "\r%-120s", line);
      open_ = true;
    } else {
      std::fprintf(stderr, "pfill: %s\n", line);
    }
    std::fflush(stderr);
  }

  void end_line() {
    if (open_) std::fprintf(stderr, "\n");
    open_ = false;
  }

 private:
  bool quiet_;
  bool tty_;
  bool open_ = false;
  std::string phase_;
  std::chrono::steady_clock::time_point last_{};
};

Vec3 parse_point(const std::string& text) {
  Vec3 p;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &p.x, &p.y, &p.z, &extra) != 3 || !is_finite(p))
    throw Error("--birth '" + text + "': give three numbers X,Y,Z");
  return p;
}

void parse_exponents(const std::string& text, FillOptions& o) {
  char extra = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf%c", &o.exponent_a, &o.exponent_b, &extra) != 2 ||
      !(o.exponent_a > o.exponent_b && o.exponent_b > 0))
    throw Error("--exponents '" + text + "': give A,B with A > B > 0 (default 12,6)");
}

// Fails before a long fill, not after it, when an output cannot be written.
void check_output_folder(const std::string& path, const char* what) {
  if (path.empty() || path == "-") return;  // "-": standard output
  const fs::path folder = fs::absolute(fs::path(path)).parent_path();
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error("cannot write " + std::string(what) + " '" + path + "': the folder " + folder.string() +
                " does not exist; create it or choose another path");
}

void run_fill(FillArgs& a) {
  const bool from_file = !a.mesh.empty();
  if (a.output.empty())
    a.output = (from_file ? fs::path(a.mesh).stem().string() : a.builtin) + "_particles.ply";
  refuse_clashing_paths({{"the mesh", a.mesh}}, {{"-o", a.output}, {"--report", a.report}, {"--preview", a.preview}},
                        {"--frames", a.frames});
  const Mesh mesh = from_file ? load_mesh_argument(a.mesh) : make_builtin(a.builtin);
  check_output_folder(a.output, "the output");
  particle_format_from_path(a.output);  // an unknown extension fails now, not after the fill
  ParticleWriteOptions wo;
  wo.spheres = a.spheres;
  wo.velocities = a.velocities;
  wo.names = parse_attribute_names(a.attribute_names);
  wo.density = a.density;
  wo.box = mesh.bounds();  // LAMMPS .data: the box around the mesh
  check_output_folder(a.preview, "the preview");
  check_output_folder(a.report, "the report");
  if (!a.birth.empty()) a.options.birth_point = parse_point(a.birth);
  parse_exponents(a.exponents, a.options);
  a.options.stop = parse_stop_criterion(a.stop);
  if (!a.birth_speed.empty()) {
    char extra = 0;
    if (std::sscanf(a.birth_speed.c_str(), "%lf,%lf%c", &a.options.birth_speed_min, &a.options.birth_speed_max,
                    &extra) != 2)
      throw Error("--birth-speed '" + a.birth_speed + "': give MIN,MAX as fractions of the top speed (e.g. 0.2,0.5)");
  }
  if (!a.colour.empty()) a.options.colour = parse_colour_option(a.colour);
  if (a.options.radius <= 0 && a.options.count == 0) a.options.count = 4000;
  // --engine lammps: every MPI rank runs the fill (SPMD); rank 0 alone prints and writes.
  bool writer = true;
  if (a.engine == "lammps") {
    a.options.engine = lammps_engine_factory();  // one line when this pfill has no LAMMPS
    a.options.finish_on_engine = true;
    writer = lammps_mpi_start().rank == 0;
    if (!writer) a.quiet = true, a.verbose = false, a.frames.clear();
  }

  ProgressPrinter printer(a.quiet);
  a.options.progress = [&printer](const FillProgress& p) { printer(p); };
  if (a.verbose) a.options.log = [](const std::string& line) { std::fprintf(stderr, "pfill: %s\n", line.c_str()); };
  std::unique_ptr<FrameWriter> frames;
  if (!a.frames.empty()) {
    frames = std::make_unique<FrameWriter>(a.frames, 1, wo);
    a.options.frame_every = a.frame_every;
    a.options.on_frame = [&frames](uint64_t, const ParticleSet& s) { frames->write(s); };
  }
  if (!a.quiet) std::fprintf(stderr, "pfill: filling %s\n", mesh.source.c_str());
  // Ctrl-C stops the fill at its next sync (pfill::Cancelled); a second one ends pfill at once.
  static volatile std::sig_atomic_t interrupted = 0;
  a.options.cancelled = [] { return interrupted != 0; };
  defer_interrupts_to(&interrupted);
  FillResult r;
  try {
    r = fill(mesh, a.options);
  } catch (const Cancelled&) {
    defer_interrupts_to(nullptr);
    std::fprintf(stderr, "\npfill: interrupted: the fill stopped and wrote nothing\n");
    throw ExitStatus{128 + static_cast<int>(interrupted)};  // as a shell reports a process ended by that signal
  } catch (const Error&) {
    if (!writer) throw ExitStatus{kExitError};  // the same error on every rank: rank 0 says it
    throw;
  }
  defer_interrupts_to(nullptr);
  printer.end_line();
  if (!writer) return;
  for (const std::string& w : r.warnings) std::fprintf(stderr, "pfill: warning: %s\n", w.c_str());

  write_particles(r.particles, a.output, wo);
  if (frames) frames->write(r.particles);
  if (!a.preview.empty()) {
    RenderOptions ro;
    ro.cut = parse_cut("z");
    write_png(render(r.particles, &mesh, ro), a.preview);
  }
  const std::string report = fill_report_json(r, mesh.source, a.options.seed, a.output).dump(2) + "\n";
  if (!a.report.empty() && a.report != "-")
    write_file_atomically(a.report, [&](AtomicFile& f) { f.write(report); });
  if (a.json || a.report == "-") {  // the JSON alone on stdout, for scripts
    std::fputs(report.c_str(), stdout);
    return;
  }

  std::printf("%s -> %s  (radius %s, %s)\n", mesh.source.c_str(), a.output.c_str(), num(r.radius).c_str(),
              r.device.c_str());
  print_metrics(stdout, r.metrics);
  std::printf("  pass 1 ended    %s: %s\n", r.stop_signal.c_str(), r.stop_reason.c_str());
  std::printf("  settle          %s\n", r.settle_reason.c_str());
  std::printf("  finish          %s relaxations; %s added into holes; %s deleted where no arrangement met the bound%s\n",
              thousands(r.relief_rounds).c_str(), thousands(r.voids_filled).c_str(),
              thousands(r.relief_removed).c_str(),
              r.relief_forced ? (" (" + thousands(r.relief_forced) + " when the rounds ran out)").c_str() : "");
  std::printf("  removed         %s flagged outside, %s by the exact check (%s moved in)\n",
              thousands(r.lost_outside).c_str(), thousands(r.containment.removed).c_str(),
              thousands(r.containment.moved).c_str());
  std::string passes;
  for (const PassStats& p : r.passes)
    passes += (passes.empty() ? "" : ", ") + p.name + " " + thousands(p.steps) + " steps " + num(p.seconds, 3) + "s";
  std::printf("  time            %.1fs (field %.1fs; %s)\n", r.seconds, r.field_seconds, passes.c_str());
  if (r.peak_memory > 0)
    std::printf("  memory          peak %s MiB resident (the distance field %s MiB)\n",
                thousands(r.peak_memory >> 20).c_str(), thousands(r.field_bytes >> 20).c_str());
}

}  // namespace

CLI::App* add_fill_command(CLI::App& app) {
  auto a = std::make_shared<FillArgs>();
  FillOptions& o = a->options;
  CLI::App* cmd = app.add_subcommand("fill", "Fill a mesh with particles (no mesh: a built-in shape)");
  cmd->add_option("mesh", a->mesh,
                  "Mesh file: glTF/GLB, OBJ, STL, PLY, OFF, SMF, FBX, DAE, ...; or a built-in shape name (torus, "
                  "sphere, cube)");
  cmd->add_option("--builtin", a->builtin, "Built-in shape when no mesh is given: torus, sphere, cube")
      ->capture_default_str();
  cmd->add_option("-o,--output", a->output,
                  "Output file; format from the extension: .ply .glb .csv .vtp, .data (LAMMPS read_data, "
                  "atom_style sphere), .xyzr (Yade ymport.text) (default NAME_particles.ply here)");
  cmd->add_option("-r,--radius", o.radius, "Particle radius in mesh units")->check(positive_number());
  cmd->add_option("-n,--count", o.count, "About this many particles (picks the radius, allowing for --rest-distance; default 4000)")
      ->check(whole_number(1, SIZE_MAX));
  cmd->add_option("--rest-distance", o.rest_distance,
                  "Rest distance of the potential in contact distances 2r (>= 1; larger = sparser)")
      ->capture_default_str();
  cmd->add_option("--epsilon", o.epsilon, "Depth of the potential well")->capture_default_str();
  cmd->add_option("--cutoff", o.cutoff, "Cutoff in sigma (e.g. 2.5) for the attractive form; 0 = purely repulsive")
      ->capture_default_str();
  cmd->add_option("--exponents", a->exponents, "Potential exponents A,B (repulsive, attractive)")
      ->capture_default_str();
  cmd->add_option("--restitution", o.restitution, "Particle-particle restitution, 0..1")->capture_default_str();
  cmd->add_option("--wall-restitution", o.wall_restitution, "Particle-surface restitution, 0..1")
      ->capture_default_str();
  cmd->add_option("--damping", o.damping, "Velocity damping rate during the fill")->capture_default_str();
  cmd->add_option("--time-step", o.time_step, "Time step in units of the potential's time scale tau")
      ->capture_default_str();
  cmd->add_option("--seed", o.seed, "Random seed (same seed, mesh, options and device: same particles)")
      ->check(whole_number(0, UINT64_MAX))
      ->capture_default_str();
  cmd->add_option("--sites", o.sites,
                  "Birth sites: -1 = automatic (waves from about 2,000 particles on, else 2 sites); 0 = births in "
                  "waves over sites spread through the inside (one per --site-spacing); N = the deepest point, "
                  "then far deep points (the report's schedule)")
      ->capture_default_str();
  cmd->add_option("--site-spacing", o.site_spacing, "Waves (--sites 0): sites at least this many rest distances apart")
      ->capture_default_str();
  cmd->add_option("--site-min-depth", o.site_min_depth, "Waves (--sites 0): sites at least this many radii inside")
      ->capture_default_str();
  cmd->add_option("--site-depth", o.site_depth_share,
                  "Sites after the first lie at least this share of the deepest point's depth inside")
      ->capture_default_str();
  cmd->add_option("--birth-every", o.birth_every,
                  "Steps between birth attempts at each site (0 = automatic: 48 for waves, 3 with --sites N)")
      ->capture_default_str();
  cmd->add_option("--birth-clearance", o.birth_clearance,
                  "A site has room when no centre is within this many rest distances (0 = automatic: 0.55 for waves, 0.5 with --sites N)")
      ->capture_default_str();
  cmd->add_option("--birth-speed", a->birth_speed, "Newborn speed range MIN,MAX, fractions of the top speed (default 0.3,0.6)");
  cmd->add_option("--max-step", o.max_step_fraction, "Top speed: the most a particle moves in a step, in sigma")
      ->capture_default_str();
  cmd->add_option("--birth", a->birth, "First birth site X,Y,Z (must be inside; default the deepest point)");
  cmd->add_option("--stop", a->stop, "What ends pass 1: blocked (sites full), ke (kinetic energy), collisions")
      ->capture_default_str();
  cmd->add_option("--patience", o.blocked.patience, "Steps with no birth that mean the sites are blocked")
      ->capture_default_str();
  cmd->add_option("--stop-share", o.birth_stop_share,
                  "Waves (--sites 0): pass 1 also ends when the births of the last --patience steps are at most "
                  "this share of the particles (-1 = automatic: 0.03 under a --max-overlap below 0.01, else 0.003)")
      ->capture_default_str();
  cmd->add_option("--max-steps", o.max_steps,
                  "Step budget of pass 1 (0 = automatic: 100 a particle + 20,000); when it runs out, pass 1 ends "
                  "with what is in (for trials of large fills)")
      ->capture_default_str();
  cmd->add_option("--settle-steps", o.settle_budget, "Most steps of the settle pass (it ends sooner at rest)")
      ->capture_default_str()
      ->check(whole_number(1, UINT64_MAX));
  cmd->add_option("--void-rounds", o.void_rounds, "Rounds of inserting spheres into holes in the finish")
      ->capture_default_str();
  cmd->add_option("--void-clearance", o.void_clearance,
                  "A hole takes a sphere when the nearest centre is this many rest distances away")
      ->capture_default_str();
  cmd->add_option("--max-overlap", o.max_overlap, "Largest overlap of any pair after the finish, fraction of r (0: none)")
      ->capture_default_str();
  cmd->add_option("--colour", a->colour,
                  "Particle colours: surface (the mesh's colours/texture), depth, none or #RRGGBB "
                  "(default: surface when the mesh has colours, else none)");
  cmd->add_option("--skin", o.skin, "Neighbour-list skin in sigma; 0 = automatic (0.5 on CPUs, 0.3 on GPUs)")->capture_default_str();
  cmd->add_option("--sync-every", o.sync_every, "Steps between reads of the step history and positions")
      ->capture_default_str();
  cmd->add_option("--engine", a->engine,
                  "Particle engine: opencl (one OpenCL device) or lammps (LAMMPS across MPI ranks: mpirun -np P "
                  "pfill fill ... --engine lammps)")
      ->check(CLI::IsMember({"opencl", "lammps"}))
      ->capture_default_str();
  cmd->add_option("--device", o.device, "OpenCL device: index or name (see `pfill devices`; or PFILL_DEVICE)");
  cmd->add_option("--report", a->report,
                  "Write the metrics and the run's figures as JSON to this file (- : standard output, instead of "
                  "the summary)");
  cmd->add_flag("--json", a->json, "Print the summary as JSON (the --report document) on standard output");
  cmd->add_option("--preview", a->preview, "Render the result, cut open, to this PNG");
  cmd->add_option("--frames", a->frames, "Write the fill as numbered PLY frames into this folder");
  cmd->add_option("--every", a->frame_every, "Steps between frames")
      ->check(whole_number(1, UINT64_MAX))
      ->capture_default_str();
  cmd->add_flag("--spheres", a->spheres, "GLB: an instanced low-poly sphere per particle");
  cmd->add_flag("--velocities", a->velocities,
                "Write each particle's last velocity (PLY/CSV vx vy vz, VTP velocity, GLB _VELOCITY, LAMMPS "
                "Velocities, xyzr columns 6-8), also in --frames");
  cmd->add_option("--attribute-names", a->attribute_names,
                  "PLY and CSV attribute names: pfill (radius, red green blue, vx vy vz, id) or houdini "
                  "(pscale, Cd.r Cd.g Cd.b as floats 0..1, v.x v.y v.z, id)")
      ->check(CLI::IsMember({"pfill", "houdini"}))
      ->capture_default_str();
  cmd->add_option("--density", a->density, "LAMMPS .data: every particle's density (mass per volume, in the "
                                           "units of your LAMMPS run)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", a->quiet, "No progress output");
  cmd->add_flag("-v,--verbose", a->verbose, "Say what the fill chose for itself (the engine's automatic settings)");
  cmd->callback([a, cmd]() {
    if (!a->mesh.empty() && cmd->count("--builtin") > 0)
      throw Error("give a mesh file or --builtin NAME, not both");
    if (cmd->count("--radius") > 0 && cmd->count("--count") > 0)
      throw Error("give -r (the radius) or -n (a count, which picks the radius), not both");
    run_fill(*a);
  });
  return cmd;
}

}  // namespace pfill::cli
