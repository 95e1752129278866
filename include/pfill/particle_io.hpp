/// @file particle_io.hpp
/// @brief Particle files: writers for PLY, GLB, CSV, VTK PolyData (.vtp),
/// LAMMPS data (.data) and Yade text (.xyzr), readers for PLY and CSV, and
/// the numbered frame sequence of a fill.
///
/// Every format carries each particle's id (ParticleSet::id: stable through
/// a fill, so frames can be matched particle by particle) and, when asked
/// and the set has them, its velocity.
///
/// Every writer is atomic (see atomic_file.hpp): on any error the target is
/// left as it was and pfill::Error names the path and the reason. The format
/// follows the extension of the path (case-insensitive).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "pfill/contacts.hpp"
#include "pfill/particle_attributes.hpp"
#include "pfill/particles.hpp"

namespace pfill {

enum class ParticleFormat { Ply, Glb, Csv, Vtp, LammpsData, Xyzr };

/// The format of `path` from its extension (.ply .glb .csv .vtp .data .xyzr); throws
/// pfill::Error listing the supported extensions otherwise.
ParticleFormat particle_format_from_path(const std::filesystem::path& path);

/// How PLY and CSV name their attributes.
enum class AttributeNames {
  Pfill,   ///< radius, red green blue (PLY uchar; CSV r,g,b 0..255), vx vy vz, id
  Houdini  ///< pscale, Cd.r Cd.g Cd.b (floats 0..1, sRGB), v.x v.y v.z, id
};

/// "pfill" or "houdini"; throws pfill::Error naming both otherwise.
AttributeNames parse_attribute_names(const std::string& text);

struct ParticleWriteOptions {
  bool velocities = true;   ///< write velocities when the set has them
  bool spheres = false;     ///< GLB: add an instanced low-poly sphere per particle
  int sphere_subdivisions = 1;  ///< GLB spheres: icosphere level (1: 80 triangles)
  bool vtp_binary = true;   ///< VTP: appended raw binary (false: ascii)
  AttributeNames names = AttributeNames::Pfill;  ///< PLY and CSV attribute names
  /// LAMMPS data: the simulation box before its margin (e.g. the mesh's
  /// bounds); empty: the particles' bounds. The box is grown by a margin of
  /// 5% of its largest side (at least the largest radius) on every side.
  Box3 box;
  double density = 1.0;     ///< LAMMPS data: every particle's density (mass / volume)
  /// The contact network of these particles (contacts.hpp), or none. With
  /// one, every format carries each particle's `coordination`, and PLY adds
  /// `element edge` (int vertex1 vertex2, float gap), VTP a line cell per
  /// pair, LAMMPS data `Bonds` (atom_style hybrid sphere bond).
  const ContactNetwork* contacts = nullptr;
  /// Boundary particles' attributes (particle_attributes.hpp), or none: each
  /// present vector is written, as `kind` (uchar), nx ny nz and `area` (PLY,
  /// CSV; VTP kind, normal, area; GLB _KIND, _NORMAL, _AREA; xyzr columns),
  /// and LAMMPS data gives each kind its atom type (1 inner, 2 boundary).
  const ParticleAttributes* attributes = nullptr;
};

/// Whether float32 positions would move some sphere by more than 1e-5 of the
/// smallest radius (far from the origin): PLY then stores doubles, GLB its
/// points about their centre with the node's translation.
bool positions_need_doubles(const ParticleSet& particles);

/// Writes `particles` in the format named by the extension of `path`.
void write_particles(const ParticleSet& particles, const std::filesystem::path& path,
                     const ParticleWriteOptions& options = {});

/// Binary little-endian PLY: element vertex with float x y z radius, uchar
/// red green blue (with colours), float vx vy vz (with velocities), uint id.
/// Houdini names: pscale, float Cd.r Cd.g Cd.b (0..1), v.x v.y v.z, id.
void write_ply(const ParticleSet& particles, const std::filesystem::path& path,
               const ParticleWriteOptions& options = {});

/// glTF binary. Node "particles": one POINTS primitive with POSITION (min/max
/// set), COLOR_0 (linear FLOAT VEC3) with colours, and the radius as the
/// custom attribute _RADIUS (SCALAR FLOAT), the id as _ID (SCALAR FLOAT:
/// glTF allows no integer vertex attributes past 16 bits; exact to 2^24) and,
/// with velocities, _VELOCITY (VEC3 FLOAT). With options.spheres, also node
/// "particle spheres": a unit icosphere scaled to the mean radius, instanced
/// once per particle by EXT_mesh_gpu_instancing (TRANSLATION, SCALE, and
/// _COLOR_0 with colours). The extension is listed in extensionsUsed only,
/// not extensionsRequired, so viewers without it still open the file: they
/// show the points and one particle-sized sphere at the spheres node's origin.
void write_glb(const ParticleSet& particles, const std::filesystem::path& path,
               const ParticleWriteOptions& options = {});

/// CSV with header x,y,z,radius[,r,g,b][,vx,vy,vz],id (Houdini names:
/// x,y,z,pscale[,Cd.r,Cd.g,Cd.b][,v.x,v.y,v.z],id); numbers at full double
/// precision (max_digits10), so a read gives back the same values.
void write_csv(const ParticleSet& particles, const std::filesystem::path& path,
               const ParticleWriteOptions& options = {});

/// VTK XML PolyData: Points (Float64), one vertex cell per particle, PointData
/// "radius", "id" (Int64), "colour" (UInt8 x3) and "velocity" (Float64 x3)
/// where present.
void write_vtp(const ParticleSet& particles, const std::filesystem::path& path,
               const ParticleWriteOptions& options = {});

/// LAMMPS data file for atom_style sphere: one atom type, Atoms lines
/// `id type diameter density x y z` (ids: ParticleSet::id), a Velocities
/// section `id vx vy vz 0 0 0` with velocities; the box from options.box.
/// Colours are not written (LAMMPS has no place for them).
void write_lammps_data(const ParticleSet& particles, const std::filesystem::path& path,
                       const ParticleWriteOptions& options = {});

/// Whitespace text for Yade's ymport.text: `#` comment lines, then one line
/// `x y z r id` per particle (ymport.text reads the first four columns),
/// followed by `vx vy vz` with velocities. Colours are not written.
void write_xyzr(const ParticleSet& particles, const std::filesystem::path& path,
                const ParticleWriteOptions& options = {});

struct ParticleReadOptions {
  /// Radius of every particle when the file has none; 0 means "the file must
  /// have radii" (an error otherwise).
  double default_radius = 0.0;
  /// Where given, set to the boundary particles' attributes the file holds
  /// (`kind`, nx ny nz, `area`: as the writers name them in each format;
  /// vectors the file lacks stay empty). PLY, CSV, VTP, GLB and .xyzr carry
  /// them; LAMMPS data gives none.
  ParticleAttributes* attributes = nullptr;
};

/// Reads any particle file pfill writes (by extension: .ply .glb .csv .vtp
/// .data .xyzr).
ParticleSet read_particles(const std::filesystem::path& path, const ParticleReadOptions& options = {});

/// pfill's GLB: the POINTS primitive (POSITION, _RADIUS, _ID, COLOR_0,
/// _VELOCITY), moved by its node's translation.
ParticleSet read_glb(const std::filesystem::path& path, const ParticleReadOptions& options = {});
/// VTK PolyData as write_vtp writes it (ascii or appended raw, Float32/64).
ParticleSet read_vtp(const std::filesystem::path& path, const ParticleReadOptions& options = {});
/// LAMMPS data, atom_style sphere: the Atoms section `id type diameter density x y z`.
ParticleSet read_lammps_data(const std::filesystem::path& path, const ParticleReadOptions& options = {});
/// Yade text: `x y z r [id ...]` lines after `#` comments.
ParticleSet read_xyzr(const std::filesystem::path& path, const ParticleReadOptions& options = {});

/// PLY in ascii, binary_little_endian or binary_big_endian; reads x y z and,
/// where present, radius, red green blue (uchar, or float in [0,1]) and vx vy
/// vz from the vertex element, of any scalar type; other properties and
/// elements are skipped. Truncated or malformed files throw pfill::Error.
ParticleSet read_ply(const std::filesystem::path& path, const ParticleReadOptions& options = {});

/// CSV whose header names the columns x,y,z[,radius][,r,g,b][,vx,vy,vz] in
/// any order (case-insensitive; other columns ignored).
ParticleSet read_csv(const std::filesystem::path& path, const ParticleReadOptions& options = {});

/// Writes a fill as numbered PLY files DIR/frame_000000.ply, frame_000001.ply,
/// ... one every `every` steps, each atomically; creates DIR, and refuses a
/// DIR that already holds frames (they would mix with the new ones). Each frame
/// carries the particles' ids, so a particle can be followed across frames.
class FrameWriter {
 public:
  FrameWriter(std::filesystem::path dir, uint64_t every, ParticleWriteOptions options = {});

  /// Writes a frame when step % every == 0; returns whether it did.
  bool offer(uint64_t step, const ParticleSet& particles);
  /// Writes the next frame unconditionally (e.g. the final state); returns its path.
  std::filesystem::path write(const ParticleSet& particles);

  uint64_t frames_written() const { return next_frame_; }
  const std::filesystem::path& dir() const { return dir_; }

  /// DIR/frame_NNNNNN.ply
  static std::filesystem::path frame_path(const std::filesystem::path& dir, uint64_t frame);

 private:
  std::filesystem::path dir_;
  uint64_t every_;
  ParticleWriteOptions options_;
  uint64_t next_frame_ = 0;
};

/// The frame_*.ply files of `dir`, in frame order; throws pfill::Error when
/// `dir` is not a folder.
std::vector<std::filesystem::path> list_frames(const std::filesystem::path& dir);

}  // namespace pfill
