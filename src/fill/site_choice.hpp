// Birth sites chosen per process (issue 31): each process chooses the
// sites of its own part of space, and together they are exactly the sites
// of the one-process choice, at any process count.
//
// The choice is spread_birth_sites' (birth_sites.hpp): candidates on a
// lattice at a third of the spacing, at least `min_depth` inside, taken
// deepest first (ties: the lower lattice index), each kept unless a kept
// one lies within the spacing. Here the depths are the mesh's exact
// distances at the candidates (Boundary::fast_signed_distance), so no
// process builds a field, and the sequential rule is computed by sweeps
// that each process makes over its own candidates: a candidate is kept
// once every deeper candidate within the spacing is decided and none of
// them was kept, dropped once one was. Each process also holds the
// candidates of the others within the spacing of its region (its halo),
// and after each sweep the processes tell each other what they decided
// near their borders; the deepest undecided candidate anywhere can always
// be decided, so the sweeps end, and one process needs one sweep. A
// site's key is its lattice index (the same at any process count).
//
// Measured on the OpenCL engine (spot, -n 16000, seeds 1-4): the same
// rule on exact depths packs 0.6181 against the field's 0.6178; sites by
// independent tiles (parallel Poisson-disk sampling) packed 0.6168, and
// their LAMMPS fills 0.6168 against 0.6180 (docs/lammps_engine.md).
#pragma once
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "pfill/birth_sites.hpp"
#include "pfill/boundary.hpp"
#include "pfill/engine/birth_view.hpp"
#include "pfill/engine/particle_engine.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

/// The candidates' lattice over a mesh's box (the same on every process).
struct SiteLattice {
  /// Sites at least `spacing` apart and `min_depth` inside; candidates a
  /// third of the spacing apart from the box's low corner.
  SiteLattice(const Box3& box, double spacing, double min_depth);

  Vec3 origin;
  double spacing = 0, min_depth = 0;
  double step = 0;                   ///< the candidates' spacing
  std::array<int64_t, 3> points{};   ///< lattice points along each axis

  uint64_t index(const std::array<int64_t, 3>& q) const {
    return static_cast<uint64_t>(q[0]) +
           static_cast<uint64_t>(points[0]) * (static_cast<uint64_t>(q[1]) + static_cast<uint64_t>(points[1]) * static_cast<uint64_t>(q[2]));
  }
  Vec3 point(const std::array<int64_t, 3>& q) const {
    return origin + Vec3(static_cast<double>(q[0]), static_cast<double>(q[1]), static_cast<double>(q[2])) * step;
  }
  Vec3 point(uint64_t index) const;
  /// The lattice's extent, within `margin` of regions[region] (regions
  /// empty: one process, the whole extent).
  Box3 extent_near(const std::vector<Box3>& regions, int region, double margin) const;
};

/// A lattice point at least the lattice's min_depth inside, by the mesh's exact depth.
struct DeepPoint {
  double depth;
  uint64_t lattice;  ///< its lattice index
};

/// The lattice's deep points within `box`, asked block by block (a block
/// wholly outside or nowhere deep enough costs one query), in parallel.
std::vector<std::vector<DeepPoint>> deep_points_in(const Boundary& boundary, const SiteLattice& lattice,
                                                   const Box3& box);

struct KeyedSite {
  BirthSite site;
  uint64_t key = 0;  ///< a key base + the site's lattice index
};

/// One process's part of the choice.
class SiteChoice {
 public:
  /// The candidates this process decides (those `regions[region]` owns,
  /// owning_region) and its halo (the others' within the spacing of it).
  /// `regions` empty: one process, every candidate its own.
  SiteChoice(const Boundary& boundary, const SiteLattice& lattice, const std::vector<Box3>& regions, int region);

  /// Decides what it can, deepest first; returns the decisions of this
  /// sweep within the spacing of another region, a word each (lattice
  /// index * 2 + kept), for the others' halos.
  std::vector<uint64_t> sweep();
  /// Takes the other processes' decisions (words of their sweeps; any not
  /// in this halo are ignored).
  void apply(const std::vector<uint64_t>& words);
  /// This process's candidates not yet decided.
  size_t undecided() const { return open_.size(); }
  /// The kept candidates of this process, keyed `key_base` + lattice index, in key order.
  std::vector<KeyedSite> sites(uint64_t key_base) const;
  size_t candidates() const { return cands_.size(); }

 private:
  enum State : uint8_t { kUndecided, kKept, kDropped };
  struct Candidate {
    double depth;
    uint64_t lattice;
    State state;
    bool own, border;  ///< decided here; near another region
    bool waits;        ///< in waiting_
    uint32_t blocker;  ///< while it waits: the deeper undecided candidate it found last
  };
  size_t cell_of(const Vec3& p) const;
  bool near_kept(const Vec3& p) const;
  uint32_t deeper_undecided(const Vec3& p, uint32_t i);

  const SiteLattice& lattice_;
  std::vector<Candidate> cands_;  ///< deepest first (ties: lower lattice index)
  std::unordered_map<uint64_t, uint32_t> halo_;  ///< lattice index -> candidate, for apply
  Vec3 grid_origin_;
  std::array<int64_t, 3> grid_dims_{};
  std::vector<std::vector<Vec3>> kept_;         ///< per cell of the spacing: kept candidates' places
  std::vector<std::vector<uint32_t>> waiting_;  ///< per cell: undecided ones others may wait for (decided ones go lazily)
  std::vector<uint32_t> open_;                  ///< this process's undecided candidates, deepest first
};

/// This process's sites of the choice over `view`'s regions (collective:
/// sweeps until no process has a candidate undecided; one gather a sweep).
std::vector<KeyedSite> choose_sites(const Boundary& boundary, const SiteLattice& lattice, const BirthView& view,
                                    ParticleEngine& engine, uint64_t key_base);

}  // namespace pfill
