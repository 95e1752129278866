// The ranges of FillOptions, checked before any work (issue 33: a NaN, an
// infinity or 1e300 in any setting must end in a one-line error, never an
// Embree assertion, a raw OpenCL build log or a fill that "ends empty").
#include "fill/fill_options_check.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>

#include "pfill/error.hpp"

namespace pfill {
namespace {

constexpr double kMaxParticles = 100'000'000;

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

void need(bool ok, const std::string& what) {
  if (!ok) throw Error(what);
}

bool finite(double v) { return std::isfinite(v); }

}  // namespace

void check_fill_options(const FillOptions& o) {
  need(finite(o.radius) && o.radius >= 0, "radius must be a positive number");
  need(o.radius > 0 || o.count > 0, "give a particle radius (-r) or a count (-n)");
  need(static_cast<double>(o.count) <= kMaxParticles,
       "count " + std::to_string(o.count) + " is more than pfill handles (" + fmt(kMaxParticles) +
           "); ask for fewer particles");
  need(o.rest_distance >= 1 && o.rest_distance <= 10,
       "rest_distance must be 1..10 (a multiple of the contact distance 2r)");
  need(finite(o.epsilon) && o.epsilon >= 1e-6 && o.epsilon <= 1e6, "epsilon must be in [1e-6, 1e6]");
  need(finite(o.exponent_a) && finite(o.exponent_b) && o.exponent_b >= 1 && o.exponent_a <= 48 &&
           o.exponent_a - o.exponent_b >= 1,
       "exponents must be A,B with 1 <= B, B + 1 <= A <= 48 (default 12,6)");
  need(o.cutoff == 0 || (o.cutoff > 1 && o.cutoff <= 5), "cutoff must be 0 (purely repulsive) or in (1, 5] sigma");
  need(o.restitution >= 0 && o.restitution <= 1, "restitution must be in [0, 1]");
  need(o.wall_restitution >= 0 && o.wall_restitution <= 1, "wall_restitution must be in [0, 1]");
  need(finite(o.damping) && o.damping >= 0, "damping must be a number >= 0");
  need(o.time_step >= 1e-4 && o.time_step <= 0.05,
       "time_step must be in [0.0001, 0.05] tau (smaller steps never finish)");
  need(o.max_step_fraction >= 1e-3 && o.max_step_fraction <= 0.5, "max_step_fraction must be in [0.001, 0.5] sigma");
  need(o.sites >= -1 && o.sites <= 64,
       "sites must be -1..64 (-1: automatic; 0: births in waves over sites spread inside)");
  need(o.site_depth_share >= 0 && o.site_depth_share <= 1,
       "site_depth_share must be in [0, 1] (a share of the deepest point's depth)");
  need(o.birth_every >= 0 && o.birth_every <= 1000, "birth_every must be 1..1000 (or 0: automatic)");
  need(o.site_spacing >= 0.5 && o.site_spacing <= 1000, "site_spacing must be in [0.5, 1000] rest distances");
  need(o.site_min_depth >= 1 && o.site_min_depth <= 1000, "site_min_depth must be in [1, 1000] radii");
  if (o.birth_point) {
    const Vec3& p = *o.birth_point;
    need(finite(p.x) && finite(p.y) && finite(p.z), "birth_point must be three finite numbers x, y, z");
  }
  need(o.birth_speed_min >= 0 && o.birth_speed_max >= o.birth_speed_min && o.birth_speed_max <= 1 &&
           o.birth_speed_max >= 0.05,
       "birth_speed must be MIN,MAX with 0 <= MIN <= MAX <= 1 and MAX >= 0.05 (fractions of the top speed; "
       "newborns at rest never spread)");
  need(o.birth_clearance == 0 || (o.birth_clearance >= 0.25 && o.birth_clearance <= 4),
       "birth_clearance must be 0 (automatic) or in [0.25, 4] rest distances; below 0.25 a site never "
       "fills up and births go on without end");
  need(o.birth_stop_share == -1 || (o.birth_stop_share >= 0 && o.birth_stop_share < 1),
       "birth_stop_share must be in [0, 1), or -1 for automatic");
  need(o.blocked.patience >= std::max(100, 10 * o.birth_every) && o.blocked.patience <= 10'000'000,
       "patience must be at least 100 steps and 10 birth intervals (birth_every), at most 10,000,000 "
       "(default 1500)");
  need(o.max_steps == 0 || (o.max_steps >= 100 && o.max_steps <= 1'000'000'000'000ull),
       "max_steps must be 0 (automatic) or 100..1e12 steps");
  need(o.top_up_patience >= 1 && o.top_up_patience <= 10'000'000, "top_up_patience must be 1..10,000,000");
  need(o.rest_steps >= 1 && o.rest_steps <= 10'000'000, "rest_steps must be 1..10,000,000");
  need(o.rest_speed > 0 && o.rest_speed <= 1, "rest_speed must be in (0, 1]");
  need(o.settle_budget >= 1 && o.settle_budget <= 1'000'000'000'000ull, "settle_budget must be 1..1e12 steps");
  need(o.max_overlap >= 0 && o.max_overlap < 1, "max_overlap must be in [0, 1) (a fraction of r)");
  need(o.containment_tolerance >= 0 && o.containment_tolerance <= 1,
       "containment_tolerance must be in [0, 1] (a fraction of r)");
  need(o.void_rounds >= 0 && o.void_rounds <= 100, "void_rounds must be 0..100");
  need(o.void_clearance > 0 && o.void_clearance <= 4, "void_clearance must be in (0, 4] rest distances");
  need(o.field_spacing > 0 && o.field_spacing <= 2, "field_spacing must be in (0, 2] radii");
  need(o.max_field_samples >= 4096, "max_field_samples must be at least 4096");
  need(o.skin >= 0 && o.skin <= 2, "skin must be in [0, 2] sigma (0: automatic)");
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
    throw Error("no particle of radius " + fmt(radius) + " fits: the mesh's box is only " + fmt(thinnest) +
                " across; choose a radius below " + fmt(thinnest / 2));
  if (o.birth_point) {
    const Vec3& p = *o.birth_point;
    const bool in_box = p.x >= box.lo.x && p.x <= box.hi.x && p.y >= box.lo.y && p.y <= box.hi.y &&
                        p.z >= box.lo.z && p.z <= box.hi.z;
    need(in_box, "birth_point lies outside the mesh's box, so outside the mesh; give a point inside it or leave "
                 "it out");
  }
  // Damping is a rate in the mesh's time; per step it removes 1 - exp(-damping dt).
  const double a = o.exponent_a, b = o.exponent_b;
  const double sigma = o.rest_distance * 2 * radius / std::pow(a / b, 1 / (a - b));
  const double dt = o.time_step * sigma / std::sqrt(o.epsilon);
  if (o.damping * dt > 0.1)
    throw Error("damping " + fmt(o.damping) + " stops every particle within a few steps at this radius; keep it " +
                "below " + fmt(0.1 / dt));
}

void check_coordinates_resolve(const Mesh& mesh, double radius) {
  const Box3 box = mesh.bounds();
  if (box.empty() || !(radius > 0)) return;
  const double far = std::max({std::abs(box.lo.x), std::abs(box.lo.y), std::abs(box.lo.z), std::abs(box.hi.x),
                               std::abs(box.hi.y), std::abs(box.hi.z)});
  const double spacing = far * 0x1p-52;  // about the gap between neighbouring doubles there
  if (spacing > 0.01 * radius)
    throw Error("the mesh lies " + fmt(far) + " from the origin, where coordinates are spaced " + fmt(spacing) +
                " apart, " + fmt(100 * spacing / radius) + "% of the radius " + fmt(radius) +
                ": the spheres' positions could not be written as the fill measured them; move the mesh nearer "
                "the origin");
}

std::string name_fill_options(const std::string& message, bool cli) {
  struct Name {
    const char* cpp;
    const char* flag;
    const char* python;
  };
  static const Name kNames[] = {
      {"radius", "-r", "radius"}, {"count", "-n", "count"},
      {"rest_distance", "--rest-distance", "rest_distance"}, {"epsilon", "--epsilon", "epsilon"},
      {"exponents", "--exponents", "exponents"}, {"cutoff", "--cutoff", "cutoff"},
      {"restitution", "--restitution", "restitution"}, {"wall_restitution", "--wall-restitution", "wall_restitution"},
      {"damping", "--damping", "damping"}, {"time_step", "--time-step", "time_step"},
      {"max_step_fraction", "--max-step", "max_step"}, {"sites", "--sites", "sites"},
      {"site_depth_share", "--site-depth", "site_depth"}, {"birth_every", "--birth-every", "birth_every"},
      {"site_spacing", "--site-spacing", "site_spacing"}, {"site_min_depth", "--site-min-depth", "site_min_depth"},
      {"birth_point", "--birth", "birth"}, {"birth_speed", "--birth-speed", "birth_speed"},
      {"birth_clearance", "--birth-clearance", "birth_clearance"}, {"birth_stop_share", "--stop-share", "stop_share"},
      {"patience", "--patience", "patience"}, {"max_steps", "--max-steps", "max_steps"},
      {"settle_budget", "--settle-steps", "settle_budget"}, {"max_overlap", "--max-overlap", "max_overlap"},
      {"void_rounds", "--void-rounds", "void_rounds"}, {"void_clearance", "--void-clearance", "void_clearance"},
      {"skin", "--skin", "skin"}, {"sync_every", "--sync-every", "sync_every"}, {"frame_every", "--every", "every"}};
  auto is_word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; };
  std::string out;
  size_t i = 0;
  while (i < message.size()) {
    if (!is_word(message[i])) {
      out += message[i++];
      continue;
    }
    size_t j = i;
    while (j < message.size() && is_word(message[j])) ++j;
    const std::string word = message.substr(i, j - i);
    // Names with an underscore anywhere; a plain word only as the message's subject (its first word).
    const Name* hit = nullptr;
    for (const Name& n : kNames)
      if (word == n.cpp && (i == 0 || word.find('_') != std::string::npos)) hit = &n;
    out += hit ? (cli ? hit->flag : hit->python) : word;
    i = j;
  }
  return out;
}

}  // namespace pfill
