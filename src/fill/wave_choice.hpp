// Which of a wave's open sites take a newborn, each process deciding its
// own (issue 31). A wave of equal spheres births at every open wave site
// (they lie several rest distances apart: their newborns never crowd each
// other), and while the fill is sparse also at each open room site clear
// of the wave's other newborns. Room sites spaced wider than that
// clearance never crowd each other either, so a room site depends only on
// the open wave sites within the clearance: each process decides its own
// room sites once the others have told it their open wave sites near its
// border. What travels is those border sites and two words a process,
// where every open site went to every process before (4 words a birth).
//
// Ids and places then follow the processes' order (as the finish's do),
// each process's newborns in key order; one process: key order, as before.
// Pass 2's cap counts births in key order over every process and keeps the
// gather (FillPasses::wave_sites).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fill/site_verdicts.hpp"
#include "pfill/engine/birth_view.hpp"
#include "pfill/engine/particle_engine.hpp"

namespace pfill {

/// The sites of `open` (this process's open wave sites) within `reach` of
/// another process's region, as words (key, x, y, z) for
/// gather_over_processes (site_verdicts.hpp's append_words; read back
/// with sites_of_words): what the others' room sites must keep clear of.
/// None on a complete view.
std::vector<uint64_t> border_site_words(const BirthView& view, const std::vector<OpenSite>& open, double reach);

/// A wave's newborns on this process, in their order: its open wave sites
/// (`open`, key order), then each of its open room sites (`rooms`, key
/// order) that lies `clearance` or more from every open wave site (its own
/// and the others' near its border, `told`) and from the room sites taken
/// before it.
std::vector<OpenSite> choose_wave(const std::vector<OpenSite>& open, const std::vector<OpenSite>& rooms,
                                  const std::vector<OpenSite>& told, double clearance);

/// A wave's newborns over the processes: this process's first place in the
/// wave, the wave's total, and the place of its newest newborn (the one
/// with the largest key: the last of one process's wave, so a removal of
/// "the newest" removes the same sphere at any process count).
struct WaveShare {
  size_t first = 0, total = 0, newest = 0;
};
/// From `mine` (this process's newborns, choose_wave's order): one gather
/// of two words a process (collective; nothing on a complete view).
WaveShare share_wave(ParticleEngine& engine, const BirthView& view, const std::vector<OpenSite>& mine);
/// The share of the process at `region` from every process's words
/// (count, largest key), in rank order.
WaveShare wave_share_of(const std::vector<uint64_t>& words, int region);

}  // namespace pfill
