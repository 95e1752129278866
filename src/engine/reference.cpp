// The double-precision oracle of the engine step: the same formulas
// (kernels/physics.cl in double precision: kernels/physics_double.hpp) and the same
// order of operations as the kernels (kernels/*_step.cl), with brute-force pairs.
#include "pfill/engine/reference.hpp"

#include <algorithm>
#include <functional>
#include <string>
#include <utility>

#include "pfill/error.hpp"
#include "../../kernels/physics_double.hpp"

namespace pfill {

namespace {

physics::pf_fire_rule fire_rule(const EngineParams& p, const EngineConstants& c) {
  physics::pf_fire_rule r;
  r.dt_max = p.fire.dt_max * c.dt;
  r.dt_min = p.fire.dt_min * c.dt;
  r.grow = p.fire.grow;
  r.shrink = p.fire.shrink;
  r.alpha_start = p.fire.alpha_start;
  r.alpha_shrink = p.fire.alpha_shrink;
  r.delay = p.fire.delay;
  return r;
}

}  // namespace

ReferenceEngine::ReferenceEngine(const EngineParams& params) : params_(params), constants_(derive_constants(params)) {
  restart_minimiser();
}

void ReferenceEngine::set_field(const ScalarGrid& field) {
  field_ = field;
  // EngineParams::wall_offset: the kernels add it to each sample they read
  for (float& v : field_.values) v += static_cast<float>(params_.wall_offset);
  has_field_ = true;
}

size_t ReferenceEngine::add_particles(const std::vector<Particle>& particles) {
  const size_t first = particles_.size();
  for (Particle p : particles) {
    if (p.mass == 0) p.mass = particle_mass(params_, p.radius);
    particles_.push_back(p);
    flags_.push_back(false);
  }
  return first;
}

std::string ReferenceEngine::describe() const { return "the C++ reference engine (double precision, every pair)"; }

void ReferenceEngine::run_steps(size_t k) {
  for (size_t s = 0; s < k; ++s) history_.push_back(step());
}

std::vector<StepRecord> ReferenceEngine::read_history() {
  take_in_flight();
  return std::exchange(history_, {});
}

void ReferenceEngine::take_in_flight() {
  if (!params_.fire.on) return;
  physics::pf_fire_state f{fire_.dt, fire_.alpha, fire_.backtrack, fire_.positive, fire_.restarts, fire_.restart_step};
  for (const auto& [step, power] : in_flight_)
    f = physics::pf_fire_next(f, fire_rule(params_, constants_), power, static_cast<uint32_t>(step),
                              static_cast<uint32_t>(steps_));
  in_flight_.clear();
  fire_ = {f.dt, f.alpha, f.backtrack, f.positive, f.restarts, f.restart_step};
}

void ReferenceEngine::restart_minimiser() {
  if (!params_.fire.on) return;
  take_in_flight();
  fire_ = {constants_.dt, params_.fire.alpha_start, 0, 0, 0, static_cast<uint32_t>(steps_)};
}

ParticleEngine::MinimiserState ReferenceEngine::minimiser_state() {
  take_in_flight();
  MinimiserState m;
  if (params_.fire.on) m = {fire_.dt, fire_.alpha, fire_.restarts};
  return m;
}

std::vector<size_t> ReferenceEngine::sort_by_cells() {
  take_in_flight();  // as the engine, which finishes the steps in flight to sort
  std::vector<size_t> order(particles_.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  return order;
}

std::vector<size_t> ReferenceEngine::flagged_particles() {
  std::vector<size_t> out;
  for (size_t i = 0; i < flags_.size(); ++i)
    if (flags_[i]) out.push_back(i);
  return out;
}

void ReferenceEngine::clear_flags() { std::fill(flags_.begin(), flags_.end(), false); }

void ReferenceEngine::remove_particles(std::vector<size_t> indices) {
  std::sort(indices.begin(), indices.end(), std::greater<size_t>());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  for (size_t idx : indices) {
    if (idx >= particles_.size()) throw Error("reference: cannot remove particle " + std::to_string(idx));
    particles_[idx] = particles_.back();
    flags_[idx] = flags_.back();
    particles_.pop_back();
    flags_.pop_back();
  }
}

double ReferenceEngine::pair_scale2(double rs) const {
  if (!constants_.polydisperse) return 1;
  const double rs_ref = 2 * params_.radius;
  return physics::pf_pair_scale2(rs, rs_ref, 1 / (rs_ref * rs_ref));
}

double ReferenceEngine::pair_scale(double rs) const {
  if (!constants_.polydisperse) return 1;
  const double rs_ref = 2 * params_.radius;
  return physics::pf_pair_scale(rs, rs_ref, 1 / rs_ref);
}

StepRecord ReferenceEngine::step() {
  const EngineConstants& c = constants_;
  const double sigma2 = c.sigma * c.sigma, rc2 = c.cutoff * c.cutoff, dmin = 1e-3f * c.sigma;
  const double contact2 = c.contact_distance * c.contact_distance;
  StepRecord rec;
  rec.step = steps_++;
  rec.particles = static_cast<uint32_t>(particles_.size());
  const bool fire = params_.fire.on;
  const bool restart = fire && fire_.restart_step == static_cast<uint32_t>(rec.step);
  std::vector<Particle> next = particles_;
  for (size_t i = 0; i < particles_.size(); ++i) {
    const Particle& pi = particles_[i];
    const double inv_mi = 1 / pi.mass;
    Vec3 force;
    for (size_t j = 0; j < particles_.size(); ++j) {
      if (j == i) continue;
      const Particle& pj = particles_[j];
      Vec3 d = pi.position - pj.position;
      double d2 = dot(d, d);
      const double rs = pi.radius + pj.radius;
      const double q2 = pair_scale2(rs), q = pair_scale(rs);  // the pair's scales (1 for equal spheres)
      if (d2 >= std::max(rc2 * q2, rs * rs)) continue;
      physics::pf_apart(&d.x, &d.y, &d.z, &d2, d2 < dmin * dmin, j > i, dmin);
      force += physics::pf_lj_force_scale(d2, sigma2 * q2, params_.eps, params_.exponent_a, params_.exponent_b,
                                          c.a_half, c.b_half, rc2 * q2, c.force_cap, q2 * q) * d;
      if (d2 < std::max(rs * rs, contact2 * q2)) {
        const Vec3 n = d / std::sqrt(d2);
        force +=
            physics::pf_contact_damping(dot(pi.velocity - pj.velocity, n), inv_mi, 1 / pj.mass, c.dashpot, q) * n;
        if (j > i && d2 < rs * rs) ++rec.colliding_pairs;
      }
    }
    Vec3 u = pi.velocity, x = pi.position;
    if (fire) {
      double power = 0;  // (a restart's speed cap: the kernels' PF_STEP_CAP / dt)
      physics::pf_fire_kick_drift(&u.x, &u.y, &u.z, &x.x, &x.y, &x.z, force.x, force.y, force.z, inv_mi, fire_.dt,
                                  fire_.alpha, restart, fire_.backtrack, c.max_speed * c.dt / fire_.dt, &power);
      rec.power += power;
    } else {
      physics::pf_kick_drift(&u.x, &u.y, &u.z, &x.x, &x.y, &x.z, force.x, force.y, force.z, inv_mi, c.dt,
                             c.damping_factor, c.max_speed);
    }
    if (has_field_) {
      double g[3];
      double phi = physics::sample(field_, x.x, x.y, x.z, g);
      const Vec3 gp = (x - field_.origin) / field_.spacing;
      const bool outside_box = gp.x < 0 || gp.y < 0 || gp.z < 0 || gp.x > field_.dims[0] - 1 ||
                               gp.y > field_.dims[1] - 1 || gp.z > field_.dims[2] - 1;
      if (phi > 0 || outside_box) {
        ++rec.flagged;
        flags_[i] = true;
      }
      physics::wall_push(&x.x, &x.y, &x.z, &u.x, &u.y, &u.z, phi, g, phi > -pi.radius, pi.radius, params_.wall_restitution,
                field_);
    }
    next[i].position = x;
    next[i].velocity = u;
    rec.kinetic_energy += 0.5 * pi.mass * dot(u, u);
    rec.max_speed = std::max(rec.max_speed, length(u));
    rec.max_displacement = std::max(rec.max_displacement, length(x - pi.position));
  }
  particles_ = std::move(next);
  if (fire) {
    // As the engine's step t: it takes in the record of step t - 2 when that is in flight.
    if (!in_flight_.empty() && in_flight_.front().first + 2 == rec.step) {
      physics::pf_fire_state f{fire_.dt, fire_.alpha, fire_.backtrack, fire_.positive, fire_.restarts,
                               fire_.restart_step};
      f = physics::pf_fire_next(f, fire_rule(params_, c), in_flight_.front().second,
                                static_cast<uint32_t>(in_flight_.front().first), static_cast<uint32_t>(rec.step + 1));
      fire_ = {f.dt, f.alpha, f.backtrack, f.positive, f.restarts, f.restart_step};
      in_flight_.erase(in_flight_.begin());
    }
    in_flight_.emplace_back(rec.step, rec.power);
  }
  return rec;
}

double ReferenceEngine::potential_energy() const {
  const EngineConstants& c = constants_;
  double e = 0;
  for (size_t i = 0; i < particles_.size(); ++i)
    for (size_t j = i + 1; j < particles_.size(); ++j) {
      const Vec3 d = particles_[i].position - particles_[j].position;
      const double d2 = std::max(dot(d, d), 1e-300);
      const double rs = particles_[i].radius + particles_[j].radius;
      const double q2 = pair_scale2(rs), q = pair_scale(rs);
      e += physics::pf_lj_energy(d2, c.sigma * c.sigma * q2, params_.eps * (q2 * q), params_.exponent_a, params_.exponent_b,
                                 c.a_half, c.b_half, c.cutoff * c.cutoff * q2);
    }
  return e;
}

std::vector<std::vector<uint32_t>> ReferenceEngine::neighbour_lists() const {
  const double rc2 = constants_.cutoff * constants_.cutoff;
  std::vector<std::vector<uint32_t>> out(particles_.size());
  for (size_t i = 0; i < particles_.size(); ++i)
    for (size_t j = 0; j < particles_.size(); ++j) {
      if (i == j) continue;
      const Vec3 d = particles_[i].position - particles_[j].position;
      const double rs = particles_[i].radius + particles_[j].radius;
      if (dot(d, d) < std::max(rc2 * pair_scale2(rs), rs * rs)) out[i].push_back(static_cast<uint32_t>(j));
    }
  return out;
}

}  // namespace pfill
