// The figures of a shell of boundary particles (surface_sampling.hpp) as
// JSON and as summary lines: `pfill surface`, `pfill check --shell`, `pfill
// fill --shell` (src/cli/surface_command.cpp).
#pragma once
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "pfill/boundary.hpp"
#include "pfill/mesh.hpp"
#include "pfill/particle_attributes.hpp"
#include "pfill/particles.hpp"
#include "pfill/surface_sampling.hpp"

namespace pfill::cli {

nlohmann::ordered_json shell_json(const ShellStats& stats);
void print_shell(std::FILE* out, const ShellStats& stats);
/// The figures of the shell among `particles`, at its mean radius: those of
/// kind boundary where the file gave kinds (`attributes`, fill --shell),
/// else those whose centre lies within half their radius of the surface.
ShellStats measure_shell_of(const Boundary& boundary, const ParticleSet& particles,
                            const ParticleAttributes* attributes = nullptr);
/// R for about `count` particles in a hexagonal layer on the mesh's surface.
double surface_radius_for_count(const Mesh& mesh, size_t count);
inline std::string fs_stem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

}  // namespace pfill::cli
