// Everything an engine holds, in parts with one job each; the step forms
// (step_kernels.hpp) act on it and Engine (engine.cpp) is the facade.
#pragma once
#include <CL/opencl.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/cell_grid.hpp"
#include "engine/device_array.hpp"
#include "engine/device_field.hpp"
#include "engine/engine_hold.hpp"
#include "engine/neighbour_lists.hpp"
#include "engine/particle_arrays.hpp"
#include "engine/step_history.hpp"
#include "pfill/device/program.hpp"
#include "pfill/engine/params.hpp"

namespace pfill {

struct EngineState {
  EngineState(Device& device, const EngineParams& params);

  /// Enqueues `kernel` over `items` work-items (with a profiling device,
  /// keeping its event for kernel_times).
  void run(Kernel& kernel, size_t items);

  Device& device;
  DeviceChoices choices;      // the automatic settings made for the device
  EngineParams params;        // as given, with the skin made the chosen one
  EngineConstants constants;  // derived from `params`
  size_t n = 0;               // particles (while a hold is on: those taking part; hold.out more follow them)
  cl_uint level_mask = 0;     // the cell levels a particle added so far fell in (a bit each; kernels skip others)
  uint64_t steps = 0;         // steps enqueued
  ParticleArrays particles;
  NeighbourLists lists;       // the lists, their request words, the births linked in
  CellGrid cells;             // the grid the lists are built from
  DeviceField wall;           // the distance field the wall kernels sample
  HoldState hold;             // ParticleEngine::hold
  DeviceArray<cl_float8> fire;  // the FIRE state (params.fire), one for each of two steps in turn (common.cl)
  std::unique_ptr<StepHistory> records;  // made with the form's finalize_history kernel
  std::vector<std::pair<std::string, cl::Event>> events;
};

}  // namespace pfill
