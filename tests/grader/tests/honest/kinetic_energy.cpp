// Task 6, written apart from the reference solution: a correct kinetic_energy and
// correct_energy_drift that the class grader's copy finder must not call a copy.
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace billiard {

double kinetic_energy(int n, const Velocities& velocities) {
  checks::rows(velocities, n, "velocities");
  if (n <= 0) return 0;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    sum += velocities(i, 0) * velocities(i, 0) + velocities(i, 1) * velocities(i, 1);
  }
  return sum / n;
}

void correct_energy_drift(int n, Velocities& velocities, double target_mean_square) {
  checks::rows(velocities, n, "velocities");
  if (std::isnan(target_mean_square) || std::isinf(target_mean_square) || target_mean_square < 0) {
    throw std::invalid_argument("target_mean_square must be finite and at least 0, got " +
                                std::to_string(target_mean_square));
  }
  const double current = kinetic_energy(n, velocities);
  if (current == 0) {
    if (target_mean_square > 0) {
      throw std::invalid_argument("velocities: every circle is at rest, so no factor gives target_mean_square > 0");
    }
    return;
  }
  const double factor = std::sqrt(target_mean_square / current);
  for (int i = 0; i < n; ++i) velocities.row(i) *= factor;
}

}  // namespace billiard
