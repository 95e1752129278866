// Size classes kept at their shares (size_deficit.hpp).
#include "fill/size_deficit.hpp"

#include <algorithm>
#include <cmath>

namespace pfill {
namespace {

// Classes a continuous law is drawn by: fine enough that a class's own
// spread matters little, few enough that each holds many spheres.
constexpr int kBins = 16;
// A class expected fewer times than this, and at most this share by
// number, is rare: it loses no sphere below its share (one large sphere of
// four is an eighth of a 1:10 mix's volume). A law's bins, a sixteenth of
// the number each, are not rare even in a small fill.
constexpr double kRareClass = 16, kRareShare = 0.02;
// A continuous law's hole takes the largest bin that fits while the bins'
// KS distance stays within this: the largest sphere that fits a hole packs
// denser than the one furthest below its share (spot, lognormal 0.2, 16,000:
// 0.6233 -> 0.6248 at seed 1, KS 0.007 -> 0.021; draws inside a bin add to
// the bins' distance, and issue 29 asks for a KS distance below 0.03).
// Deletions likewise (may_lose): the five seeds' mean 0.6234 -> 0.6247.
constexpr double kKsTolerance = 0.015;

}  // namespace

SizeDeficit::SizeDeficit(const RadiusDistribution& sizes)
    : sizes_(sizes), classes_(sizes.size_classes(kBins)), count_(classes_.size(), 0) {}

void SizeDeficit::front_load(double expected, double first_wave) {
  first_quota_.assign(classes_.size(), 0);
  size_t commonest = 0;
  for (size_t k = 0; k < classes_.size(); ++k)
    if (classes_[k].number_share > classes_[commonest].number_share) commonest = k;
  for (size_t k = commonest + 1; k < classes_.size(); ++k) {
    const double quota = classes_[k].number_share * expected;
    if (quota <= first_wave) first_quota_[k] = static_cast<size_t>(std::ceil(quota - 1e-6));  // (a whole count, fill_scale_for_count)
  }
}

std::vector<double> SizeDeficit::front_radii(std::mt19937_64& rng) const {
  std::vector<double> out;
  for (size_t k = first_quota_.size(); k-- > 0;)
    for (size_t n = count_[k]; n < first_quota_[k]; ++n) out.push_back(draw(k, rng));
  std::stable_sort(out.begin(), out.end(), [](double a, double b) { return a > b; });
  return out;
}

std::vector<size_t> SizeDeficit::caps_held_to_front(const std::vector<double>& placed, bool always) const {
  // The whole fill the placed front classes stand for: the least of each
  // one's placed count over its number share (or placed volume over its
  // volume share, in spheres of the mean volume).
  const bool by_volume = sizes_.basis() == FractionBasis::Volume;
  std::vector<double> cubes(classes_.size(), 0);
  for (double r : placed) cubes[class_of(r)] += r * r * r;
  double total = -1;
  bool short_of_quota = always;
  for (size_t k = 0; k < first_quota_.size(); ++k) {
    if (first_quota_[k] == 0) continue;
    short_of_quota = short_of_quota || count_[k] < first_quota_[k];
    const double stands = by_volume ? cubes[k] / (classes_[k].volume_share * sizes_.mean_cube())
                                    : static_cast<double>(count_[k]) / classes_[k].number_share;
    total = total < 0 ? stands : std::min(total, stands);
  }
  if (!short_of_quota || !(total > 0)) return {};
  std::vector<size_t> caps(classes_.size());
  for (size_t k = 0; k < classes_.size(); ++k)
    caps[k] = k < first_quota_.size() && first_quota_[k] > 0
                  ? count_[k]  // no more of a front class: none found room
                  : static_cast<size_t>(std::llround(classes_[k].number_share * total));
  return caps;
}

bool SizeDeficit::all_capped() const {
  if (cap_.empty()) return false;
  for (size_t k = 0; k < classes_.size(); ++k)
    if (count_[k] < cap_[k]) return false;
  return true;
}

void SizeDeficit::count_first(const std::vector<double>& radii, size_t n) {
  std::fill(count_.begin(), count_.end(), 0);
  for (size_t i = 0; i < n; ++i) ++count_[class_of(radii[i])];
  total_ = n;
}

void SizeDeficit::recount(const std::vector<double>& radii, size_t own, ProcessGroup& group) {
  count_first(radii, own);
  if (group.alone()) return;
  std::vector<double> counts(count_.begin(), count_.end());
  group.sum(counts);
  set_counts(std::vector<size_t>(counts.begin(), counts.end()));
}

void SizeDeficit::set_counts(const std::vector<size_t>& counts) {
  if (counts.size() != count_.size()) return;
  count_ = counts;
  total_ = 0;
  for (size_t c : counts) total_ += c;
}

void SizeDeficit::remove_from(size_t k) {
  size_t& c = count_[k];
  if (c > 0) --c, --total_;
}

std::vector<size_t> SizeDeficit::candidates(double surplus_share) const {
  const double next = static_cast<double>(total_ + 1);
  const double surplus = std::max(1.0, surplus_share * next);
  std::vector<std::pair<double, size_t>> by_deficit;
  for (size_t k = 0; k < classes_.size(); ++k) {
    const double deficit = classes_[k].number_share * next - static_cast<double>(count_[k]);
    if (!cap_.empty() && count_[k] >= cap_[k]) continue;  // held to its share of the front classes
    if (deficit > -surplus) by_deficit.push_back({deficit, k});
  }
  std::sort(by_deficit.begin(), by_deficit.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second > b.second);
  });
  std::vector<size_t> out;
  for (size_t k = first_quota_.size(); k-- > 0;)
    if (count_[k] < first_quota_[k]) out.push_back(k);
  for (const auto& d : by_deficit)
    if (std::find(out.begin(), out.end(), d.second) == out.end()) out.push_back(d.second);
  return out;
}

