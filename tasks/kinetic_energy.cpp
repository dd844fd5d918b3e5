// Task 6: kinetic_energy and correct_energy_drift -- is energy conserved?
//
// Write both functions below (declared in lib/include/billiard/course.hpp).
//
// kinetic_energy: the mean squared velocity <v^2> = (1/n) sum_i (vx_i^2 + vy_i^2): a mean,
// not a sum, so that tables with different n can be compared. Return 0 for n = 0. Check the
// arguments:  checks::rows(velocities, n, "velocities");
// Elastic collisions conserve it exactly; on a computer it changes by rounding only, about
// 1e-16 per collision. The `billiard` command prints its relative drift.
//
// correct_energy_drift: multiply every velocity by the same factor s so that <v^2> becomes
// target_mean_square. Multiplying all velocities by s multiplies <v^2> by s^2, so
// s = sqrt(target / now). Directions do not change. Throw std::invalid_argument if the target
// is negative or not finite, or if all circles are at rest and the target is positive.
//
// Run this task's tests:   ./build.sh test -L kinetic_energy
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

double kinetic_energy(int n, const Velocities& velocities) {
  // Delete these two lines and write the task.
  throw NotImplemented(6, "kinetic_energy", "tasks/kinetic_energy.cpp");
  (void)n, (void)velocities;
}

void correct_energy_drift(int n, Velocities& velocities, double target_mean_square) {
  // Delete these two lines and write the task.
  throw NotImplemented(6, "correct_energy_drift", "tasks/kinetic_energy.cpp");
  (void)n, (void)velocities, (void)target_mean_square;
}

}  // namespace billiard
