// The finish's deletions (finish_removals.hpp).
#include "fill/finish_removals.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "fill/word_bits.hpp"

namespace pfill {
namespace {

/// Each sphere's overlapping partners, one run each: partners[first[i]] up
/// to partners[first[i + 1]] (a vector a sphere cost ~70 MiB at 1e6).
struct OverlapPartners {
  OverlapPartners(size_t n, const std::vector<Overlap>& overlaps) : first(n + 1, 0), partners(2 * overlaps.size()) {
    for (const Overlap& o : overlaps) ++first[o.i + 1], ++first[o.j + 1];
    for (size_t i = 0; i < n; ++i) first[i + 1] += first[i];
    std::vector<size_t> next(first.begin(), first.end() - 1);
    for (const Overlap& o : overlaps) partners[next[o.i]++] = o.j, partners[next[o.j]++] = o.i;
  }
  std::vector<size_t> first;
  std::vector<uint32_t> partners;
};

/// Every sphere's summed overlaps.
std::vector<double> pressures(size_t n, const std::vector<Overlap>& overlaps) {
  std::vector<double> pressed(n, 0);
  for (const Overlap& o : overlaps) {
    pressed[o.i] += o.fraction;
    pressed[o.j] += o.fraction;
  }
  return pressed;
}

}  // namespace

std::vector<size_t> most_compressed(const FinishView& view, const std::vector<Overlap>& overlaps,
                                    const RemovalRule& rule) {
  const ParticleSet& now = view.set;
  const size_t n = now.size();
  std::vector<double> need(n, 0);
  const std::vector<double> pressed = pressures(n, overlaps);
  const OverlapPartners touching(n, overlaps);
  for (const Overlap& o : overlaps) {
    const double excess = 0.5 * std::max(0.0, o.fraction - rule.max_overlap);
    need[o.i] = std::max(need[o.i], excess);
    need[o.j] = std::max(need[o.j], excess);
  }
  // Unequal spheres: the volume a sphere must give up, r_i^2 r_min need_i
  // (need_i a share of the smallest radius), counted in spheres of the
  // distribution's mean volume, as the deletions keep to it (counted in
  // smallest spheres, as for equal ones, 1:2 half-half deleted 4.5 times
  // too many small and twice too many large).
  SizeDeficit* sizes = rule.sizes;
  double excess = 0;
  std::vector<size_t> candidates;
  for (size_t i = 0; i < view.own; ++i)
    if (need[i] > 0) {
      excess += sizes ? 3 * need[i] * now.radii[i] * now.radii[i] * rule.radius / rule.mean_cube : 3 * need[i];
      candidates.push_back(i);
    }
  const std::vector<uint64_t>& key = view.keys;
  std::sort(candidates.begin(), candidates.end(), [&](size_t a, size_t b) {
    return pressed[a] > pressed[b] || (pressed[a] == pressed[b] && key[a] < key[b]);
  });
  // Jams (clusters of pairs over the bound) that the relaxation could not
  // undo lose their most pressed sphere, a share of them a round, so that
  // the rounds do not grow with the number of jams (that is, with N).
  std::vector<uint32_t> root(n);
  for (size_t i = 0; i < n; ++i) root[i] = static_cast<uint32_t>(i);
  auto find = [&](uint32_t i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  for (const Overlap& o : overlaps)
    if (o.fraction > rule.max_overlap) root[find(o.i)] = find(o.j);
  std::vector<bool> blocked(n, false), jam_done(n, false), chosen(n, false);
  std::vector<size_t> out;
  // Unequal spheres: a class goes only while it keeps its share (the
  // large are the most pressed: deleting by pressure alone thinned them,
  // 1:2 half-half ended 60:40). (The counts are every process's, from the
  // caller; each process lowers them by its own deletions only.)
  auto may_go = [&](size_t i) { return !sizes || sizes->may_lose(sizes->class_of(now.radii[i])); };
  auto take = [&](size_t i) {
    if (sizes) sizes->remove(now.radii[i]);
    out.push_back(i);
    chosen[i] = true;
    jam_done[find(static_cast<uint32_t>(i))] = true;
    for (size_t k = touching.first[i]; k < touching.first[i + 1]; ++k) blocked[touching.partners[k]] = true;
  };
  // Only the most pressed jams, `jam_share` of them: removing a few
  // spheres relieves the pressure far around (the bunny: 14 removed
  // cleared 1,349 pairs over the bound), and one from every jam emptied
  // holes the packing could not fill again (0.584 against 0.592).
  std::vector<bool> counted(n, false);
  size_t jams = 0;
  for (size_t i : candidates) {
    const uint32_t r = find(static_cast<uint32_t>(i));
    if (!counted[r]) counted[r] = true, ++jams;
  }
  const size_t most = static_cast<size_t>(std::ceil(rule.jam_share * static_cast<double>(jams)));
  for (size_t i : candidates) {
    if (out.size() >= most) break;
    if (!jam_done[find(static_cast<uint32_t>(i))] && !blocked[i] && may_go(i)) take(i);
  }
  const size_t want = static_cast<size_t>(std::ceil(rule.share * excess));
  for (size_t i : candidates) {
    if (out.size() >= want) break;
    if (!blocked[i] && !chosen[i] && may_go(i)) take(i);
  }
  return out;
}

std::vector<size_t> picks_the_classes_allow(ParticleEngine& engine, const FinishView& view,
                                            const std::vector<Overlap>& overlaps, const std::vector<size_t>& picked,
                                            SizeDeficit& sizes) {
  const std::vector<double> pressed = pressures(view.set.size(), overlaps);
  std::vector<uint64_t> words;  // a pick: its pressure, key, class, process and place in `picked`
  for (size_t j = 0; j < picked.size(); ++j) {
    const size_t i = picked[j];
    words.insert(words.end(), {bits_of(pressed[i]), view.keys[i], sizes.class_of(view.set.radii[i]),
                               static_cast<uint64_t>(view.region), j});
  }
  engine.gather_over_processes(words);
  std::vector<size_t> order(words.size() / 5);
  for (size_t k = 0; k < order.size(); ++k) order[k] = 5 * k;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const double pa = double_of(words[a]), pb = double_of(words[b]);
    return pa > pb || (pa == pb && words[a + 1] < words[b + 1]);
  });
  std::vector<bool> kept(picked.size(), false);
  for (size_t w : order) {
    const size_t k = static_cast<size_t>(words[w + 2]);
    if (!sizes.may_lose(k)) continue;
    sizes.remove_from(k);
    if (static_cast<int>(words[w + 3]) == view.region) kept[static_cast<size_t>(words[w + 4])] = true;
  }
  std::vector<size_t> out;
  for (size_t j = 0; j < picked.size(); ++j)
    if (kept[j]) out.push_back(picked[j]);
  return out;
}

std::vector<size_t> one_of_each_over(const FinishView& view, const std::vector<Overlap>& overlaps,
                                     double max_overlap) {
  const std::vector<double> pressed = pressures(view.set.size(), overlaps);
  std::vector<bool> gone(view.set.size(), false);
  std::vector<size_t> out;
  for (const Overlap& o : overlaps) {
    if (o.fraction <= max_overlap) continue;
    if (view.complete()) {
      if (gone[o.i] || gone[o.j]) continue;
      const size_t k = pressed[o.i] >= pressed[o.j] ? o.i : o.j;
      gone[k] = true;
      out.push_back(k);
      continue;
    }
    const bool i_goes =
        pressed[o.i] > pressed[o.j] || (pressed[o.i] == pressed[o.j] && view.keys[o.i] < view.keys[o.j]);
    const size_t k = i_goes ? o.i : o.j;
    if (view.is_own(k) && !gone[k]) gone[k] = true, out.push_back(k);
  }
  return out;
}

}  // namespace pfill
