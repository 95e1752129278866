// `pfill fill [MESH] -o OUT [options]`: the main job. Without a mesh it
// fills a built-in shape and writes into the current folder.
#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <map>
#include <optional>

#include "cli/commands.hpp"
#include "cli/contact_options.hpp"
#include "cli/shell_run.hpp"
#include "cli/format.hpp"
#include "cli/mesh_argument.hpp"
#include "cli/metrics_report.hpp"
#include "cli/number_checks.hpp"
#include "cli/path_checks.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/device/device.hpp"
#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/fill_report.hpp"
#include "pfill/fill_settings.hpp"
#include "pfill/lammps.hpp"
#include "pfill/particle_share.hpp"
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
  std::map<std::string, std::string> settings;  // FillOptions by name (fill_settings.hpp), as typed
  std::string engine = "opencl";      // --engine: opencl or lammps (docs/lammps_engine.md)
  bool spheres = false;
  bool velocities = false;
  bool quiet = false;
  bool verbose = false;               // the fill's own choices (FillOptions::log) on stderr
  bool json = false;                  // the summary as JSON on stdout
  std::string attribute_names = "pfill";
  double density = 1.0;               // LAMMPS .data
  ContactArgs contacts;               // --contacts, --contact-gap, --pairs
  ShellArgs shell;                    // --shell, --shell-radius
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
    if (p.phase == FillPhase::Field) {  // nothing to count yet
      if (new_phase) std::fprintf(stderr, "pfill: building the signed distance field\n");
      return;
    }
    if (new_phase && !tty_) std::fprintf(stderr, "pfill: %s\n", to_string(p.phase));
    char line[256];
    std::snprintf(line, sizeof line, "%-7s %9s particles (~%s when full)  KE %-9.3g pairs %-6u %7.0f steps/s  %5.0fs%s%s",
                  to_string(p.phase), thousands(p.particles).c_str(), thousands(p.target).c_str(), p.kinetic_energy,
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
  std::optional<FillPhase> phase_;  // none before the first line
  std::chrono::steady_clock::time_point last_{};
};

// A setting out of range is bad usage (exit 2): one line naming the flag.
[[noreturn]] void usage_error(const std::string& message) {
  std::fprintf(stderr, "pfill: error: %s\n", excerpt(message, 600).c_str());
  throw ExitStatus{kExitUsage};
}

