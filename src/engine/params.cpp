// Checks engine settings and derives sigma, cutoff, time step and caps.
#include "pfill/engine/params.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "pfill/device/device.hpp"
#include "pfill/device/program.hpp"
#include "pfill/error.hpp"

namespace pfill {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw Error("engine settings: " + what);
}

// e/2 when e is an even integer up to 64 (products beat pow), else 0.
int even_half(double e) {
  const double h = e / 2;
  return (h == std::floor(h) && h >= 1 && h <= 32) ? static_cast<int>(h) : 0;
}

// Cells for the densest listing: spheres of diameter `s` at packing 0.74
// in a cell of edge `edge`, 30% margin, plus slack; whole float8 loads.
unsigned cell_capacity_for(double edge, double s) {
  const double dense = std::pow(edge, 3) * 0.74 / (M_PI / 6 * std::pow(s, 3));
  const unsigned cap = static_cast<unsigned>(std::clamp(std::ceil(1.3 * dense) + 8, 8.0, 248.0));
  return (cap + 7) / 8 * 8;
}

// The cell levels (EngineConstants::cell_levels): with unequal spheres
// of radii 1:2 or more, level 0 holds radii up to level_radius in cells
// its largest pair reaches, and each level up twice the radii in cells
// twice as wide, so that a small sphere's cells hold small spheres only,
// not the many that fit in a cell sized for the largest pair.
void derive_cells(const EngineParams& p, double rest, EngineConstants& c) {
  const double ratio = c.max_radius / p.radius;
  const unsigned doublings = ratio >= 2 ? static_cast<unsigned>(std::floor(std::log2(ratio))) : 0;
  c.cell_levels = c.polydisperse ? std::min(1 + doublings, 8u) : 1;
  c.level_radius = c.max_radius / std::ldexp(1.0, static_cast<int>(c.cell_levels) - 1);
  const double q0 = c.level_radius / p.radius;  // level 0's largest pair scale
  c.cell_size = c.cell_levels == 1 ? c.list_reach
                                   : std::max({c.cutoff * q0, 2 * c.level_radius, rest * q0}) + c.skin;
  c.cell_capacity = cell_capacity_for(c.cell_size, 0.8 * std::min(2 * p.radius, rest));
  // a level above 0 holds radii above half its largest, in cells twice level 0's ratio to it
  const double up_diameter = 0.8 * std::min(2 * c.level_radius, rest * q0);
  c.cell_capacity_up = c.cell_levels == 1 ? c.cell_capacity : cell_capacity_for(2 * c.cell_size, up_diameter);
}

// The skin derive_constants uses: Engine resolves an automatic skin for its
// step form first; elsewhere, as in the reference, which lists nothing, it
// is the gpu form's.
double skin_sigma_of(const EngineParams& p) { return p.skin_sigma > 0 ? p.skin_sigma : kGpuFormSkinSigma; }

// Every setting's range, one line naming the bad one (derive_constants).
void check_params(const EngineParams& p) {
  require(std::isfinite(p.radius) && p.radius > 0, "radius must be > 0");
  require(p.max_radius == 0 || p.max_radius >= p.radius, "max_radius must be 0 or >= radius");
  require(p.rest_distance >= 0, "rest_distance must be >= 0 (0: twice the radius)");
  require(std::isfinite(p.eps) && p.eps > 0, "eps must be > 0");
  require(p.exponent_b > 0 && p.exponent_a > p.exponent_b, "exponents need a > b > 0 (default 12, 6)");
  require(p.cutoff_sigma == 0 || p.cutoff_sigma > 1, "cutoff_sigma must be 0 (purely repulsive) or > 1");
  require(p.restitution >= 0 && p.restitution <= 1, "restitution must be in [0, 1]");
  require(p.wall_restitution >= 0 && p.wall_restitution <= 1, "wall_restitution must be in [0, 1]");
  require(p.damping >= 0, "damping must be >= 0");
  require(p.dt >= 0, "dt must be >= 0 (0: derived from the potential)");
  require(p.max_step_fraction > 0 && p.max_step_fraction <= 0.5, "max_step_fraction must be in (0, 0.5]");
  require(p.force_cap >= 0, "force_cap must be >= 0 (0: derived)");
  require(p.skin_sigma >= 0 && p.skin_sigma <= 2, "skin_sigma must be in [0, 2] (0: automatic)");
  require(p.inner_skin_sigma > 0, "inner_skin_sigma must be > 0");
  require(p.inner_lists != InnerLists::on || p.inner_skin_sigma < skin_sigma_of(p),
          "inner_skin_sigma must be below skin_sigma for inner lists");
  require(p.history_capacity >= 2, "history_capacity must be >= 2");
  require(std::isfinite(p.wall_offset), "wall_offset must be a finite number");
  require(p.work_group >= 1, "work_group must be >= 1");
  require(p.force_buffers <= 1024, "force_buffers must be <= 1024 (0: one per compute unit)");
  if (p.fire.on) {
    const FireParams& f = p.fire;
    require(p.damping == 0, "damping must be 0 with fire.on (FIRE drops velocities itself)");
    require(f.dt_min > 0 && f.dt_min <= 1 && f.dt_max >= 1, "fire needs 0 < dt_min <= 1 <= dt_max (units of dt)");
    require(f.grow >= 1 && f.shrink > 0 && f.shrink < 1, "fire needs grow >= 1 and shrink in (0, 1)");
    require(f.alpha_start >= 0 && f.alpha_start < 1 && f.alpha_shrink > 0 && f.alpha_shrink <= 1,
            "fire needs alpha_start in [0, 1) and alpha_shrink in (0, 1]");
    require(f.delay >= 0, "fire.delay must be >= 0");
  }

}

}  // namespace

