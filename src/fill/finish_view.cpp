// The finish's view per process and what the processes agree on (finish_view.hpp).
#include "fill/finish_view.hpp"
#include "fill/particle_set_of.hpp"
#include "fill/word_bits.hpp"

#include <algorithm>
#include <utility>

namespace pfill {

ParticleSet at_true_radii(const std::vector<Particle>& ps, double radius, double shrink, bool unequal) {
  ParticleSet set = to_particle_set(ps);
  if (!unequal) {
    set.radii.assign(ps.size(), radius);  // exact: the engine's floats would round it
  } else {
    for (double& r : set.radii) r += shrink;
  }
  return set;
}

FinishView finish_view(ParticleEngine& engine, double reach, double radius, double shrink, bool unequal) {
  FinishView v;
  static_cast<LocalView&>(v) = engine.local_view(reach);
  v.set = at_true_radii(v.particles, radius, shrink, unequal);
  v.particles = std::vector<Particle>();  // (memory: held once, in `set`)
  return v;
}

size_t total_over_processes(ParticleEngine& engine, const FinishView& view, size_t n) {
  if (view.complete()) return n;
  std::vector<uint64_t> counts{n};
  engine.gather_over_processes(counts);
  size_t total = 0;
  for (uint64_t c : counts) total += static_cast<size_t>(c);
  return total;
}

std::vector<size_t> picked_everywhere(ParticleEngine& engine, const FinishView& view,
                                      const std::vector<size_t>& picked) {
  std::vector<uint64_t> mine;
  mine.reserve(picked.size());
  for (size_t k : picked) mine.push_back(view.indices[k]);
  if (!view.complete()) engine.gather_over_processes(mine);
  return std::vector<size_t>(mine.begin(), mine.end());
}

std::vector<Vec3> places_everywhere(ParticleEngine& engine, std::vector<Vec3> mine) {
  std::vector<uint64_t> words;
  words.reserve(3 * mine.size());
  for (const Vec3& p : mine) words.insert(words.end(), {bits_of(p.x), bits_of(p.y), bits_of(p.z)});
  engine.gather_over_processes(words);
  mine.clear();
  for (size_t w = 0; w + 3 <= words.size(); w += 3)
    mine.emplace_back(double_of(words[w]), double_of(words[w + 1]), double_of(words[w + 2]));
  return mine;
}

namespace {

/// Whether p lies within `d` of another process's sub-domain.
bool near_border(const FinishView& view, const Vec3& p, double d) {
  for (size_t r = 0; r < view.regions.size(); ++r)
    if (static_cast<int>(r) != view.region && distance_to_box(view.regions[r], p) < d) return true;
  return false;
}

}  // namespace

std::vector<Vec3> holes_decided_here(ParticleEngine& engine, const FinishView& view, std::vector<Vec3> holes,
                                     std::vector<double>& gaps, double clearance) {
  std::vector<Vec3> kept;
  std::vector<double> kept_gaps;
  for (size_t k = 0; k < holes.size(); ++k)
    if (view.decides(holes[k])) {
      kept.push_back(holes[k]);
      if (!gaps.empty()) kept_gaps.push_back(gaps[k]);
    }
  if (!gaps.empty()) gaps = std::move(kept_gaps);
  if (view.complete()) return kept;
  // Holes near a border, with their process, to every process: a lower
  // process's hole wins (a rule every process applies alike).
  std::vector<uint64_t> border;
  for (const Vec3& h : kept)
    if (near_border(view, h, clearance))
      border.insert(border.end(), {static_cast<uint64_t>(view.region), bits_of(h.x), bits_of(h.y), bits_of(h.z)});
  engine.gather_over_processes(border);
  std::vector<Vec3> lower;  // the lower processes' border holes
  for (size_t k = 0; k + 3 < border.size(); k += 4)
    if (static_cast<int>(border[k]) < view.region)
      lower.push_back({double_of(border[k + 1]), double_of(border[k + 2]), double_of(border[k + 3])});
  std::vector<Vec3> out;
  std::vector<double> out_gaps;
  for (size_t k = 0; k < kept.size(); ++k) {
    bool taken = false;
    for (const Vec3& h : lower) taken = taken || length(h - kept[k]) < clearance;
    if (taken) continue;
    out.push_back(kept[k]);
    if (!gaps.empty()) out_gaps.push_back(gaps[k]);
  }
  if (!gaps.empty()) gaps = std::move(out_gaps);
  return out;
}

SetShare share_over_processes(ParticleEngine& engine, size_t mine, int region, bool complete) {
  std::vector<uint64_t> counts{mine};
  if (!complete) engine.gather_over_processes(counts);
  SetShare share;
  for (size_t r = 0; r < counts.size(); ++r) {
    if (static_cast<int>(r) < region) share.first += counts[r];
    share.total += counts[r];
  }
  return share;
}

SetShare batch_ids(ParticleEngine& engine, const FinishView& view, std::vector<Particle>& mine, uint64_t& next) {
  const SetShare share = share_over_processes(engine, mine.size(), view.region, view.complete());
  for (size_t k = 0; k < mine.size(); ++k) mine[k].id = next + share.first + k;
  next += share.total;
  return share;
}

std::vector<size_t> places_of(const SetShare& share, size_t n) {
  std::vector<size_t> places(n);
  for (size_t k = 0; k < n; ++k) places[k] = share.first + k;
  return places;
}

}  // namespace pfill