// Fails before a long fill, not after it, when an output cannot be written:
// a missing or unwritable folder (a read-only file system, /sys), a path
// that is a folder. Probes the folder with a file of its own, removed at once.
void check_output_path(const std::string& path, const char* what) {
  if (path.empty() || path == "-") return;  // "-": standard output
  const fs::path folder = fs::absolute(fs::path(path)).parent_path();
  std::error_code ec;
  const std::string start = "cannot write " + std::string(what) + " '" + path + "': ";
  if (!fs::is_directory(folder, ec))
    throw Error(start + "the folder " + folder.string() + " does not exist; create it or choose another path");
  if (fs::is_directory(fs::path(path), ec)) throw Error(start + "it is a folder; give a file name");
  const fs::path probe = folder / (".pfill-probe-" + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) {
    const int error = errno;
    if (error != EEXIST)
      throw Error(start + "the folder " + folder.string() + " is not writable (" + std::strerror(error) + ")");
    return;
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

// Options that do nothing for the chosen output say so (stderr, not an error).
void warn_unused_options(const FillArgs& a, const CLI::App& cmd) {
  const ParticleFormat f = particle_format_from_path(a.output);
  auto warn = [](const std::string& what) { std::fprintf(stderr, "pfill: warning: %s\n", what.c_str()); };
  if (cmd.count("--density") > 0 && f != ParticleFormat::LammpsData)
    warn("--density applies to LAMMPS .data output only; ignored for " + a.output);
  if (cmd.count("--every") > 0 && a.frames.empty()) warn("--every applies to --frames only; ignored");
  if (a.spheres && f != ParticleFormat::Glb) warn("--spheres applies to .glb output only; ignored for " + a.output);
  if (cmd.count("--attribute-names") > 0 && f != ParticleFormat::Ply && f != ParticleFormat::Csv && a.frames.empty())
    warn("--attribute-names applies to .ply and .csv output only; ignored for " + a.output);
}

// The settings as the library takes them (the table's parsers), checked
// before the mesh is read: a bad value is bad usage, named by its flag.
void parse_settings(FillArgs& a, const CLI::App& cmd) {
  try {
    for (const FillSetting& setting : fill_settings())
      if (cmd.count(setting.flag()) > 0) setting.set(a.options, a.settings[setting.name]);
    // (--radii alone: its radii are in mesh units, no count to scale them to)
    if (a.options.radius <= 0 && a.options.count == 0 && !a.options.radii) a.options.count = 4000;
    check_fill_options(a.options);
  } catch (const Error& e) {
    usage_error(with_flags(e.what()));
  }
}

/// `-o out.%r.csv`: this rank's part of the particles (its own: those of
/// its LAMMPS sub-domain), written to the path with %r replaced by the
/// rank; `pfill join` puts the parts back together.
void write_rank_part(const ParticleSet& own, std::string path, int rank, const ParticleWriteOptions& wo) {
  ParticleSet part = own;
  if (!part.has_ids())
    for (size_t i = 0; i < own.size(); ++i) part.ids.push_back(own.id(i));
  for (size_t at; (at = path.find("%r")) != std::string::npos;) path.replace(at, 2, std::to_string(rank));
  write_particles(part, path, wo);
}

void run_fill(FillArgs& a, const CLI::App& cmd) {
  const bool from_file = !a.mesh.empty();
  if (a.output.empty())
    a.output = (from_file ? fs::path(a.mesh).stem().string() : a.builtin) + "_particles.ply";
  parse_settings(a, cmd);
  refuse_clashing_paths({{"the mesh", a.mesh}}, {{"-o", a.output}, {"--report", a.report}, {"--preview", a.preview}, {"--pairs", a.contacts.pairs}},
                        {"--frames", a.frames});
  particle_format_from_path(a.output);  // an unknown extension fails now, not after the fill
  if (!a.preview.empty()) {
    std::string ext = fs::path(a.preview).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".png") throw Error("--preview '" + a.preview + "': the preview is a PNG picture; give a .png path");
  }
  check_output_path(a.output, "the output");
  check_output_path(a.preview, "the preview");
  check_output_path(a.report, "the report");
  for (const std::string* path : {&a.output, &a.preview, &a.report})  // left by a SIGKILL during a rename
    if (!path->empty() && *path != "-") remove_stale_temporaries(*path);
  warn_unused_options(a, cmd);
  // OpenCL starts (~0.1 s) on the other core while this one reads the mesh
  // (0.22 s for the bunny), not beside the field's two threads.
  std::future<void> opencl;
  if (a.engine != "lammps")
    opencl = std::async(std::launch::async, preload_platforms);
  const Mesh mesh = from_file ? load_mesh_argument(a.mesh) : make_builtin(a.builtin);
  if (mesh.turned_faces > 0 && !a.quiet)
    std::fprintf(stderr, "pfill: warning: the winding was inconsistent: %s faces were turned to agree with their "
                         "neighbours\n", thousands(mesh.turned_faces).c_str());
  ParticleWriteOptions wo;
  wo.spheres = a.spheres;
  wo.velocities = a.velocities;
  wo.names = parse_attribute_names(a.attribute_names);
  wo.density = a.density;
  wo.box = mesh.bounds();  // LAMMPS .data: the box around the mesh
  std::unique_ptr<ShellRun> shell;  // --shell: the fill in the mesh moved in by the shell's radius
  if (a.shell.shell) shell = std::make_unique<ShellRun>(a.shell, mesh, a.options);
  // -o with %r: every rank writes its own part of the output (docs/lammps_engine.md)
  const bool parts = a.output.find("%r") != std::string::npos;
  if (parts && (shell || a.contacts.wanted()))
    usage_error("-o with %r (a file per MPI rank) takes neither --shell nor contacts (--contacts, --pairs): "
                "give one output file");
  // Rank 0 needs the whole set after a fill across ranks: to write one file, a preview or the last frame.
  const bool whole_on_first = !parts || !a.preview.empty() || !a.frames.empty();
  // --engine lammps: every MPI rank runs the fill (SPMD); rank 0 alone prints and writes.
  bool writer = true;
  int rank = 0;
  if (a.engine == "lammps") {
    a.options.engine = lammps_engine_factory();  // one line when this pfill has no LAMMPS
    a.options.finish_on_engine = true;
    a.options.wall_from_mesh = true;  // each rank computes only the wall its spheres reach
    rank = lammps_mpi_start().rank;
    writer = rank == 0;
    if (!writer) {
      a.quiet = true, a.verbose = false;
      if (!a.frames.empty()) {  // every rank takes each frame (collective); rank 0 writes it
        a.options.frame_every = a.frame_every;
        a.options.on_frame = [](uint64_t, const ParticleSet&) {};
      }
      a.frames.clear();
    }
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
    r = fill(shell ? shell->fill_mesh() : mesh, a.options);
  } catch (const Cancelled&) {
    defer_interrupts_to(nullptr);
    if (frames && frames->frames_written() > 0)
      std::fprintf(stderr, "\npfill: interrupted: the fill stopped; %llu frames are in %s, no output was written\n",
                   static_cast<unsigned long long>(frames->frames_written()), a.frames.c_str());
    else
      std::fprintf(stderr, "\npfill: interrupted: the fill stopped and wrote nothing\n");
    throw ExitStatus{128 + static_cast<int>(interrupted)};  // as a shell reports a process ended by that signal
  } catch (const Error& e) {
    defer_interrupts_to(nullptr);
    if (!writer) throw ExitStatus{kExitError};  // the same error on every rank: rank 0 says it
    throw Error(with_flags(e.what()));  // the library names its settings as C++ does
  }
  defer_interrupts_to(nullptr);
  printer.end_line();
  // Each rank holds its own spheres (FillResult::in_parts): it writes them
  // as its part, or they go to rank 0, which writes the whole (so does a
  // preview, or the last frame, need). A result every rank holds whole
  // (unequal spheres on LAMMPS): rank 0's part is all of it.
  if (parts) write_rank_part(r.in_parts || writer ? r.particles : ParticleSet(), a.output, rank, wo);
  if (r.in_parts && whole_on_first) r.particles = gather_particles(*lammps_process_group(), r.particles);
  if (!writer) return;
  if (shell) {
    shell->join(r);  // r.particles: the inner spheres, then the shell's
    wo.attributes = &shell->attributes();
  }
  for (const std::string& w : r.warnings)
    std::fprintf(stderr, "pfill: warning: %s\n", with_flags(w).c_str());

  ContactResult contacts;  // after the fill, from its final particles
  if (a.contacts.wanted()) {
    const Boundary boundary(mesh);
    contacts = find_and_write_contacts(a.contacts, r.particles, &boundary);
    wo.contacts = contacts.network.get();
  }
  if (!parts) write_particles(r.particles, a.output, wo);
  wo.contacts = nullptr;
  if (frames) frames->write(r.particles);
  if (!a.preview.empty()) {
    RenderOptions ro;
    ro.cut = parse_cut("z");
    write_png(render(r.particles, &mesh, ro), a.preview);
  }
  nlohmann::ordered_json report_json = fill_report_json(r, mesh.source, a.options.seed, a.output);
  if (contacts.network) report_json["contacts"] = contacts.report;
  if (shell) report_json["shell"] = shell->report();
  const std::string report = report_json.dump(2) + "\n";
  if (!a.report.empty() && a.report != "-")
    write_file_atomically(a.report, [&](AtomicFile& f) { f.write(report); });
  if (a.json || a.report == "-") {  // the JSON alone on stdout, for scripts
    std::fputs(report.c_str(), stdout);
    return;
  }

  const std::string sizes = r.radii ? "radii " + num(r.radii->min_radius()) + ".." + num(r.radii->max_radius())
                                    : "radius " + num(r.radius);
  std::printf("%s -> %s  (%s, %s)\n", mesh.source.c_str(), a.output.c_str(), sizes.c_str(), r.device.c_str());
  print_metrics(stdout, r.metrics);
  if (r.radii_fit) print_radii_fit(stdout, *r.radii, *r.radii_fit);
  if (contacts.network) print_contacts_line(stdout, *contacts.network, true);
  if (shell) shell->print(stdout);
  std::printf("  pass 1 ended    %s: %s\n", r.stop_signal.c_str(), r.stop_reason.c_str());
  std::printf("  settle          %s\n", r.settle_reason.c_str());
  std::printf("  finish          %s relaxations%s; %s added into holes; %s deleted where no arrangement met the bound%s\n",
              thousands(r.finish_rounds).c_str(),
              r.finish_near_rounds ? (" (" + thousands(r.finish_near_rounds) + " of the last jams alone)").c_str() : "",
              thousands(r.holes_filled).c_str(),
              thousands(r.finish_removed).c_str(),
              r.finish_forced ? (" (" + thousands(r.finish_forced) + " when the rounds ran out)").c_str() : "");
  std::printf("  removed         %s flagged outside, %s by the exact check (%s moved in)\n",
              thousands(r.lost_outside).c_str(), thousands(r.containment.removed).c_str(),
              thousands(r.containment.moved).c_str());
  std::string passes;
  for (const PassStats& p : r.passes)
    passes += (passes.empty() ? "" : ", ") + p.name + " " + thousands(p.steps) + " steps " + num(p.seconds, 3) + "s" +
              (p.kernel_seconds >= 0  // PFILL_PROFILE=1
                   ? " [kernels " + num(p.kernel_seconds, 3) + "s, transfers " + num(p.transfer_seconds, 3) + "s" +
                         (p.list_rebuilds >= 0 ? ", lists rebuilt on " + thousands(p.list_rebuilds) + " steps" : "") +
                         "]"
                   : std::string());
  std::printf("  time            %.1fs (field %.1fs; set-up %ss; %s; verify %ss)\n", r.seconds, r.field_seconds,
              num(r.setup_seconds, 2).c_str(), passes.c_str(), num(r.verify_seconds, 2).c_str());
  // (The LAMMPS engine's waves build no field: the mesh answers.)
  if (r.peak_memory > 0)
    std::printf("  memory          peak %s MiB resident (%s)\n", thousands(r.peak_memory >> 20).c_str(),
                r.field_bytes > 0 ? ("the distance field " + thousands(r.field_bytes >> 20) + " MiB").c_str()
                                  : "no distance field");
}

}  // namespace

