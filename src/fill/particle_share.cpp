// A packing held in parts over processes (particle_share.hpp): halos and
// the gather, as rows of 8-byte words through the ProcessGroup.
#include "pfill/particle_share.hpp"

#include "fill/word_bits.hpp"
#include "pfill/engine/birth_view.hpp"

namespace pfill {
namespace {

/// A row's words: centre, radius, id (its bits), then what the set has.
struct RowLayout {
  bool velocities = false, colours = false;
  size_t extra = 0;
  size_t width() const { return 5 + (velocities ? 3 : 0) + (colours ? 1 : 0) + extra; }
};

void append_row(const ParticleSet& s, size_t i, const RowLayout& l, std::vector<double>& out) {
  const Vec3& p = s.positions[i];
  out.insert(out.end(), {p.x, p.y, p.z, s.radii[i], double_of(s.id(i))});
  if (l.velocities) out.insert(out.end(), {s.velocities[i].x, s.velocities[i].y, s.velocities[i].z});
  if (l.colours) out.push_back(double_of(uint64_t{s.colours[i][0]} | uint64_t{s.colours[i][1]} << 8 | uint64_t{s.colours[i][2]} << 16));
}

/// The rows back as spheres (their extra words, if any, into `extra`).
ParticleSet from_rows(const std::vector<double>& rows, const RowLayout& l, std::vector<double>* extra) {
  ParticleSet s;
  const size_t w = l.width(), n = rows.size() / w;
  for (size_t k = 0; k < n; ++k) {
    const double* r = &rows[k * w];
    s.positions.push_back({r[0], r[1], r[2]});
    s.radii.push_back(r[3]);
    s.ids.push_back(bits_of(r[4]));
    size_t at = 5;
    if (l.velocities) s.velocities.push_back({r[at], r[at + 1], r[at + 2]}), at += 3;
    if (l.colours) {
      const uint64_t c = bits_of(r[at++]);
      s.colours.push_back({static_cast<uint8_t>(c), static_cast<uint8_t>(c >> 8), static_cast<uint8_t>(c >> 16)});
    }
    if (extra) extra->insert(extra->end(), r + at, r + at + l.extra);
  }
  return s;
}

Bytes bytes_of(const std::vector<double>& words) {
  Bytes b;
  to_bytes(words, b);
  return b;
}

}  // namespace

bool ParticleShare::owns(const Vec3& p) const { return complete() || owning_region(regions, p) == region; }

ParticleSet halo_of(const ParticleShare& share, const ParticleSet& own, double reach,
                    const std::vector<double>& own_extra, size_t width, std::vector<double>* extra) {
  if (share.complete()) return {};
  RowLayout l;
  l.extra = width;
  std::vector<Bytes> to(share.regions.size());
  for (size_t p = 0; p < share.regions.size(); ++p) {
    if (static_cast<int>(p) == share.region) continue;
    std::vector<double> rows;
    for (size_t i = 0; i < own.size(); ++i)
      if (distance_to_box(share.regions[p], own.positions[i]) <= reach) {
        append_row(own, i, l, rows);
        rows.insert(rows.end(), own_extra.begin() + static_cast<long>(i * width),
                    own_extra.begin() + static_cast<long>((i + 1) * width));
      }
    to[p] = bytes_of(rows);
  }
  return from_rows(from_bytes<double>(share.group->exchange(to)), l, extra);
}

ParticleSet own_and_halo(const ParticleSet& own, const ParticleSet& halo) {
  ParticleSet view;
  view.positions = own.positions;
  view.radii = own.radii;
  view.positions.insert(view.positions.end(), halo.positions.begin(), halo.positions.end());
  view.radii.insert(view.radii.end(), halo.radii.begin(), halo.radii.end());
  view.ids.resize(own.size());
  for (size_t i = 0; i < own.size(); ++i) view.ids[i] = own.id(i);
  view.ids.insert(view.ids.end(), halo.ids.begin(), halo.ids.end());
  return view;
}

ParticleSet gather_particles(ProcessGroup& group, const ParticleSet& own, bool everywhere) {
  if (group.alone()) return own;
  // Every process writes the same columns, though one may hold no sphere.
  std::vector<double> has{own.has_velocities() ? 1.0 : 0.0, own.has_colours() ? 1.0 : 0.0};
  group.max(has);
  RowLayout l;
  l.velocities = has[0] > 0;
  l.colours = has[1] > 0;
  std::vector<double> rows;
  for (size_t i = 0; i < own.size(); ++i) append_row(own, i, l, rows);
  const Bytes mine = bytes_of(rows);
  return in_id_order(
      from_rows(from_bytes<double>(everywhere ? group.all_gather(mine) : group.gather_to_first(mine)), l, nullptr));
}

}  // namespace pfill
