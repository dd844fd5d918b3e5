// Instructor-only graded tests of task 6 (`kinetic_energy`, `correct_energy_drift`), hidden
// from students (left out of the student release; the grader shows neither their names nor
// their feedback). Expected values are computed here in long double; 1e-12 relative covers
// the rounding of a sum of up to 5,000 squares in double.
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/student_messages.hpp"

#include <cmath>
#include <cstdint>

namespace {

using billiard::Velocities;
using billiard::testing::explain;
using billiard::testing::text;

double mean_square(const Velocities& v) {
  long double sum = 0;
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    sum += static_cast<long double>(v(i, 0)) * v(i, 0) + static_cast<long double>(v(i, 1)) * v(i, 1);
  }
  return static_cast<double>(sum / static_cast<long double>(v.rows()));
}

GRADED_TEST(KineticEnergy, HeldOutSizesAndScales, 2, hidden) {
  // Mean square and correction for sizes and speed scales the visible tests do not use.
  const int sizes[] = {2, 3, 64, 5000};
  const double scales[] = {1e-3, 0.7, 250.0, 3e4};
  for (int k = 0; k < 4; ++k) {
    const int n = sizes[k];
    Velocities v = billiard::testing::gaussian_velocities(n, 777 + static_cast<std::uint64_t>(k)) * scales[k];
    const double expected = mean_square(v);
    const double got = billiard::kinetic_energy(n, v);
    EXPECT_NEAR(got, expected, 1e-12 * expected)
        << explain(text("<v^2> = ", expected, " for ", n, " velocities of scale ", scales[k]), text("returned ", got),
                   "<v^2> is the mean of vx^2 + vy^2 over the circles.");

    const Velocities before = v;
    const double target = 0.5 * expected + 1.0;
    billiard::correct_energy_drift(n, v, target);
    EXPECT_NEAR(mean_square(v), target, 1e-12 * target)
        << explain(text("<v^2> = ", target, " after correct_energy_drift"), text("<v^2> is ", mean_square(v)),
                   "multiply every velocity by sqrt(target / current).");
    const double factor = std::sqrt(target / expected);
    EXPECT_LE((v - before * factor).cwiseAbs().maxCoeff(), 1e-12 * factor * before.cwiseAbs().maxCoeff())
        << explain("every velocity multiplied by the same factor", "the directions or ratios changed",
                   "rescale all velocities by one common factor; do not change their directions.");
  }
}

}  // namespace
