#include "fill/fill_progress.hpp"

#include "pfill/peak_memory.hpp"

namespace pfill {

const char* to_string(FillPhase phase) {
  switch (phase) {
    case FillPhase::Field: return "field";
    case FillPhase::Pass1: return "pass 1";
    case FillPhase::Pass2: return "pass 2";
    case FillPhase::Settle: return "settle";
    case FillPhase::Finish: return "finish";
    case FillPhase::Verify: return "verify";
  }
  return "?";
}

void FillReporter::set_schedule(size_t target, const TimeLeftSchedule& schedule) {
  target_ = target;
  time_left_ = TimeLeft(schedule);
}

double FillReporter::elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

void FillReporter::report(size_t particles, double kinetic_energy, uint32_t colliding_pairs, uint64_t step,
                          uint64_t finish_steps) {
  if (!callback_) return;
  FillProgress p;
  p.phase = phase_;
  p.step = step;
  p.particles = particles;
  p.target = target_;
  p.kinetic_energy = kinetic_energy;
  p.colliding_pairs = colliding_pairs;
  p.elapsed = elapsed();
  const double dt = std::chrono::duration<double>(Clock::now() - last_report_).count();
  if (dt > 0 && p.step >= last_step_) p.steps_per_second = static_cast<double>(p.step - last_step_) / dt;
  last_report_ = Clock::now();
  last_step_ = p.step;
  p.remaining = time_left_.estimate(phase_, p.elapsed, particles, p.step, finish_steps);
  p.peak_memory = peak_resident_bytes();
  callback_(p);
}

}  // namespace pfill
