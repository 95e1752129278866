// `pfill render`: a picture of a particle file, or numbered pictures of a
// --frames folder with one fixed camera.
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include <unistd.h>

#include "cli/commands.hpp"
#include "cli/mesh_argument.hpp"
#include "cli/path_checks.hpp"
#include "pfill/boundary.hpp"
#include "pfill/colour.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/render.hpp"
#include "pfill/shapes.hpp"

namespace fs = std::filesystem;

namespace pfill {
namespace {

struct RenderArguments {
  std::string input;
  std::string output;
  std::string mesh;
  std::string view = "three-quarter";
  std::string size = "1024x768";
  std::string cut;
  std::string colour;  // empty: keep the file's colours
  std::string frame_camera = "union";
  double radius = 0;
  int samples = 2;
  int ao_rays = 6;
};

// The shell drawn around the particles: a built-in shape name or a mesh file.
std::optional<Mesh> load_shell(const std::string& name) {
  if (name.empty()) return std::nullopt;
  return cli::load_mesh_argument(name);
}

void parse_size(const std::string& text, RenderOptions& options) {
  int w = 0, h = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &extra) != 2 || w < 1 || h < 1 || w > 16384 || h > 16384)
    throw Error("--size '" + text + "': give WIDTHxHEIGHT in pixels, each 1..16384 (e.g. 1024x768)");
  options.width = w;
  options.height = h;
}

// `--colour`: recolours each particle set before it is drawn. Surface and
// depth need the mesh (its Boundary is built once, for all frames).
class Recolour {
 public:
  Recolour(const std::string& text, const Mesh* shell) {
    if (text.empty()) return;
    options_ = parse_colour_option(text);
    const bool needs_mesh = options_->mode == ColourMode::Surface || options_->mode == ColourMode::Depth;
    if (needs_mesh && !shell)
      throw Error("--colour " + text + " colours from the mesh: give it with --mesh (or use none or #RRGGBB)");
    if (needs_mesh) boundary_ = std::make_unique<Boundary>(*shell);
  }

  void apply(ParticleSet& particles) {
    if (!options_) return;
    if (options_->mode == ColourMode::None) {
      particles.colours.clear();
    } else if (options_->mode == ColourMode::Constant) {
      particles.colours.assign(particles.size(), options_->constant);
    } else {
      const std::string note = colour_particles(*boundary_, particles, *options_);
      if (!note.empty() && !noted_) std::fprintf(stderr, "pfill render: note: %s\n", note.c_str());
      noted_ = noted_ || !note.empty();
    }
  }

 private:
  std::optional<ColourOptions> options_;
  std::unique_ptr<Boundary> boundary_;
  bool noted_ = false;  // say a fallback once, not once per frame
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void render_file(const RenderArguments& args, const RenderOptions& options, const Mesh* shell) {
  const auto start = std::chrono::steady_clock::now();
  Recolour recolour(args.colour, shell);
  ParticleReadOptions read;
  read.default_radius = args.radius;
  ParticleSet particles = read_particles(args.input, read);
  recolour.apply(particles);
  write_png(render(particles, shell, options), args.output);
  std::fprintf(stderr, "pfill render: wrote %s (%dx%d, %zu particles, %.2f s)\n", args.output.c_str(),
               options.width, options.height, particles.size(), seconds_since(start));
}

// Every frame_*.ply of the folder into OUT/frame_*.png, one camera (and one
// cut plane) for all, framed on the union of all frames or on the last one.
void render_frames(const RenderArguments& args, RenderOptions options, const Mesh* shell) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<fs::path> frames = list_frames(args.input);
  if (frames.empty()) throw Error("'" + args.input + "' holds no frame_*.ply files (write them with --frames)");
  Recolour recolour(args.colour, shell);
  std::error_code ec;
  fs::create_directories(args.output, ec);
  if (!fs::is_directory(args.output))
    throw Error("cannot create the output folder '" + args.output + "'" + (ec ? ": " + ec.message() : ""));
  ParticleReadOptions read;
  read.default_radius = args.radius;

