// An engine's hold (ParticleEngine::hold) on the OpenCL engine: the
// particles taking part, moving or held, renumbered first and stepped
// alone; the rest kept past them, untouched; the held ones given a mass
// the steps cannot move. The finish relaxes its last jams this way in
// place of a second engine for their region (one engine's cell grid and
// 1e6 spheres' upload a round: 26 rounds at 1e6).
#pragma once
#include <CL/opencl.hpp>

#include <cstddef>
#include <functional>
#include <vector>

#include "pfill/engine/particle_engine.hpp"

namespace pfill {

struct EngineState;

/// What a hold keeps aside (EngineState::hold).
struct HoldState {
  bool active = false;
  size_t out = 0;                      ///< particles past EngineState::n, taking no part in the steps
  std::vector<cl_float> inverse_mass;  ///< each stepping particle's own, by its current index
};

/// The held ones' inverse mass: a mass of 1e30, as the finish's region engines
/// give them (FIRE's kick moves them by nothing in float).
constexpr cl_float kHeldInverseMass = 1e-30f;

/// Renumbers the particles whose part_of(position) is moving or held first
/// (each part in its order), the rest after them; the held ones come to
/// rest with kHeldInverseMass. Then steps move only those first ones, the
/// lists rebuilt at the next step. Returns how many take part.
size_t hold_particles(EngineState& s, const std::function<ParticleEngine::StepPart(const Vec3&)>& part_of);

/// Every particle steps again, each with its own mass (nothing without a hold).
void release_particles(EngineState& s);

}  // namespace pfill
