// Which spheres the finish deletes (see finish.cpp): after a stalled
// relaxation the most pressed, and when the rounds run out one of each
// pair still over the bound. Decided on a FinishView: each process picks
// among its own spheres only, from pressures summed over every pair in
// view (the halo holds every partner of a halo sphere that touches an own
// one), ties going by the view's keys, so that processes that see the
// same pair decide it alike.
#pragma once
#include <cstddef>
#include <vector>

#include "fill/finish_view.hpp"
#include "fill/size_deficit.hpp"
#include "pfill/packing_metrics.hpp"

namespace pfill {

struct RemovalRule {
  double max_overlap = 0.001;  ///< the bound, fraction of the smaller radius
  double jam_share = 0.1;      ///< the most pressed of this share of the jams lose a sphere each
  double share = 0.5;          ///< of the estimated excess, this share goes
  double radius = 0;           ///< the smallest radius (unequal spheres' excess)
  /// Unequal spheres: the classes' counts over every process (the caller
  /// counts them: SizeDeficit::recount), which a deletion keeps to; null: equal
  /// spheres. (Split over processes, each sees only its own deletions:
  /// picks_the_classes_allow then holds every process's picks together.)
  SizeDeficit* sizes = nullptr;
  double mean_cube = 0;        ///< unequal: the distribution's mean r^3
};

/// After a stalled relaxation: the spheres pressed hardest, about `share`
/// of the excess the overlaps imply, one in each of the most pressed
/// `jam_share` of the jams, never two that touch. View indices, own only.
std::vector<size_t> most_compressed(const FinishView& view, const std::vector<Overlap>& overlaps,
                                    const RemovalRule& rule);

/// Unequal spheres split over processes: of every process's `picked`
/// (most_compressed's, each process's within the classes' shares on its
/// own), those the classes' shares allow together. Every process walks
/// all the picks alike, most pressed first (ties by key), a class losing
/// a sphere only while `sizes` (every process's counts, before this
/// round's deletions) may lose one; without it P processes could each
/// take a class's whole allowance. Returns this process's kept, in
/// `picked`'s order. Collective.
std::vector<size_t> picks_the_classes_allow(ParticleEngine& engine, const FinishView& view,
                                            const std::vector<Overlap>& overlaps, const std::vector<size_t>& picked,
                                            SizeDeficit& sizes);

/// Out of rounds: the more pressed sphere of every pair over the bound.
/// One process: in the pairs' order, skipping a pair one of whose spheres
/// already goes; per sub-domain every such pair's more pressed sphere
/// (a skip would depend on pairs the other process cannot see). View
/// indices, own only.
std::vector<size_t> one_of_each_over(const FinishView& view, const std::vector<Overlap>& overlaps,
                                     double max_overlap);

}  // namespace pfill
