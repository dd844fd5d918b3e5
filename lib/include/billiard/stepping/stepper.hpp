// A time-stepped integrator for point particles in a level-set domain (level_set.hpp) under
// uniform gravity: the method the event-driven Simulation is contrasted with (lib/PHYSICS.md,
// "Time stepping in level-set domains").
//
//   using namespace billiard::stepping;
//   Coordinates x(1, 2), v(1, 2);
//   x << 0.2, 0.0;  v << 1.0, 0.5;
//   Stepper stepper({circle({0, 0}, 1.0)}, x, v, /*dt=*/1e-3, Vector(0, -1));
//   stepper.advance_to(10.0);
//   double drift = stepper.energy() - stepper.initial_energy();
//
// Particles do not interact; each has unit mass. Every step moves all particles by dt: a kick,
// a straight drift and a kick (Integrator below); a drift that ends outside the domain is cut
// where it leaves (linear interpolation of omega), the velocity is reflected about the inward
// normal there, and the drift goes on for the rest of the step.
//
// Arguments are checked at the boundary: std::invalid_argument naming the argument and its value,
// the stepper unchanged. A level set that throws during a step (a user's function returning the
// wrong shape) leaves the stepper as it was before the call.
#pragma once

#include "billiard/engine/plane.hpp"
#include "billiard/stepping/level_set.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace billiard::stepping {

// Velocity Verlet ("leapfrog"): v += g dt/2; x += v dt; v += g dt/2. Exact for free flight
// under uniform gravity. Euler: x += v dt; v += g dt; its energy drifts by |g|^2 dt^2 / 2 per step.
enum class Integrator { Leapfrog, Euler };

// The particles at one instant. `parts[i]` is the part of the domain particle i is in (the last
// one it was inside); `reflections[i]` counts its reflections since time 0.
struct StepperState {
  double time = 0.0;
  std::int64_t steps = 0;
  Coordinates positions;
  Velocities velocities;
  std::vector<int> parts;
  std::vector<std::int64_t> reflections;
};

class Stepper {
 public:
  // At most this many reflections in one step for one particle; a particle still outside after
  // them (a corner hit at a grazing angle, a step longer than the domain is wide) stays at its
  // last crossing point for the rest of the step, and unresolved_steps() counts it.
  static constexpr int kMaxReflectionsPerStep = 8;

  // positions and velocities: N by 2, finite; every position strictly inside the domain (some
  // part's omega > 0). dt > 0 and finite; gravity finite. The domain has at least one part.
  Stepper(Domain domain, const Coordinates& positions, const Velocities& velocities, double dt, const Vector& gravity = Vector::Zero(),
          Integrator integrator = Integrator::Leapfrog);

  // n >= 0 steps.
  void step(std::int64_t n = 1);
  // The steps that end at or before `time` (up to 1e-9 of a step, so that a whole number of
  // steps is reached): afterwards time() is in (time - dt, time]. `time` finite and >= time().
  void advance_to(double time);
  // A copy of this stepper back at its initial state: running it again gives the same states
  // (the replay).
  Stepper restarted() const;

  const StepperState& state() const { return state_; }
  const StepperState& initial_state() const { return initial_; }
  double time() const { return state_.time; }
  std::int64_t steps() const { return state_.steps; }
  double dt() const { return dt_; }
  const Vector& gravity() const { return gravity_; }
  Integrator integrator() const { return integrator_; }
  const Domain& domain() const { return domain_; }
  int size() const { return static_cast<int>(state_.positions.rows()); }

  // Unit mass: E_i = |v_i|^2 / 2 - g . x_i, and their sum.
  Eigen::VectorXd energies() const;
  double energy() const;
  double initial_energy() const;
  std::int64_t total_reflections() const;
  // Particle-steps that ended outside the domain after kMaxReflectionsPerStep reflections.
  std::int64_t unresolved_steps() const { return unresolved_steps_; }

 private:
  void one_step(StepperState& s, std::int64_t& unresolved) const;

  Domain domain_;
  double dt_;
  Vector gravity_;
  Integrator integrator_;
  StepperState initial_;
  StepperState state_;
  std::int64_t unresolved_steps_ = 0;
};

// E_i = |v_i|^2 / 2 - g . x_i for each particle of a state (unit mass).
Eigen::VectorXd energies(const StepperState& state, const Vector& gravity);

}  // namespace billiard::stepping