CLI::App* add_fill_command(CLI::App& app, bool show_all) {
  auto a = std::make_shared<FillArgs>();
  CLI::App* cmd = app.add_subcommand("fill", "Fill a mesh with particles (no mesh: a built-in shape)");
  const std::string details = show_all ? "Output details" : "";  // shown by --help-all
  cmd->add_flag("--help-all", "Also show the tuning options and the output details (all accepted always)");
  cmd->add_option("mesh", a->mesh,
                  "Mesh file: glTF/GLB, OBJ, STL, PLY, OFF, SMF, FBX, DAE, ...; or a built-in shape name (torus, "
                  "sphere, cube)");
  cmd->add_option("--builtin", a->builtin, "Built-in shape when no mesh is given: torus, sphere, cube")
      ->capture_default_str()
      ->group(details);
  cmd->add_option("-o,--output", a->output,
                  "Output file; format from the extension: .ply .glb .csv .vtp, .data (LAMMPS read_data, "
                  "atom_style sphere), .xyzr (Yade ymport.text) (default NAME_particles.ply here); with --engine lammps, "
                  "%r in the name writes a file per MPI rank (pfill join)");
  // Every FillOptions setting from the table, by its one name; the
  // tuning ones only in `pfill fill --help-all` (still accepted always).
  for (const FillSetting& setting : fill_settings()) {
    const std::string flags = (setting.short_flag.empty() ? "" : setting.short_flag + ",") + setting.flag();
    const std::string shown = setting.get(FillOptions{});
    CLI::Option* opt = cmd->add_option(flags, a->settings[setting.name],
                                       setting.help + (shown.empty() ? "" : " [" + shown + "]"));
    opt->type_name(setting.value_form);
    opt->group(setting.tier == SettingTier::User ? "Options" : show_all ? "Tuning" : "");
  }
  cmd->add_option("--engine", a->engine,
                  "Particle engine: opencl (one OpenCL device) or lammps (LAMMPS across MPI ranks: mpirun -np P "
                  "pfill fill ... --engine lammps)")
      ->check(CLI::IsMember({"opencl", "lammps"}))
      ->capture_default_str();
  cmd->add_option("--report", a->report,
                  "Write the metrics and the run's figures as JSON to this file (- : standard output, instead of "
                  "the summary)");
  cmd->add_flag("--json", a->json, "Print the summary as JSON (the --report document) on standard output");
  cmd->add_option("--preview", a->preview, "Render the result, cut open, to this PNG");
  cmd->add_option("--frames", a->frames, "Write the fill as numbered PLY frames into this folder");
  cmd->add_option("--every", a->frame_every, "Steps between frames")
      ->check(whole_number(1, UINT64_MAX))
      ->capture_default_str()
      ->group(details);
  cmd->add_flag("--spheres", a->spheres, "GLB: an instanced low-poly sphere per particle");
  cmd->add_flag("--velocities", a->velocities,
                "Write each particle's last velocity (PLY/CSV vx vy vz, VTP velocity, GLB _VELOCITY, LAMMPS "
                "Velocities, xyzr columns 6-8), also in --frames")
      ->group(details);
  cmd->add_option("--attribute-names", a->attribute_names,
                  "PLY and CSV attribute names: pfill (radius, red green blue, vx vy vz, id) or houdini "
                  "(pscale, Cd.r Cd.g Cd.b as floats 0..1, v.x v.y v.z, id)")
      ->check(CLI::IsMember({"pfill", "houdini"}))
      ->capture_default_str()
      ->group(details);
  cmd->add_option("--density", a->density, "LAMMPS .data: every particle's density (mass per volume, in the "
                                           "units of your LAMMPS run)")
      ->check(positive_number("--density"))
      ->capture_default_str()
      ->group(details);
  add_contact_options(cmd, a->contacts, true, details);
  add_shell_options(cmd, a->shell, details);
  cmd->add_flag("-q,--quiet", a->quiet, "No progress output");
  cmd->add_flag("-v,--verbose", a->verbose, "Say what the fill chose for itself (the engine's automatic settings)")
      ->group(details);
  cmd->callback([a, cmd]() {
    if (!a->mesh.empty() && cmd->count("--builtin") > 0)
      throw Error("give a mesh file or --builtin NAME, not both");
    if (cmd->count("--radius") > 0 && cmd->count("--count") > 0)
      throw Error("give -r (the radius) or -n (a count, which picks the radius), not both");
    run_fill(*a, *cmd);
  });
  return cmd;
}

}  // namespace pfill::cli
