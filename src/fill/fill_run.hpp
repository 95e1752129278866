// The fill run (fill.cpp), its steps in the order of the algorithm: the
// plan, the field and the birth sites (fill_sites.cpp), the engine's
// passes (fill_passes.cpp), the finish (finish.cpp) and the check
// (fill_verify.cpp). One FillRun a call of pfill::fill.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fill/fill_plan.hpp"
#include "fill/fill_progress.hpp"
#include "fill/finish.hpp"
#include "fill/held_sites.hpp"
#include "fill/large_first.hpp"
#include "pfill/boundary.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/particle_engine.hpp"
#include "pfill/exact_field.hpp"
#include "pfill/fill.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/particle_share.hpp"
#include "pfill/sdf.hpp"

namespace pfill {

class FillRun {
 public:
  /// `diagnostics`: diagnose(mesh), which the caller has already needed.
  FillRun(const Mesh& mesh, const MeshDiagnostics& diagnostics, const FillOptions& options)
      : mesh_(mesh), diagnostics_(diagnostics), o_(options), reporter_(options.progress) {}

  FillResult run();

 private:
  // The fractions asked won over the count: what the fill did, and what came of it.
  std::string held_to_large_note(const std::string& short_front) const;

  // With a profiling device (PFILL_PROFILE=1): the device's time since the
  // last call goes to the pass just ended (the first call only starts the
  // count, past the field upload and the program builds).
  void note_device_times();

  // ---- plan, field, sites, engine ----
  void prepare();

  // The engine of the plan, given the wall or the field.
  void make_engine();

  // With the wall from the mesh (the LAMMPS engine) no process builds the
  // field: each chooses the waves' sites of its own sub-domain from the
  // mesh's exact distances (site_choice.hpp), or the report's few sites
  // from candidates it holds (mesh_sites.hpp); a given first site in
  // place of the deepest; a site for each of the mesh's closed parts that
  // has none (part_sites.hpp).
  bool sites_from_mesh() const;

  // The fill's own field beside the engine's wall from the mesh: twice as coarse.
  SdfOptions coarse_options() const;

  // This process's sites (collective). An object too thin for any takes
  // the field's way after all: its one deepest point, or the error that no
  // sphere fits.
  void choose_split_sites(const SdfOptions& coarse);

  // The waves' sites (and room sites) of this process's sub-domain; false when none anywhere.
  bool split_wave_sites();

  // The report's few sites (on every process) from candidates each holds.
  bool report_sites_from_mesh();

  // The birth sites on the field (and the room sites of waves).
  void plan_sites();

  // Sites from the mesh: the sites (every process's, in part order) for
  // the mesh's closed parts that none of `sites` lies in, each its deepest
  // of `candidates` (collective).
  std::vector<KeyedSite> sites_for_parts(const std::vector<BirthSite>& sites, const HeldCandidates& candidates);

  // The parts' counts in the result, and the warning of those too small (once).
  void note_parts(const PartSites& parts);

  // Unequal spheres sized by a count whose rare large ones do not all fit
  // at the count rule's radii: every radius shrinks until they do (large_first_scale.hpp),
  // the plan and sites again at that scale, on the field already built
  // (its spacing a little coarser against the new radii, which the final
  // exact check makes good; its band and margin reach past the largest).
  void rescale_for_large_first();

  // The same with the sites from the mesh: the large spheres' candidates
  // held per process, reaching as shallow as the smallest scale tried
  // needs (the scale search and the placement share them).
  void rescale_split();

  // The plan at `scale` on the field already built; the sites again, and
  // the engine (its radius was the old plan's) where it was built.
  void replan_at(double scale);

  // This process's candidates for spheres of `smallest` radius and up:
  // the coarse field's lattice with the mesh's depths, in its sub-domain.
  HeldCandidates held_candidates(double smallest, const LargeFirstSettings& s);

  // The rare large spheres' placement: on the field, or (sites from the
  // mesh, no field) on the candidates each process holds, made at the
  // first placement when the scale search did not make them.
  LargePlacer large_placer();
  // ---- finish: overlaps resolved by moving spheres; holes filled (finish.cpp) ----
  void finish(uint64_t next_id);

  FinishSettings finish_settings() const;

  // ---- verify: exact containment, holes, metrics (fill_verify.cpp) ----
  void verify();

  /// The caller's cancel hook (FillOptions::cancelled).
  void throw_if_cancelled() const;

  Mesh mesh_;
  MeshDiagnostics diagnostics_;
  FillOptions o_;
  FillReporter reporter_;
  FillPlan plan_;
  std::unique_ptr<Boundary> boundary_;
  ScalarGrid field_;
  std::unique_ptr<ExactField> wall_;  ///< FillOptions::wall_from_mesh: the engines' wall (field_ is then coarser)
  std::vector<BirthSite> sites_;
  HeldSites held_;  ///< the sites this process holds, for FillPasses (sites_ and the waves' room sites, or split)
  std::optional<HeldCandidates> candidates_;  ///< split sites: the large spheres' candidates, until placed
  std::unique_ptr<Device> device_;
  EngineParams params_;
  std::unique_ptr<ParticleEngine> engine_;
  ParticleSet particles_;  ///< after the finish: this process's own spheres (one process: all)
  ParticleShare share_;     ///< where the other processes' lie (one process: nowhere)
  uint64_t next_id_ = 1;
  uint64_t relax_steps_ = 0;  ///< the finish's steps
  uint64_t fill_steps_ = 0;   ///< engine steps of passes 1 to the settle, kept once the engine is gone
  DeviceTimes device_times_;  ///< the device's times at the last note_device_times()
  bool device_times_noted_ = false;
  FillResult result_;
  std::vector<size_t> size_caps_;  ///< each size class's most spheres, where the largest fell short (FillPasses::size_caps)
};

}  // namespace pfill
