// The ranges of FillOptions, checked before any work (fill_options_check.hpp):
// a NaN, an infinity or 1e300 in any setting ends in a one-line error, never
// an Embree assertion, a raw OpenCL build log or a fill that "ends empty".
#include "fill/fill_options_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "fill/fill_plan.hpp"
#include "fill/short_number.hpp"
#include "pfill/error.hpp"

namespace pfill {
void check_fill_options(const FillOptions& o) {
  // Each test is written so that NaN fails it.
  auto need = [](bool ok, const std::string& what) {
    if (!ok) throw Error(what);
  };
  auto in = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
  need(o.radius >= 0 && std::isfinite(o.radius), "radius must be a positive number");
  need(!(o.radius > 0 && o.count > 0), "give a count or a radius, not both (a count picks the radius)");
  need(o.radius > 0 || o.count > 0 || o.radii, "give a count or a particle radius");
  need(!(o.radii && o.radius > 0),
       "radii with radius: give radii with a count (its radii then relative) or alone (radii in mesh units)");
  need(!o.radii || o.rest_distance == 1, "radii need rest_distance 1 (unequal spheres rest touching)");
  need(o.count <= kMaxParticles, "a count of " + std::to_string(o.count) + " is more than pfill handles (" +
                                      short_number(kMaxParticles) + "); ask for fewer particles");
  need(in(o.max_overlap, 0, 0.999999), "max_overlap must be in [0, 1) (a fraction of r)");
  need(in(o.rest_distance, 1, 10), "rest_distance must be 1..10 (a multiple of the contact distance 2r)");
  need(in(o.epsilon, 1e-6, 1e6), "epsilon must be in [1e-6, 1e6]");
  need(o.exponents[1] >= 1 && o.exponents[0] <= 48 && o.exponents[0] - o.exponents[1] >= 1,
       "exponents must be A,B with 1 <= B, B + 1 <= A <= 48 (default 12,6)");
  need(o.cutoff == 0 || in(o.cutoff, 1.000001, 5), "cutoff must be 0 (purely repulsive) or in (1, 5] sigma");
  need(in(o.restitution, 0, 1), "restitution must be in [0, 1]");
  need(in(o.wall_restitution, 0, 1), "wall_restitution must be in [0, 1]");
  need(o.sites >= -1 && o.sites <= 64, "sites must be -1..64 (-1: automatic; 0: births in waves over sites spread inside)");
  need(in(o.site_depth, 0, 1), "site_depth must be in [0, 1] (a share of the deepest point's depth)");
  need(in(o.site_spacing, 0.5, 1e3), "site_spacing must be in [0.5, 1000] rest distances");
  need(in(o.site_min_depth, 1, 1e3), "site_min_depth must be in [1, 1000] radii");
  need(o.room_spacing == 0 || in(o.room_spacing, 0.5, 1e3), "room_spacing must be 0 (none) or in [0.5, 1000] rest distances");
  need(o.birth_every >= 0 && o.birth_every <= 1000, "birth_every must be 1..1000 (or 0: automatic)");
  need(!o.birth || (std::isfinite(o.birth->x) && std::isfinite(o.birth->y) && std::isfinite(o.birth->z)),
       "birth must be three finite numbers X,Y,Z");
  need(o.birth_speed[0] >= 0 && o.birth_speed[1] >= o.birth_speed[0] && o.birth_speed[1] <= 1 &&
           o.birth_speed[1] >= 0.05,
       "birth_speed must be MIN,MAX with 0 <= MIN <= MAX <= 1 and MAX >= 0.05 (fractions of the top speed; "
       "newborns at rest never spread)");
  // Bounds that keep every pass finite: a site that always has room, a
  // patience of nothing, a vanishing step or speed would make a fill
  // endless or empty.
  need(o.birth_clearance == 0 || in(o.birth_clearance, 0.25, 4),
       "birth_clearance must be 0 (automatic) or in [0.25, 4] rest distances; below 0.25 a site never "
       "fills up and births go on without end");
  need(o.patience == 0 || (o.patience >= std::max(100, 10 * o.birth_every) && o.patience <= 10'000'000),
       "patience must be 0 (automatic) or at least 100 steps and 10 birth intervals (birth_every), at most "
       "10,000,000");
  need(o.stop_share == -1 || (o.stop_share >= 0 && o.stop_share < 1),
       "stop_share must be in [0, 1), or -1 for automatic");
  need(o.max_overfill == -1 || (o.max_overfill >= 0 && o.max_overfill <= 1),
       "max_overfill must be in [0, 1], or -1 for none");
  need(std::isfinite(o.damping) && o.damping >= 0 && o.damping <= 1e6, "damping must be in [0, 1e6]");
  need(o.time_step == 0 || in(o.time_step, 1e-4, 0.05),
       "time_step must be 0 (automatic) or in [0.0001, 0.05] tau (smaller steps never finish)");
  need(o.max_step == 0 || in(o.max_step, 1e-3, 0.5), "max_step must be 0 (automatic) or in [0.001, 0.5] sigma");
  need(o.max_steps == 0 || (o.max_steps >= 100 && o.max_steps <= 1'000'000'000'000ull),
       "max_steps must be 0 (automatic) or 100..1e12 steps");
  need(o.top_up_patience >= 1 && o.top_up_patience <= 10'000'000, "top_up_patience must be 1..10,000,000");
  need(o.rest_steps >= 1 && o.rest_steps <= 10'000'000, "rest_steps must be 1..10,000,000");
  need(o.rest_speed > 0 && o.rest_speed <= 1, "rest_speed must be in (0, 1]");
  need(o.settle_steps >= 1 && o.settle_steps <= 1'000'000'000'000ull, "settle_steps must be 1..1e12 steps");
  need(in(o.containment_tolerance, 0, 1), "containment_tolerance must be in [0, 1] (a fraction of r)");
  need(o.hole_rounds >= 0 && o.hole_rounds <= 100, "hole_rounds must be 0..100");
  need(o.hole_clearance > 0 && o.hole_clearance <= 4, "hole_clearance must be in (0, 4] rest distances");
  need(o.field_spacing > 0 && o.field_spacing <= 2, "field_spacing must be in (0, 2] radii");
  need(o.max_field_samples >= 4096, "max_field_samples must be at least 4096");
  need(in(o.skin, 0, 2), "skin must be in [0, 2] sigma (0: automatic)");
  need(o.sync_every >= 1 && o.sync_every <= 1000, "sync_every must be 1..1000");
  need(o.sort_every >= 0, "sort_every must be >= 0 (0: never)");
  need(!o.on_frame || o.frame_every >= 1, "frame_every must be at least 1 step");
}

void check_fill_options(const FillOptions& o, const Mesh& mesh, double radius) {
  const Box3 box = mesh.bounds();
  const Vec3 size = box.size();
  const double thinnest = std::min({size.x, size.y, size.z});
  // No sphere fits in a box thinner than its diameter (and a radius far
  // past the mesh's size would put the distance field's samples where the
  // ray tracer cannot go).
  if (!(2 * radius <= thinnest))
    throw Error("no particle of radius " + short_number(radius) + " fits: the mesh's box is only " +
                short_number(thinnest) + " across; choose a radius below " + short_number(thinnest / 2));
  if (o.birth) {
    const Vec3& p = *o.birth;
    const bool in_box = p.x >= box.lo.x && p.x <= box.hi.x && p.y >= box.lo.y && p.y <= box.hi.y &&
                        p.z >= box.lo.z && p.z <= box.hi.z;
    if (!in_box)
      throw Error("birth lies outside the mesh's box, so outside the mesh; give a point inside it or leave it out");
  }
  // Damping is a rate in the mesh's time; per step it removes 1 - exp(-damping dt).
  const double a = o.exponents[0], b = o.exponents[1];
  const double sigma = o.rest_distance * 2 * radius / std::pow(a / b, 1 / (a - b));
  // (Automatic: the waves' step, the longer of the two schedules'.)
  const double dt = (o.time_step > 0 ? o.time_step : kWaveTimeStep) * sigma / std::sqrt(o.epsilon);
  if (o.damping * dt > 0.1)
    throw Error("damping " + short_number(o.damping) + " stops every particle within a few steps at this radius; "
                "keep it below " + short_number(0.1 / dt));
}

void check_coordinates_resolve(const Mesh& mesh, double radius) {
  const Box3 box = mesh.bounds();
  if (box.empty() || !(radius > 0)) return;
  const double far = std::max({std::abs(box.lo.x), std::abs(box.lo.y), std::abs(box.lo.z), std::abs(box.hi.x),
                               std::abs(box.hi.y), std::abs(box.hi.z)});
  const double spacing = far * 0x1p-52;  // about the gap between neighbouring doubles there
  if (spacing > 0.01 * radius)
    throw Error("the mesh lies " + short_number(far) + " from the origin, where coordinates are spaced " +
                short_number(spacing) + " apart, " + short_number(100 * spacing / radius) + "% of the radius " +
                short_number(radius) + ": the spheres' positions could not be written as the fill measured them; "
                "move the mesh nearer the origin");
}

}  // namespace pfill
