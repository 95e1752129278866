/// @file step_record.hpp
/// @brief The scalars the engine records for every step (the device-side
/// history the fill's stopping tests read in batches).
#pragma once
#include <cstdint>

namespace pfill {

struct StepRecord {
  uint64_t step = 0;               ///< index of the step since the engine was made
  double kinetic_energy = 0;       ///< sum of m u^2 / 2 over particles, half-step velocities after the step
  double max_speed = 0;            ///< largest |u| after the step
  double max_displacement = 0;     ///< largest distance a centre moved in the step (wall push included)
  uint32_t colliding_pairs = 0;    ///< pairs whose spheres overlap (d < r_i + r_j) at the step's start
  uint32_t flagged = 0;            ///< particles whose centre was outside the field (or its box) this step
  uint32_t cell_overflow = 0;      ///< particles that met a full cell or neighbour list (neighbours lost: should be 0)
  uint32_t particles = 0;          ///< particle count during the step
  bool lists_rebuilt = false;      ///< the step rebuilt the neighbour lists (cost: cell fill + list build; not recorded under FIRE)
  double power = 0;                ///< FIRE (EngineParams::fire): sum of F.v over particles at the step's start, the minimiser's test
};

}  // namespace pfill
