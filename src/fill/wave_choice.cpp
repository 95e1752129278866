// A wave's newborns decided per process (wave_choice.hpp).
#include "fill/wave_choice.hpp"

#include <algorithm>

#include "fill/centre_grid.hpp"

namespace pfill {
namespace {

/// How far p lies inside box b from its nearest face.
double depth_in_box(const Box3& b, const Vec3& p) {
  return std::min({p.x - b.lo.x, b.hi.x - p.x, p.y - b.lo.y, b.hi.y - p.y, p.z - b.lo.z, b.hi.z - p.z});
}

/// Whether p, in this process's region, lies within `reach` of another's.
bool near_another_region(const BirthView& view, const Vec3& p, double reach) {
  // (regions tile space: deeper than the reach in its own, near no other)
  if (depth_in_box(view.regions[static_cast<size_t>(view.region)], p) >= reach) return false;
  for (size_t r = 0; r < view.regions.size(); ++r)
    if (static_cast<int>(r) != view.region && distance_to_box(view.regions[r], p) < reach) return true;
  return false;
}

}  // namespace

std::vector<uint64_t> border_site_words(const BirthView& view, const std::vector<OpenSite>& open, double reach) {
  std::vector<uint64_t> words;
  if (view.complete()) return words;
  for (const OpenSite& s : open)
    if (near_another_region(view, s.position, reach)) append_words(s, words);
  return words;
}

std::vector<OpenSite> choose_wave(const std::vector<OpenSite>& open, const std::vector<OpenSite>& rooms,
                                  const std::vector<OpenSite>& told, double clearance) {
  std::vector<OpenSite> chosen = open;
  if (rooms.empty()) return chosen;
  // Every centre a room site must keep clear of: the wave sites, then the room sites taken.
  std::vector<Vec3> taken;
  for (const OpenSite& s : open) taken.push_back(s.position);
  for (const OpenSite& s : told) taken.push_back(s.position);
  CentreGrid grid(clearance);
  for (size_t k = 0; k < taken.size(); ++k) grid.insert(taken[k], static_cast<uint32_t>(k));
  for (const OpenSite& s : rooms) {
    const Vec3& at = s.position;
    if (grid.any_near(at, [&](uint32_t j) { return length(taken[j] - at) < clearance; })) continue;
    grid.insert(at, static_cast<uint32_t>(taken.size()));
    taken.push_back(at);
    chosen.push_back(s);
  }
  return chosen;
}

WaveShare share_wave(ParticleEngine& engine, const BirthView& view, const std::vector<OpenSite>& mine) {
  uint64_t largest = 0;
  for (const OpenSite& s : mine) largest = std::max(largest, s.key);
  std::vector<uint64_t> words{mine.size(), largest};
  if (!view.complete()) engine.gather_over_processes(words);
  return wave_share_of(words, view.region);
}

WaveShare wave_share_of(const std::vector<uint64_t>& words, int region) {
  WaveShare share;
  uint64_t newest_key = 0;
  for (size_t w = 0; w + 2 <= words.size(); w += 2) {
    const size_t count = static_cast<size_t>(words[w]);
    if (static_cast<int>(w / 2) < region) share.first += count;
    if (count > 0 && (share.total == 0 || words[w + 1] > newest_key))
      newest_key = words[w + 1], share.newest = share.total + count - 1;
    share.total += count;
  }
  return share;
}

}  // namespace pfill