EngineConstants derive_constants(const EngineParams& p) {
  check_params(p);
  EngineConstants c;
  const double a = p.exponent_a, b = p.exponent_b;
  const double rest = p.rest_distance > 0 ? p.rest_distance : 2 * p.radius;
  c.sigma = rest / std::pow(a / b, 1 / (a - b));
  c.cutoff = p.cutoff_sigma > 0 ? p.cutoff_sigma * c.sigma : rest;
  c.tau = c.sigma * std::sqrt(1 / p.eps);
  c.dt = p.dt > 0 ? p.dt : 0.005 * c.tau;
  c.max_speed = p.max_step_fraction * c.sigma / c.dt;
  c.force_cap = p.force_cap > 0 ? p.force_cap : c.max_speed / c.dt;
  c.damping_factor = std::exp(-p.damping * c.dt);
  c.contact_distance = rest;
  // Stiffness of the potential at its minimum, and the damping ratio that
  // gives the restitution for a linear spring of that stiffness.
  const double x = c.sigma / rest;
  const double k = 4 * p.eps * (a * (a + 1) * std::pow(x, a) - b * (b + 1) * std::pow(x, b)) / (rest * rest);
  const double log_e = std::log(std::max(p.restitution, 1e-6));
  const double zeta = p.restitution >= 1 ? 0 : -log_e / std::sqrt(M_PI * M_PI + log_e * log_e);
  c.dashpot = 2 * zeta * std::sqrt(k);
  c.max_radius = p.max_radius > 0 ? p.max_radius : p.radius;
  // Unequal spheres: each pair's lengths scale with (r_i + r_j) / (2 radius)
  // (physics.cl PF_DEFINE_PAIR_SCALE2), the largest pair's by max_radius /
  // radius. Automatic: a max_radius within kEqualRadiusTolerance of radius
  // (what the fill and its finish pass for equal spheres) runs every pair
  // at scale 1, as equal spheres.
  c.polydisperse = p.pair_scaling == PairScaling::automatic
                       ? c.max_radius > p.radius * (1 + kEqualRadiusTolerance)
                       : p.pair_scaling == PairScaling::on;
  const double q_max = c.polydisperse ? c.max_radius / p.radius : 1.0;
  c.skin = skin_sigma_of(p) * c.sigma;
  // (2 max_radius: a sphere up to max_radius touches at r_i + r_j even below the scaled rest distance)
  c.list_reach = std::max({c.cutoff * q_max, 2 * c.max_radius, rest * q_max}) + c.skin;
  derive_cells(p, rest, c);
  // Lists: spheres of diameter 0.9 * min(2 r, rest) at packing 0.74 within the reach.
  const double s_list = 0.9 * std::min(2 * p.radius, rest);
  double in_reach = 4.0 / 3.0 * M_PI * std::pow(c.list_reach, 3) * 0.74 / (M_PI / 6 * std::pow(s_list, 3));
  if (c.polydisperse) {
    // Lists hold each pair within its own reach (kernels/common.cl
    // PF_LISTED): at most the reference spheres within the reference
    // pair's reach, or those in the shell around a sphere of max_radius out
    // to its pair's reach with one of `radius` (the largest list: the
    // reach grows faster than the excluded core), whichever is more.
    const double r = p.radius, R = c.max_radius, reach_ref = std::max({c.cutoff, 2 * r, rest});
    const double reach_ss = reach_ref + c.skin;
    const double reach_bs = std::max((R + r) / (2 * r) * std::max(c.cutoff, rest), R + r) + c.skin;
    const double core = 0.9 * (R + r);
    auto count = [&](double volume) { return volume * 0.74 / (M_PI / 6 * std::pow(s_list, 3)); };
    in_reach = std::max(count(4.0 / 3.0 * M_PI * std::pow(reach_ss, 3)),
                        count(4.0 / 3.0 * M_PI * (std::pow(reach_bs, 3) - std::pow(core, 3))));
  }
  c.list_capacity = static_cast<unsigned>(std::ceil(in_reach) + 8);
  c.list_capacity = (c.list_capacity + 7) / 8 * 8;
  c.inner_skin = p.inner_skin_sigma * c.sigma;
  c.inner_reach = std::max({c.cutoff * q_max, 2 * c.max_radius, rest * q_max}) + c.inner_skin;
  // Inner rows bounded as the lists are, at the inner reach (unequal
  // spheres: as the lists): at 1e6 the finish's inner rows then take ~110
  // MiB, not the lists' ~180 (docs/benchmarks.md, 2026-12-08).
  const double in_inner = c.polydisperse ? in_reach
                                          : 4.0 / 3.0 * M_PI * std::pow(c.inner_reach, 3) * 0.74 /
                                                (M_PI / 6 * std::pow(s_list, 3));
  c.inner_capacity = std::min(c.list_capacity, (static_cast<unsigned>(std::ceil(in_inner) + 8) + 7) / 8 * 8);
  c.a_half = even_half(a);
  c.b_half = even_half(b);
  return c;
}

