// Mutant of task init_velocities: the random velocity is drawn once, before the loop, so every circle gets the same velocity.
// Expected: loses points in init_velocities (e.g. InitVelocities.DifferentCirclesGetDifferentVelocities fails; 1 of 11 tests fail).
//
// Task 2, reference solution with the one bug above: random velocities.
//
// Each velocity component is drawn from a normal distribution with mean 0 and standard
// deviation 1. This is the 2D Maxwell-Boltzmann distribution (temperature kT/m = 1), so the
// gas starts in equilibrium, no direction is preferred, and <v^2> is about 2. Any symmetric
// distribution would do: collisions drive the speeds to Maxwell-Boltzmann anyway.
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"

namespace billiard {

Velocities init_velocities(int n, const Coordinates& coordinates, Rng& rng) {
  checks::count(n);
  checks::rows(coordinates, n, "coordinates");
  std::normal_distribution<double> component(0.0, 1.0);
  Velocities velocities(n, 2);
  const double vx = component(rng), vy = component(rng);
  for (int i = 0; i < n; ++i) {
    velocities(i, 0) = vx;
    velocities(i, 1) = vy;
  }
  return velocities;
}

}  // namespace billiard
