// Mutant of task init_velocities: both components are drawn uniformly from [0, 1), so every circle moves up and to the right.
// Expected: loses points in init_velocities (e.g. InitVelocities.MeanVelocityIsZero fails; 2 of 11 tests fail).
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
  std::uniform_real_distribution<double> component(0.0, 1.0);
  Velocities velocities(n, 2);
  for (int i = 0; i < n; ++i) {
    velocities(i, 0) = component(rng);
    velocities(i, 1) = component(rng);
  }
  return velocities;
}

}  // namespace billiard