bool SizeDeficit::may_lose(size_t k, double surplus_share) const {
  if (total_ == 0 || count_[k] == 0) return false;
  const double left = static_cast<double>(total_ - 1);
  const double share = classes_[k].number_share * left;
  const bool rare = share < kRareClass && classes_[k].number_share <= kRareShare;
  const double allowed = rare ? 0 : std::max(1.0, surplus_share * left);
  if (static_cast<double>(count_[k] - 1) - share > -allowed) return true;
  return continuous() && !rare && binned_ks_with(k, -1) <= kKsTolerance;  // as holes, take_tolerated
}

double SizeDeficit::take_within(double room, std::mt19937_64& rng) {
  if (const double r = take_tolerated(room, rng); r > 0) return r;
  for (size_t k : candidates()) {
    if (classes_[k].lo > room) continue;
    const double r = std::max(std::min(draw(k, rng), room), classes_[k].lo);
    add(r);
    return r;
  }
  return 0;
}

double SizeDeficit::take_tolerated(double room, std::mt19937_64& rng) {
  if (!continuous()) return 0;
  for (size_t k = classes_.size(); k-- > 0;) {
    if (classes_[k].lo > room || (!cap_.empty() && count_[k] >= cap_[k])) continue;
    if (binned_ks_with(k, +1) > kKsTolerance) continue;
    const double r = std::max(std::min(draw(k, rng), room), classes_[k].lo);
    add(r);
    return r;
  }
  return 0;
}

double SizeDeficit::binned_ks_with(size_t k, int change) const {
  const double n = static_cast<double>(total_) + change;
  double counted = 0, requested = 0, worst = 0;
  for (size_t m = 0; m < classes_.size(); ++m) {
    counted += static_cast<double>(count_[m]) + (m == k ? change : 0);
    requested += classes_[m].number_share;
    worst = std::max(worst, std::abs(counted / n - requested));
  }
  return worst;
}

double SizeDeficit::draw(size_t k, std::mt19937_64& rng) const {
  return draw_at(k, std::uniform_real_distribution<double>(0, 1)(rng));
}

double SizeDeficit::draw_at(size_t k, double u) const { return sizes_.draw_in_class(classes_, k, u); }

size_t SizeDeficit::class_of(double radius) const {
  // Classes ascend: the first whose top reaches the radius, or the one below
  // when the radius (read back as a float) lies nearer its top.
  const auto above = std::lower_bound(classes_.begin(), classes_.end(), radius,
                                      [](const SizeClass& c, double r) { return c.hi < r; });
  if (above == classes_.end()) return classes_.size() - 1;
  const size_t k = static_cast<size_t>(above - classes_.begin());
  if (k > 0 && radius < above->lo && radius - classes_[k - 1].hi < above->lo - radius) return k - 1;
  return k;
}

}  // namespace pfill