double particle_mass(const EngineParams& p, double r) { return std::pow(r / p.radius, 3); }

double automatic_skin_sigma(const EngineParams& p, bool gpu_form) {
  if (gpu_form) return kGpuFormSkinSigma;
  const bool repulsive = p.cutoff_sigma <= 0;  // (with a cutoff the rows are long: a wider skin costs more than the rebuilds it saves)
  if (!repulsive) return kCpuFormSkinSigma;
  if (p.max_radius >= kMixSkinRatio * p.radius) return kCpuFormMixSkinSigma;
  return p.births_at_speed ? kCpuFormBirthsSkinSigma : kCpuFormSkinSigma;
}

DeviceChoices resolve_for_device(const DeviceInfo& device, const EngineParams& p) {
  DeviceChoices c;
  c.form_automatic = p.step_form == StepForm::automatic;
  c.gpu_form = c.form_automatic ? device.type != "CPU" : p.step_form == StepForm::gpu;
  c.skin_automatic = p.skin_sigma == 0;
  c.skin_sigma = c.skin_automatic ? automatic_skin_sigma(p, c.gpu_form) : p.skin_sigma;
  // The `cpu` form's variants: Newton's third law on few cores (each core's
  // force buffer is read for every particle), the pair queue for purely
  // repulsive rows (short, few entries in reach), inner lists with a
  // cutoff (long rows, most of the skin's entries out of reach).
  c.newton_automatic = p.newton == Newton::automatic;
  c.newton = !c.gpu_form && (c.newton_automatic ? device.compute_units <= 4 : p.newton == Newton::on);
  c.queue_automatic = p.pair_queue == PairQueue::automatic;
  c.pair_queue = !c.gpu_form && (c.queue_automatic ? p.cutoff_sigma <= 0 : p.pair_queue == PairQueue::on);
  c.inner_automatic = p.inner_lists == InnerLists::automatic;
  c.inner_lists = !c.gpu_form && (c.inner_automatic ? p.cutoff_sigma > 0 && p.inner_skin_sigma < c.skin_sigma
                                                    : p.inner_lists == InnerLists::on);
  c.work_group = floor_power_of_two(std::min(p.work_group, device.max_work_group));
  c.device_line = device.type + " '" + device.name + "' (" + std::to_string(device.compute_units) + " compute units)";
  return c;
}

std::string DeviceChoices::describe() const {
  auto how = [](bool automatic) { return automatic ? " (automatic)" : " (set)"; };
  auto on = [](bool b) { return b ? "on" : "off"; };
  std::ostringstream s;
  s << "engine on " << device_line << ": " << (gpu_form ? "gpu" : "cpu") << " step form" << how(form_automatic)
    << ", skin " << skin_sigma << " sigma" << how(skin_automatic) << ", work-group " << work_group;
  if (!gpu_form)
    s << ", newton " << on(newton) << how(newton_automatic) << ", pair queue " << on(pair_queue)
      << how(queue_automatic) << ", inner lists " << on(inner_lists) << how(inner_automatic);
  return s.str();
}

}  // namespace pfill
