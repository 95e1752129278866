// What the finish's rounds decide on in this process (issue 31,
// docs/lammps_engine.md "The finish per sub-domain"): the engine's
// LocalView at the spheres' true radii. One process: every sphere, all its
// own. LAMMPS at P > 1: the rank's own spheres and a halo two contact
// distances deep, so that every pair with an own sphere, and every
// partner of a halo sphere in such a pair, is in view: each rank counts,
// presses and deletes its own spheres, and finds the holes in its own
// sub-domain, without a gather of the whole set. What the ranks must
// agree on (the counts that steer the rounds, the deletions' indices, the
// holes' ids, holes on either side of a border) goes through the engine's
// collectives here.
#pragma once
#include <cstdint>
#include <vector>

#include "pfill/engine/local_view.hpp"
#include "pfill/engine/particle_engine.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/particles.hpp"

namespace pfill {

/// The engine's LocalView (own count, indices, keys, regions), its
/// particles moved into `set` at their true radii (`particles` stays empty).
struct FinishView : LocalView {
  ParticleSet set;  ///< own first, then the halo, at their true radii

  /// Whether this process counts the pair: of its two spheres, the one of
  /// the lower key is its own (so that every pair counts once over all).
  bool counts(const Overlap& o) const {
    if (is_own(o.i) && is_own(o.j)) return true;
    const uint32_t lower = keys[o.i] < keys[o.j] ? o.i : o.j;
    return is_own(lower);
  }
  /// This process's sub-domain (complete: nothing, search everywhere).
  const Box3* mine() const { return complete() ? nullptr : &regions[static_cast<size_t>(region)]; }
};

/// The engine's particles at their true radii: the engine's are smaller by
/// `shrink` (equal spheres: all of `radius`, exactly).
ParticleSet at_true_radii(const std::vector<Particle>& ps, double radius, double shrink, bool unequal);

/// The engine's view within `reach` as a FinishView: the engine's spheres
/// are smaller than the true by `shrink` (equal spheres: all of `radius`).
/// Unequal spheres: `reach` must cover two contact distances of the largest.
FinishView finish_view(ParticleEngine& engine, double reach, double radius, double shrink, bool unequal);

/// `n` summed over the processes (one process: n).
size_t total_over_processes(ParticleEngine& engine, const FinishView& view, size_t n);

/// The engine's indices of the own spheres `picked` (view indices), from
/// every process, the same list on every process.
std::vector<size_t> picked_everywhere(ParticleEngine& engine, const FinishView& view,
                                      const std::vector<size_t>& picked);

/// Every process's `mine`, one after another in process order, on every process.
std::vector<Vec3> places_everywhere(ParticleEngine& engine, std::vector<Vec3> mine);

/// Holes this process decides (in its sub-domain), less those within
/// `clearance` of a hole a lower process decided across a border (each
/// process finds holes `clearance` apart in its own sub-domain only).
/// `gaps` (may be empty) follow the holes kept.
std::vector<Vec3> holes_decided_here(ParticleEngine& engine, const FinishView& view, std::vector<Vec3> holes,
                                     std::vector<double>& gaps, double clearance);

/// A process's share of a set split over the processes (issue 31): its
/// members are the set's places [first, first + its count) of `total`, in
/// process order (ParticleEngine::add_decided_particles). No total: one
/// process holds the whole set.
struct SetShare {
  size_t first = 0, total = 0;
};

/// This process's share of a set of which it holds `mine` at `region`
/// (its place among the processes), from every process's count (one
/// gather of a word a process; collective). One process: the whole set.
SetShare share_over_processes(ParticleEngine& engine, size_t mine, int region, bool complete);

/// Ids for a batch of which this process gives `mine`: consecutive from
/// `next` over the processes in order, set in `mine`; `next` moves past
/// the whole batch. Returns this process's places in the batch.
SetShare batch_ids(ParticleEngine& engine, const FinishView& view, std::vector<Particle>& mine, uint64_t& next);

/// The places [share.first, share.first + n).
std::vector<size_t> places_of(const SetShare& share, size_t n);


}  // namespace pfill
