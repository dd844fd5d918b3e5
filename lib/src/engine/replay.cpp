// Replay of a recorded run (billiard/engine/replay.hpp). Reads the run through the public
// Simulation API.
#include "billiard/engine/replay.hpp"

#include "billiard/engine/container.hpp"
#include "container_geometry.hpp"
#include "billiard/describe.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace billiard {

Replay::Replay(const Simulation& simulation)
    : simulation_(&simulation),
      last_(simulation.initial_state()),
      since_(Eigen::VectorXd::Constant(last_.positions.rows(), last_.time)),
      asleep_(static_cast<std::size_t>(last_.positions.rows()), false),
      time_(last_.time),
      gravity_(simulation.gravity()),
      period_(simulation.container().period()) {}

bool Replay::finished() const { return next_ >= simulation_->event_log().size(); }

void Replay::apply(std::size_t k) {
  const EventRecord& e = simulation_->event_log()[k];
  last_.positions.row(e.disc) = e.position;
  last_.velocities.row(e.disc) = e.velocity;
  last_.spins[e.disc] = e.spin;
  since_[e.disc] = e.time;
  if (e.kind == EventKind::Sleep) asleep_[e.disc] = true;
  if (e.kind == EventKind::Wake) asleep_[e.disc] = false;
  if (e.other >= 0) {
    last_.positions.row(e.other) = e.other_position;
    last_.velocities.row(e.other) = e.other_velocity;
    last_.spins[e.other] = e.other_spin;
    since_[e.other] = e.time;
  }
}

// Every disc moved from its last record to time t (free flight under gravity, sleeping discs
// stay; wrapped into the periodic box if there is one).
State Replay::state_at(double t) const {
  State state = last_;
  state.time = t;
  for (Eigen::Index i = 0; i < state.positions.rows(); ++i) {
    if (asleep_[static_cast<std::size_t>(i)]) continue;
    const double dt = t - since_[i];
    Vector r = last_.positions.row(i);
    const Vector v = last_.velocities.row(i);
    r += dt * (v + 0.5 * dt * gravity_);
    state.positions.row(i) = wrap_into_period(r, period_);
    state.velocities.row(i) = (v + dt * gravity_);
  }
  return state;
}

State Replay::after_next_event() {
  if (finished()) throw std::logic_error("Replay::after_next_event: every logged event has been replayed");
  const double t = simulation_->event_log()[next_].time;
  apply(next_++);
  // Events at the same instant (a corner hit, three discs touching) come one by one: each shows
  // the state after it.
  time_ = t;
  return state_at(t);
}

State Replay::after_event(std::size_t k) {
  const auto& log = simulation_->event_log();
  if (k >= log.size() || k < next_) {
    throw std::invalid_argument("Replay::after_event: k must be in [" + std::to_string(next_) + ", " +
                                std::to_string(log.size()) + "), got " + std::to_string(k));
  }
  while (next_ <= k) apply(next_++);
  time_ = log[k].time;
  return state_at(time_);
}

State Replay::at(double t) {
  if (!std::isfinite(t) || t < time_) {
    throw std::invalid_argument(describe("Replay::at: t must be finite and not before the previous time ", time_, ", got ", t));
  }
  const auto& log = simulation_->event_log();
  while (next_ < log.size() && log[next_].time <= t) apply(next_++);
  time_ = t;
  return state_at(t);
}

}  // namespace billiard
