// Mutant of task kinetic_energy: correct_energy_drift multiplies the velocities by sqrt(now / target), the inverse of the right factor.
// Expected: loses points in kinetic_energy (e.g. CorrectEnergyDrift.ReachesTheTargetMeanSquare fails; 6 of 20 tests fail).
//
// Task 6, reference solution with the one bug above: the mean squared velocity and the energy-drift correction.
//
// With unit masses the kinetic energy per circle is <v^2> / 2, so the mean squared velocity
// <v^2> = (1/n) sum_i |v_i|^2 measures the energy. Elastic collisions conserve it exactly; in
// floating point it wanders by rounding (about 1e-16 per event in double precision).
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace billiard {

double kinetic_energy(int n, const Velocities& velocities) {
  checks::rows(velocities, n, "velocities");
  if (n == 0) return 0.0;  // no circles, no energy
  return velocities.squaredNorm() / n;  // squaredNorm() sums the squares of all entries
}

// Multiplying every velocity by s multiplies <v^2> by s^2, so s = sqrt(target / now) restores
// the target exactly while every circle keeps its direction.
void correct_energy_drift(int n, Velocities& velocities, double target_mean_square) {
  checks::rows(velocities, n, "velocities");
  if (!(std::isfinite(target_mean_square) && target_mean_square >= 0)) {
    std::ostringstream message;
    message << "target_mean_square = " << target_mean_square << ": must be a finite number >= 0";
    throw std::invalid_argument(message.str());
  }
  const double now = kinetic_energy(n, velocities);
  if (now == 0) {
    if (target_mean_square == 0) return;  // already there
    throw std::invalid_argument(
        "velocities: all circles are at rest, so no rescaling can reach target_mean_square > 0");
  }
  velocities *= std::sqrt(now / target_mean_square);
}

}  // namespace billiard
