// Which birth sites have room, decided where the room test can see it
// (issue 31): each process tests only the sites its BirthView decides
// (one process: all of them), then the verdicts are summed over the
// processes, so every process holds every site's verdict and chooses the
// same newborns, in the sites' order, with the same ids (a wave of equal
// spheres: each process builds only those at its own sites). What depends on
// other newborns (the pass-2 cap, room sites near this wave's newborns,
// newborns in flight) is then applied on every process alike.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fill/word_bits.hpp"
#include "pfill/birth_sites.hpp"
#include "pfill/engine/particle_engine.hpp"

namespace pfill {

/// verdicts[first + k] = 1 where this process decides sites[k] and
/// `has_room(site)`; the other entries stay as they are.
template <class HasRoom>
void mark_sites_with_room(const BirthView& view, const std::vector<BirthSite>& sites, const HasRoom& has_room,
                          std::vector<int>& verdicts, size_t first = 0) {
  for (size_t k = 0; k < sites.size(); ++k)
    if (view.decides(sites[k].position) && has_room(sites[k])) verdicts[first + k] = 1;
}

/// Every process's verdicts on every process (each site has one deciding
/// process). Only the sites with room travel (an MPI_Allgatherv of their
/// indices on the LAMMPS engine at P > 1): a wave's births, not one int
/// for each of the sites (1.7e8 room sites at 1e9 spheres). Nothing on one
/// process.
inline void share_verdicts(ParticleEngine& engine, const BirthView& view, std::vector<int>& verdicts) {
  if (view.complete()) return;
  std::vector<uint64_t> with_room;
  for (size_t k = 0; k < verdicts.size(); ++k)
    if (verdicts[k]) with_room.push_back(k);
  engine.gather_over_processes(with_room);
  for (uint64_t k : with_room) verdicts[k] = 1;
}

/// A site with room in a wave: its key (held_sites.hpp) and place.
struct OpenSite {
  uint64_t key;
  Vec3 position;
};

/// A site as 4 words for gather_over_processes (key, x, y, z), appended
/// to `words`; and the sites such words carry.
inline void append_words(const OpenSite& s, std::vector<uint64_t>& words) {
  words.insert(words.end(), {s.key, bits_of(s.position.x), bits_of(s.position.y), bits_of(s.position.z)});
}
inline std::vector<OpenSite> sites_of_words(const std::vector<uint64_t>& words) {
  std::vector<OpenSite> sites;
  sites.reserve(words.size() / 4);
  for (size_t w = 0; w + 4 <= words.size(); w += 4)
    sites.push_back({words[w], Vec3(double_of(words[w + 1]), double_of(words[w + 2]), double_of(words[w + 3]))});
  return sites;
}

/// Appends to `open` the sites of `sites` this process decides that
/// `has_room(site)`, each with key `key_of(k)`.
template <class KeyOf, class HasRoom>
void add_open_sites(const BirthView& view, const std::vector<BirthSite>& sites, const KeyOf& key_of,
                    const HasRoom& has_room, std::vector<OpenSite>& open) {
  for (size_t k = 0; k < sites.size(); ++k)
    if (view.decides(sites[k].position) && has_room(sites[k])) open.push_back({key_of(k), sites[k].position});
}

/// Every process's open sites on every process, in key order (an
/// MPI_Allgatherv of 4 words a site with room on the LAMMPS engine at
/// P > 1: a wave's births, never the sites without room). One process:
/// unchanged (already in key order).
inline void share_open_sites(ParticleEngine& engine, const BirthView& view, std::vector<OpenSite>& open) {
  if (view.complete()) return;
  std::vector<uint64_t> words;
  words.reserve(4 * open.size());
  for (const OpenSite& s : open) append_words(s, words);
  engine.gather_over_processes(words);
  open = sites_of_words(words);
  std::sort(open.begin(), open.end(), [](const OpenSite& a, const OpenSite& b) { return a.key < b.key; });
}

/// Unequal spheres' wave: a site with room for some size class, by its
/// key (held_sites.hpp) and place, with a bit for each class whose radius
/// (drawn from the site's stream of that class) has room there.
struct SiteFits {
  uint64_t key = 0;
  Vec3 position;
  std::vector<uint64_t> bits;
  bool fits(size_t c) const { return (bits[c / 64] >> (c % 64)) & 1u; }
};

/// Every process's SiteFits on every process, in key order (an
/// MPI_Allgatherv of 4 + classes / 64 words an open site on the LAMMPS
/// engine at P > 1). One process: unchanged.
inline void share_site_fits(ParticleEngine& engine, const BirthView& view, size_t classes,
                            std::vector<SiteFits>& fits) {
  if (view.complete()) return;
  const size_t width = 4 + (classes + 63) / 64;
  std::vector<uint64_t> words;
  words.reserve(width * fits.size());
  for (const SiteFits& f : fits) {
    append_words({f.key, f.position}, words);
    words.insert(words.end(), f.bits.begin(), f.bits.end());
  }
  engine.gather_over_processes(words);
  fits.clear();
  for (size_t w = 0; w + width <= words.size(); w += width) {
    const uint64_t* f = &words[w];
    fits.push_back({f[0], Vec3(double_of(f[1]), double_of(f[2]), double_of(f[3])),
                    std::vector<uint64_t>(f + 4, f + width)});
  }
  std::sort(fits.begin(), fits.end(), [](const SiteFits& a, const SiteFits& b) { return a.key < b.key; });
}

}  // namespace pfill