  Box3 box = shell ? shell->bounds() : Box3{};
  if (args.frame_camera == "last") {
    const Box3 last = read_particles(frames.back(), read).bounds();
    if (!last.empty()) box.add(last.lo), box.add(last.hi);
  } else {
    for (const fs::path& frame : frames) {
      const Box3 b = read_particles(frame, read).bounds();
      if (!b.empty()) box.add(b.lo), box.add(b.hi);
    }
  }
  if (options.cut && !options.cut->value) options.cut->value = box.empty() ? 0.0 : box.centre()[options.cut->axis];
  if (options.cut && !box.empty())
    box.hi[options.cut->axis] = std::max(box.lo[options.cut->axis], std::min(box.hi[options.cut->axis], *options.cut->value));
  options.camera = frame_camera(box, options.view, double(options.width) / options.height);

  // One updating line on a terminal, plain lines otherwise (logs, CI).
  const bool terminal = ::isatty(::fileno(stderr)) != 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    const fs::path out = fs::path(args.output) / (frames[i].stem().string() + ".png");
    ParticleSet particles = read_particles(frames[i], read);
    recolour.apply(particles);
    write_png(render(particles, shell, options), out);
    std::fprintf(stderr, terminal ? "\rpfill render: %zu/%zu %s" : "pfill render: %zu/%zu %s\n", i + 1,
                 frames.size(), out.filename().c_str());
  }
  if (terminal) std::fprintf(stderr, "\n");
  std::fprintf(stderr, "pfill render: wrote %zu pictures to %s (%.1f s)\n", frames.size(), args.output.c_str(),
               seconds_since(start));
}

}  // namespace

namespace cli {

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArguments>();
  CLI::App* command = app.add_subcommand(
      "render", "Draw particles as spheres into a PNG; a folder of --frames becomes numbered PNGs");
  command->add_option("input", args->input, "Particle file (.ply, .csv) or a folder of frame_*.ply")->required();
  command->add_option("-o,--output", args->output, "PNG file, or the output folder for frames")->required();
  command->add_option("--mesh", args->mesh, "Draw this mesh file (or built-in sphere, cube, torus) as a faint shell");
  command->add_option("--view", args->view, "Camera direction: three-quarter, front, side, top or iso")
      ->capture_default_str();
  command->add_option("--size", args->size, "Picture size in pixels, WIDTHxHEIGHT")->capture_default_str();
  command->add_option("--cut", args->cut,
                      "Cut the object open: remove spheres with centre beyond x|y|z=VALUE (default the centre)");
  command->add_option("--colour", args->colour,
                      "Recolour the particles: surface (from --mesh: its colours or texture), depth (distance "
                      "to --mesh), none, or #RRGGBB; default: keep the file's colours");
  command->add_option("--radius", args->radius, "Radius for particle files that have none");
  command->add_option("--samples", args->samples, "Anti-aliasing: N x N samples per pixel (1..8)")
      ->capture_default_str();
  command->add_option("--ao", args->ao_rays, "Ambient-occlusion rays per hit (0..64; 0 is fastest)")
      ->capture_default_str();
  command->add_option("--frame-camera", args->frame_camera,
                      "Frames: frame the camera on the union of all frames or on the last one")
      ->check(CLI::IsMember({"union", "last"}))
      ->capture_default_str();
  command->callback([args] {
    RenderOptions options;
    parse_size(args->size, options);
    options.view = parse_view(args->view);
    if (!args->cut.empty()) options.cut = parse_cut(args->cut);
    options.samples_per_axis = args->samples;
    options.ambient_occlusion_rays = args->ao_rays;
    if (!fs::is_directory(args->input))
      cli::refuse_clashing_paths({{"the particle file", args->input}, {"--mesh", args->mesh}}, {{"-o", args->output}});
    const std::optional<Mesh> shell = load_shell(args->mesh);
    const Mesh* shell_pointer = shell ? &*shell : nullptr;
    if (fs::is_directory(args->input))
      render_frames(*args, options, shell_pointer);
    else
      render_file(*args, options, shell_pointer);
  });
}

}  // namespace cli
}  // namespace pfill
