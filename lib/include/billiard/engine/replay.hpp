// Replaying a recorded run: the state just after each logged event, or at increasing times
// (for animations at a fixed frame rate), rebuilt from the initial state and the event log.
//
//   sim.set_log_events(true);
//   sim.advance(1000);
//   billiard::Replay replay(sim);
//   while (!replay.finished()) draw(replay.after_next_event());
//
// Between events every disc flies freely (r + v t + g t^2 / 2) or sleeps, so each disc's last
// logged position and velocity (and whether it fell asleep there) fix it. Each step costs
// O(discs touched) to apply the events plus O(N) to produce the state: a whole replay is linear
// in its length (a new Replay for every k would be quadratic). The log must have been enabled
// from the first advance() on, and the simulation must outlive the Replay (it reads the log as
// it goes, so a run advanced further while replaying is followed too).
#pragma once

#include "billiard/engine/disc.hpp"
#include "billiard/engine/simulation.hpp"

#include <cstddef>
#include <vector>

namespace billiard {

class Replay {
 public:
  explicit Replay(const Simulation& simulation);

  // Logged events applied so far (the next after_next_event() shows event number applied()).
  std::size_t applied() const { return next_; }
  // True when every logged event has been applied.
  bool finished() const;

  // Applies the next logged event and returns the state just after it, at its time. Throws
  // std::logic_error when finished().
  State after_next_event();

  // Applies the logged events up to number k (k >= applied()) and returns the state just after
  // event k, at its time. Throws std::invalid_argument if event k is not in the log or already
  // applied.
  State after_event(std::size_t k);

  // The state at time t: applies every logged event up to t. Times must not decrease from one
  // call to the next (std::invalid_argument otherwise, naming t); t may lie beyond the last
  // logged event (free flight from there).
  State at(double t);

 private:
  void apply(std::size_t k);
  State state_at(double t) const;

  const Simulation* simulation_;
  State last_;                  // each disc as last logged (position, velocity, spin) ...
  Eigen::VectorXd since_;       // ... and the time of that record
  std::vector<bool> asleep_;    // fell asleep at that record (stays put until woken)
  std::size_t next_ = 0;
  double time_;                 // time of the last state produced
  Vector gravity_;
  Vector period_;               // (0, 0) unless periodic
};

}  // namespace billiard
