// The birth sites a process holds (held_sites.hpp).
#include "fill/held_sites.hpp"

#include <algorithm>
#include <numeric>

#include "fill/pick_over_processes.hpp"
#include "fill/word_bits.hpp"

namespace pfill {
namespace {

// A site in words for gather_over_processes: key, x, y, z, depth.
constexpr size_t kWords = 5;

void pack(uint64_t key, const BirthSite& s, std::vector<uint64_t>& out) {
  out.insert(out.end(), {key, bits_of(s.position.x), bits_of(s.position.y), bits_of(s.position.z), bits_of(s.depth)});
}

BirthSite unpack(const uint64_t* w) {
  return {Vec3(double_of(w[1]), double_of(w[2]), double_of(w[3])), double_of(w[4])};
}

// Sorts `sites` and `keys` together by key.
void sort_by_key(std::vector<BirthSite>& sites, std::vector<uint64_t>& keys) {
  std::vector<size_t> order(keys.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return keys[a] < keys[b]; });
  std::vector<BirthSite> s(sites.size());
  std::vector<uint64_t> k(keys.size());
  for (size_t i = 0; i < order.size(); ++i) {
    s[i] = sites[order[i]];
    k[i] = keys[order[i]];
  }
  sites = std::move(s);
  keys = std::move(k);
}

bool same_regions(const std::vector<Box3>& a, const std::vector<Box3>& b) {
  if (a.size() != b.size()) return false;
  for (size_t r = 0; r < a.size(); ++r)
    for (int d = 0; d < 3; ++d)
      if (a[r].lo[d] != b[r].lo[d] || a[r].hi[d] != b[r].hi[d]) return false;
  return true;
}

}  // namespace

HeldSites replicated_sites(std::vector<BirthSite> sites, std::vector<BirthSite> room_sites) {
  HeldSites h;
  h.total_sites = sites.size();
  h.total_room_sites = room_sites.size();
  h.sites = std::move(sites);
  h.room_sites = std::move(room_sites);
  return h;
}

uint64_t HeldSites::room_base() const { return split ? kRoomKeyBase : sites.size(); }

HeldSites split_sites(const Boundary& boundary, const SiteLattice& waves, const std::optional<SiteLattice>& rooms,
                      ParticleEngine& engine, const BirthView& view) {
  HeldSites h;
  h.split = true;
  h.regions = view.regions;
  auto keep = [&](const std::vector<KeyedSite>& chosen, std::vector<BirthSite>& sites, std::vector<uint64_t>& keys) {
    for (const KeyedSite& k : chosen) {
      sites.push_back(k.site);
      keys.push_back(k.key);
    }
  };
  keep(choose_sites(boundary, waves, view, engine, 0), h.sites, h.keys);
  if (rooms) keep(choose_sites(boundary, *rooms, view, engine, kRoomKeyBase), h.room_sites, h.room_keys);
  std::vector<uint64_t> counts{h.sites.size(), h.room_sites.size()};
  engine.gather_over_processes(counts);
  for (size_t p = 0; p + 1 < counts.size(); p += 2) {
    h.total_sites += counts[p];
    h.total_room_sites += counts[p + 1];
  }
  return h;
}

void hand_over_sites(HeldSites& held, ParticleEngine& engine, const BirthView& view) {
  if (!held.split || view.complete() || same_regions(view.regions, held.regions)) return;
  std::vector<uint64_t> leavers;
  auto take_leavers = [&](std::vector<BirthSite>& sites, std::vector<uint64_t>& keys) {
    size_t kept = 0;
    for (size_t k = 0; k < sites.size(); ++k) {
      if (!view.decides(sites[k].position)) {
        pack(keys[k], sites[k], leavers);
        continue;
      }
      sites[kept] = sites[k];
      keys[kept++] = keys[k];
    }
    sites.resize(kept);
    keys.resize(kept);
  };
  take_leavers(held.sites, held.keys);
  take_leavers(held.room_sites, held.room_keys);
  engine.gather_over_processes(leavers);  // (each process's leavers, every process)
  bool rooms = false, waves = false;
  for (size_t w = 0; w + kWords <= leavers.size(); w += kWords) {
    const BirthSite s = unpack(&leavers[w]);
    if (!view.decides(s.position)) continue;
    const bool room = leavers[w] >= kRoomKeyBase;
    (room ? held.room_sites : held.sites).push_back(s);
    (room ? held.room_keys : held.keys).push_back(leavers[w]);
    (room ? rooms : waves) = true;
  }
  if (waves) sort_by_key(held.sites, held.keys);
  if (rooms) sort_by_key(held.room_sites, held.room_keys);
  held.regions = view.regions;
}

void put_given_site(HeldSites& held, const BirthSite& given, ParticleEngine& engine, const BirthView& view) {
  Pick deepest;  // (by the depth in `gap`'s place, the key as the order)
  for (size_t k = 0; k < held.sites.size(); ++k) {
    const Pick p{held.sites[k].position, held.sites[k].depth, held.sites[k].depth, held.keys[k], 1};
    if (beats(p, deepest, true)) deepest = p;
  }
  deepest = best_over(*engine.process_group(), deepest, true);
  if (!deepest.found) return;
  const auto held_at = std::lower_bound(held.keys.begin(), held.keys.end(), deepest.order);
  if (held_at != held.keys.end() && *held_at == deepest.order) {
    held.sites.erase(held.sites.begin() + (held_at - held.keys.begin()));
    held.keys.erase(held_at);
  }
  if (!view.decides(given.position)) return;
  const auto to = std::lower_bound(held.keys.begin(), held.keys.end(), deepest.order);
  held.sites.insert(held.sites.begin() + (to - held.keys.begin()), given);
  held.keys.insert(to, deepest.order);
}

std::vector<BirthSite> all_sites(const HeldSites& held, ParticleEngine& engine) {
  if (!held.split) return held.sites;
  std::vector<uint64_t> words;
  for (size_t k = 0; k < held.sites.size(); ++k) pack(held.keys[k], held.sites[k], words);
  engine.gather_over_processes(words);
  std::vector<BirthSite> sites;
  std::vector<uint64_t> keys;
  for (size_t w = 0; w + kWords <= words.size(); w += kWords) {
    sites.push_back(unpack(&words[w]));
    keys.push_back(words[w]);
  }
  sort_by_key(sites, keys);
  return sites;
}

}  // namespace pfill
