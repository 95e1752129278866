// The birth sites a process holds (issue 31).
//
// Replicated (one process, and every fill but the split one): every
// process holds every site, each keyed by its index, the room sites after
// the sites. Split (FillOptions::wall_from_mesh, waves of equal spheres:
// the LAMMPS engine): each process chooses and holds only the sites in its
// own sub-domain, keyed by lattice index (site_choice.hpp), and hands those
// a `balance` moved out of it to the process whose sub-domain holds them
// now; no process holds every site, nor a field they were chosen on.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "fill/site_choice.hpp"
#include "pfill/birth_sites.hpp"
#include "pfill/engine/birth_view.hpp"
#include "pfill/engine/particle_engine.hpp"

namespace pfill {

struct HeldSites {
  std::vector<BirthSite> sites;       ///< the waves' sites (or the report's)
  std::vector<BirthSite> room_sites;  ///< waves: extra sites for the first births
  /// Split: each site's key, in the order of `sites` and of `room_sites`
  /// (each sorted by key). Replicated: empty, the key is the index.
  std::vector<uint64_t> keys, room_keys;
  bool split = false;
  uint64_t total_sites = 0, total_room_sites = 0;  ///< over every process
  std::vector<Box3> regions;  ///< split: the sub-domains the sites were last placed by

  uint64_t key(size_t k) const { return split ? keys[k] : k; }
  uint64_t room_key(size_t k) const { return split ? room_keys[k] : sites.size() + k; }
  /// Keys from here on are the room sites'.
  uint64_t room_base() const;
};

/// Every site on every process.
HeldSites replicated_sites(std::vector<BirthSite> sites, std::vector<BirthSite> room_sites);

/// Split sites: the room sites' keys start here, past every lattice index of the waves' sites.
constexpr uint64_t kRoomKeyBase = uint64_t(1) << 62;

/// This process's sites of `view`'s region (collective): the waves' sites
/// on `waves`, the room sites on `rooms` (none when it is empty), each by
/// choose_sites; the totals over the processes.
HeldSites split_sites(const Boundary& boundary, const SiteLattice& waves, const std::optional<SiteLattice>& rooms,
                      ParticleEngine& engine, const BirthView& view);

/// Split, when the sub-domains of `view` differ from those the sites were
/// placed by: the sites now outside this process's region go to the
/// processes that own them (collective; one gather of the leavers).
void hand_over_sites(HeldSites& held, ParticleEngine& engine, const BirthView& view);

/// Split: `given` in place of the deepest of every process's sites (ties:
/// the lower key; the field's way puts a given first site in place of the
/// deepest), keeping its key, held by the process `view` says decides it
/// (collective).
void put_given_site(HeldSites& held, const BirthSite& given, ParticleEngine& engine, const BirthView& view);

/// Every process's sites (not the room sites), in key order, on every
/// process (collective: split sites are gathered); for the report's list.
/// Replicated: `held.sites`.
std::vector<BirthSite> all_sites(const HeldSites& held, ParticleEngine& engine);

}  // namespace pfill
