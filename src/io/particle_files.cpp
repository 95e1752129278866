// Choosing a particle format by extension, and the frame sequence of a fill.
#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdio>
#include <system_error>

#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"

namespace fs = std::filesystem;

namespace pfill {

ParticleFormat particle_format_from_path(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".ply") return ParticleFormat::Ply;
  if (extension == ".glb") return ParticleFormat::Glb;
  if (extension == ".csv") return ParticleFormat::Csv;
  if (extension == ".vtp") return ParticleFormat::Vtp;
  if (extension == ".data") return ParticleFormat::LammpsData;
  if (extension == ".xyzr") return ParticleFormat::Xyzr;
  throw Error("'" + path.string() + "': unknown particle file type '" + extension +
              "' (use .ply, .glb, .csv, .vtp, .data for LAMMPS or .xyzr for Yade)");
}

bool positions_need_doubles(const ParticleSet& particles) {
  double far = 0, smallest = HUGE_VAL;
  for (const Vec3& p : particles.positions) far = std::max({far, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  for (double r : particles.radii) smallest = std::min(smallest, r);
  return far * 0x1p-24 > 1e-5 * smallest;
}

AttributeNames parse_attribute_names(const std::string& text) {
  if (text == "pfill") return AttributeNames::Pfill;
  if (text == "houdini") return AttributeNames::Houdini;
  throw Error("attribute names '" + text + "': use pfill (radius, red green blue, vx vy vz) or houdini "
              "(pscale, Cd, v)");
}

void write_particles(const ParticleSet& particles, const fs::path& path,
                     const ParticleWriteOptions& options) {
  switch (particle_format_from_path(path)) {
    case ParticleFormat::Ply: return write_ply(particles, path, options);
    case ParticleFormat::Glb: return write_glb(particles, path, options);
    case ParticleFormat::Csv: return write_csv(particles, path, options);
    case ParticleFormat::Vtp: return write_vtp(particles, path, options);
    case ParticleFormat::LammpsData: return write_lammps_data(particles, path, options);
    case ParticleFormat::Xyzr: return write_xyzr(particles, path, options);
  }
}

ParticleSet read_particles(const fs::path& path, const ParticleReadOptions& options) {
  const ParticleFormat format = particle_format_from_path(path);
  switch (format) {
    case ParticleFormat::Ply: return read_ply(path, options);
    case ParticleFormat::Csv: return read_csv(path, options);
    case ParticleFormat::Glb: return read_glb(path, options);
    case ParticleFormat::Vtp: return read_vtp(path, options);
    case ParticleFormat::LammpsData: return read_lammps_data(path, options);
    case ParticleFormat::Xyzr: return read_xyzr(path, options);
  }
  throw Error("cannot read '" + path.string() + "': unknown particle format");
}

FrameWriter::FrameWriter(fs::path dir, uint64_t every, ParticleWriteOptions options)
    : dir_(std::move(dir)), every_(every), options_(std::move(options)) {
  if (every_ == 0) throw Error("frames every 0 steps: give a positive interval (--every K)");
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    throw Error("cannot create the frames folder '" + dir_.string() + "': " +
                (ec ? ec.message() : std::string("a file of that name exists")));
  // Frames of an earlier run would stay beside the new ones (and `pfill
  // render DIR` would show them as one sequence): refuse, before the fill.
  const size_t stale = list_frames(dir_).size();
  if (stale > 0)
    throw Error("the frames folder '" + dir_.string() + "' already holds " + std::to_string(stale) +
                " frames (frame_*.ply) of an earlier fill; remove them or choose an empty folder");
}

bool FrameWriter::offer(uint64_t step, const ParticleSet& particles) {
  if (step % every_ != 0) return false;
  write(particles);
  return true;
}

fs::path FrameWriter::write(const ParticleSet& particles) {
  const fs::path path = frame_path(dir_, next_frame_);
  write_ply(particles, path, options_);
  ++next_frame_;
  return path;
}

fs::path FrameWriter::frame_path(const fs::path& dir, uint64_t frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06llu.ply", static_cast<unsigned long long>(frame));
  return dir / name;
}

std::vector<fs::path> list_frames(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("'" + dir.string() + "' is not a folder of frames");
  std::vector<fs::path> frames;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name.rfind("frame_", 0) == 0 && entry.path().extension() == ".ply")
      frames.push_back(entry.path());
  }
  if (ec) throw Error("cannot list '" + dir.string() + "': " + ec.message());
  // Zero-padded names sort in frame order; longer names (past 999999) after.
  std::sort(frames.begin(), frames.end(), [](const fs::path& a, const fs::path& b) {
    const std::string na = a.filename().string(), nb = b.filename().string();
    return na.size() != nb.size() ? na.size() < nb.size() : na < nb;
  });
  return frames;
}

}  // namespace pfill
