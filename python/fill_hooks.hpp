// FillOptions::progress and ::cancelled for Python callers, whose fill
// runs without the GIL.
#pragma once
#include <pybind11/pybind11.h>

#include <chrono>
#include <exception>
#include <optional>
#include <string>
#include <utility>

#include "pfill/error.hpp"
#include "pfill/fill.hpp"

namespace pfill::python {

namespace py = pybind11;

/// The Python side of the fill's hooks: progress calls and cancel polls
/// take the GIL for a moment; a Python exception raised there (a
/// KeyboardInterrupt from Ctrl-C, or the progress callback's own) stops the
/// fill and is raised again once the fill has unwound.
class FillHooks {
  using Clock = std::chrono::steady_clock;

 public:
  FillHooks(py::object progress, py::object cancelled) : progress_(std::move(progress)), cancelled_(std::move(cancelled)) {}
  FillHooks(const FillHooks&) = delete;  // the hooks point at this object
  FillHooks& operator=(const FillHooks&) = delete;

  void attach(FillOptions& o) {
    o.cancelled = [this] { return poll(); };
    if (!progress_.is_none()) o.progress = [this](const FillProgress& p) { report(p); };
  }

  /// After the fill threw pfill::Cancelled: the Python error that caused
  /// it, else pfill.Cancelled (the user's `cancelled` returned true).
  [[noreturn]] void raise_cancelled() {
    if (pending_) std::rethrow_exception(pending_);
    throw Cancelled();
  }

 private:
  bool poll() {
    if (pending_ || user_cancelled_) return true;
    // Signals and the user's hook at most every 20 ms: a sync can be more
    // often than that, and the GIL may be busy.
    const Clock::time_point now = Clock::now();
    if (now - last_poll_ < std::chrono::milliseconds(20)) return false;
    last_poll_ = now;
    py::gil_scoped_acquire gil;
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!cancelled_.is_none() && py::bool_(cancelled_())) user_cancelled_ = true;
    } catch (const py::error_already_set&) {
      pending_ = std::current_exception();
    }
    return pending_ || user_cancelled_;
  }

  void report(const FillProgress& p) {
    if (pending_) return;
    // A new phase at once, else at most ten calls a second (the fill
    // reports at every sync).
    const Clock::time_point now = Clock::now();
    if (p.phase == last_phase_ && now - last_report_ < std::chrono::milliseconds(100)) return;
    last_phase_ = p.phase;
    last_report_ = now;
    py::gil_scoped_acquire gil;
    try {
      py::dict d;
      d["phase"] = to_string(p.phase);
      d["step"] = p.step;
      d["particles"] = p.particles;
      d["target"] = p.target;
      d["kinetic_energy"] = p.kinetic_energy;
      d["colliding_pairs"] = p.colliding_pairs;
      d["steps_per_second"] = p.steps_per_second;
      d["elapsed"] = p.elapsed;
      d["remaining"] = p.remaining >= 0 ? py::object(py::float_(p.remaining)) : py::none();
      progress_(d);
    } catch (const py::error_already_set&) {
      pending_ = std::current_exception();
    }
  }

  py::object progress_, cancelled_;
  std::exception_ptr pending_;
  bool user_cancelled_ = false;
  Clock::time_point last_poll_{};
  std::optional<FillPhase> last_phase_;
  Clock::time_point last_report_{};
};

}  // namespace pfill::python
