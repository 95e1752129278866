// A wave of unequal spheres (FillPasses, fill_passes.hpp), decided where
// each site's room can be seen (issue 31). Each newborn takes the size
// class furthest below its share whose radius fits (SizeDeficit), and
// the wave's newborns must keep clear of each other: so the sites are
// walked in order, each birth changing the next site's choice. What needs
// the particles is only whether each class's radius has room at a site:
// each class draws its radius from a stream of its own (site, class), so
// the process that decides a site answers that for every class at once,
// and every process walks the open sites' answers (a few words a site
// with room, never the particles) to the same newborns. Each builds only
// those at its own sites.
#include <algorithm>

#include "fill/counter_rng.hpp"
#include "fill/fill_passes.hpp"

namespace pfill {

/// The wave: the same walk on every process, each handing over the
/// newborns at the sites it decides (ids in the walk's order).
int FillPasses::birth_wave_of_sizes() {
  const bool capped = reporter_.phase() == FillPhase::Pass2;
  std::vector<SiteFits> open = size_fits();
  share_site_fits(engine_, view_, sizes_->classes(), open);
  struct Born {
    Vec3 position;
    double radius;
  };
  std::vector<Born> wave;
  std::vector<Particle> mine;
  std::vector<size_t> places;
  for (const SiteFits& f : open) {
    if (capped && engine_.size() + wave.size() >= result_.max_parts) break;
    const Vec3& at = f.position;
    for (size_t c : sizes_->candidates()) {
      if (!f.fits(c)) continue;
      const double r = class_radius(f.key, c);
      // The wave's large newborns may reach each other across the sites' spacing.
      if (std::any_of(wave.begin(), wave.end(), [&](const Born& b) {
            return length(b.position - at) < plan_.birth_clearance * (r + b.radius);
          }))
        continue;
      sizes_->add(r);
      if (view_.decides(at)) {
        mine.push_back(newborn(at, r, f.key, next_id_ + wave.size()));
        places.push_back(wave.size());
      }
      wave.push_back({at, r});
      break;
    }
  }
  if (wave.empty()) return 0;
  next_id_ += wave.size();
  newest_ = engine_.add_decided_particles(mine, places, wave.size()) + wave.size() - 1;
  return static_cast<int>(wave.size());
}

/// The sites this process decides where some class's radius has room in
/// the snapshot, with the classes that do (in site order).
std::vector<SiteFits> FillPasses::size_fits() const {
  const RoomGrid room(snapshot_, snapshot_radii_, plan_.birth_clearance, plan_.max_radius);
  const size_t classes = sizes_->classes();
  std::vector<SiteFits> open;
  for (size_t k = 0; k < held_.sites.size(); ++k) {
    const Vec3& at = held_.sites[k].position;
    if (!view_.decides(at) || room.pocket_full(held_.sites[k], plan_.mean_radius)) continue;
    SiteFits f{held_.key(k), at, std::vector<uint64_t>((classes + 63) / 64, 0)};
    bool any = false;
    for (size_t c = 0; c < classes; ++c)
      if (room.has_room(at, class_radius(f.key, c))) f.bits[c / 64] |= uint64_t{1} << (c % 64), any = true;
    if (any) open.push_back(std::move(f));
  }
  return open;
}

/// The radius class c draws at `site` in this wave: from the stream of
/// (seed, step, site, 2 + c), the same on whichever process asks (one
/// uniform: no generator to seed for each class of each site).
double FillPasses::class_radius(uint64_t site, size_t c) const {
  return sizes_->draw_at(c, CounterRng(o_.seed, engine_.steps_done(), site, 2 + c).uniform());
}

/// The size classes' counts over every process: each counts its own
/// particles of the view (the first `own`), then the sums (one process:
/// the whole view).
void FillPasses::count_sizes() {
  if (view_.complete()) return sizes_->recount(snapshot_radii_);
  sizes_->recount(snapshot_radii_, view_.own, *engine_.process_group());
}

}  // namespace pfill
