// Unequal spheres: which size the next sphere should have, so that what
// ends in the mesh follows the requested distribution. Large spheres find
// room less often as the fill grows; drawing at random would leave them
// short. Instead each size class keeps a count of the spheres present, and
// a birth (or a hole of the finish) takes the class furthest below its
// share, trying smaller ones where the large do not fit, within a small
// surplus: the distribution holds at every moment of the fill.
#pragma once
#include <cstddef>
#include <random>
#include <vector>

#include "pfill/engine/process_group.hpp"
#include "pfill/radius_distribution.hpp"

namespace pfill {

class SizeDeficit {
 public:
  /// `sizes` in mesh units.
  explicit SizeDeficit(const RadiusDistribution& sizes);

  /// Classes so rare that the whole fill expects at most `first_wave`
  /// spheres of them (out of `expected`), and larger than the commonest
  /// class, are born first, largest first, until their share of `expected`
  /// is in: a large sphere finds room only while the mesh is still empty
  /// (a 1:10 mix by volume expects one large sphere in a thousand, and its
  /// deficit by number would lead only after a thousand births).
  void front_load(double expected, double first_wave);
  /// The radii of front_load's quota still to come, largest first (drawn
  /// inside each class), for placing them before any birth.
  std::vector<double> front_radii(std::mt19937_64& rng) const;
  /// The quota is done with: what was placed stands, and the deficit rules
  /// take it from there (a class that got fewer is not tried first again).
  void end_front_load() { first_quota_.clear(); }
  /// When a front-loaded class got fewer than its quota, or `always` (the
  /// radii were shrunk below the count rule's) (`placed`: the radii of
  /// those placed): the count each class may reach so that every share (by
  /// number, or by volume for a distribution given by volume) stays the one
  /// asked relative to what was placed; empty when nothing fell short or
  /// none was placed. Call before end_front_load.
  std::vector<size_t> caps_held_to_front(const std::vector<double>& placed, bool always = false) const;
  /// Holds each class k to at most caps[k] spheres (empty: no caps): the
  /// classes at their cap are no candidates.
  void set_caps(std::vector<size_t> caps) { cap_ = std::move(caps); }
  bool capped() const { return !cap_.empty(); }
  const std::vector<size_t>& caps() const { return cap_; }
  /// Whether every class is at its cap (no sphere may follow).
  bool all_capped() const;

  /// Counts the spheres present (their radii) afresh.
  void recount(const std::vector<double>& radii) { count_first(radii, radii.size()); }
  /// The same where the spheres are split over `group`'s processes: this
  /// process's are the first `own` of `radii` (a halo may follow), and the
  /// counts are every process's summed. Collective.
  void recount(const std::vector<double>& radii, size_t own, ProcessGroup& group);
  /// Each class's count, and setting them all (the sums of every process's
  /// own counts, when the spheres are split over processes).
  const std::vector<size_t>& counts() const { return count_; }
  void set_counts(const std::vector<size_t>& counts);
  void add(double radius) { ++count_[class_of(radius)], ++total_; }
  void remove(double radius) { remove_from(class_of(radius)); }
  void remove_from(size_t k);  ///< one sphere less in class k

  /// The classes a new sphere may take, furthest below their share first
  /// (ties: the larger): those whose count stays within the allowed surplus
  /// (a class may run ahead by `surplus_share` of the spheres, at least one).
  std::vector<size_t> candidates(double surplus_share = 0.002) const;
  /// Whether a sphere of class k may go without leaving its class short
  /// of its share by more than the surplus a class may run ahead by (at
  /// least one sphere; a rare class, expected fewer than 16 times and at
  /// most 2% by number, loses none below its share). A continuous law's
  /// bin may go further below while the bins' KS distance stays within the
  /// tolerance of take_tolerated: the finish then deletes the spheres
  /// pressed hardest, whatever their bin.
  bool may_lose(size_t k, double surplus_share = 0) const;
  /// A sphere for a hole with `room` (the largest radius it takes): of the
  /// first of candidates() whose smallest radius fits, drawn inside the
  /// class and capped at the room; counted in (add). 0 when none fits.
  /// A continuous law (16 bins of equal number share) first takes the
  /// largest bin that fits and keeps the bins' Kolmogorov-Smirnov distance
  /// within a tolerance (take_tolerated), then the deficit rule.
  double take_within(double room, std::mt19937_64& rng);
  /// A radius of class k, drawn by the law inside the class.
  double draw(size_t k, std::mt19937_64& rng) const;
  /// The radius of class k at the quantile u in [0, 1) of the law inside the class.
  double draw_at(size_t k, double u) const;
  size_t class_of(double radius) const;
  size_t classes() const { return classes_.size(); }

 private:
  /// The bins' cumulative count against the law's, at its largest gap, with
  /// `change` (+1 or -1) spheres in bin k.
  double binned_ks_with(size_t k, int change) const;
  double take_tolerated(double room, std::mt19937_64& rng);
  void count_first(const std::vector<double>& radii, size_t n);  ///< the counts of radii[0, n) alone
  /// A law whose bins may drift within the KS tolerance (discrete classes
  /// are held to their shares by number or volume: those are the contract).
  bool continuous() const {
    return sizes_.law() != RadiusDistribution::Law::Discrete && sizes_.law() != RadiusDistribution::Law::Equal;
  }

  RadiusDistribution sizes_;
  std::vector<SizeClass> classes_;
  std::vector<size_t> count_;
  std::vector<size_t> first_quota_;  ///< per class: spheres born ahead of the others (front_load)
  std::vector<size_t> cap_;          ///< per class: most spheres (set_caps); empty: none
  size_t total_ = 0;
};

}  // namespace pfill
