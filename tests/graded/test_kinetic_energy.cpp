// Graded tests of task 6: `kinetic_energy` (the mean squared velocity <v^2>) and
// `correct_energy_drift` (rescaling all velocities to a target <v^2>).
//
// The tests use only these two functions: velocities are written by hand or come from the
// fixtures, drifting velocities are made by hand, and every expected mean square is computed
// here (in long double), never with the student's kinetic_energy. Tolerances are for rounding
// only: a sum of n squares in double is exact to about n * 1e-16 relative, so 1e-12 relative
// is ample for the sizes used here (n <= 1000).
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/student_messages.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace {

using billiard::Velocities;
using billiard::testing::explain;
using billiard::testing::expect_invalid_argument;
using billiard::testing::row;
using billiard::testing::text;

// Relative rounding tolerance (see the top of the file).
constexpr double kRel = 1e-12;

// (1/n) sum |v_i|^2, computed independently in long double.
double mean_square(const Velocities& v) {
  if (v.rows() == 0) return 0;
  long double sum = 0;
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    sum += static_cast<long double>(v(i, 0)) * v(i, 0) + static_cast<long double>(v(i, 1)) * v(i, 1);
  }
  return static_cast<double>(sum / static_cast<long double>(v.rows()));
}

const char* const kHintMean =
    "<v^2> is the mean over the circles of the squared speed: add vx^2 + vy^2 over all circles, then divide by n.";

// ---------------------------------------------------------------------------------------------
// kinetic_energy

// The hint for a wrong <v^2> of n circles whose right value is `mean`: the two common slips by
// name (the sum instead of the mean; the 1/2 of the kinetic energy), otherwise the definition.
std::string mean_square_hint(double got, double mean, int n) {
  if (std::abs(got - n * mean) <= 1e-9 * n * mean) {
    return "you returned the sum of the squared speeds; <v^2> is their mean, so divide by n.";
  }
  if (std::abs(got - mean / 2) <= 1e-9 * mean) {
    return "you returned half of <v^2>: kinetic_energy returns the mean squared speed itself, without the 1/2 of "
           "the kinetic energy m v^2 / 2.";
  }
  return kHintMean;
}

GRADED_TEST(KineticEnergy, TwoCirclesByHand, 2, visible) {
  // (3^2 + 4^2 + 0 + 0) / 2 = 12.5
  Velocities v(2, 2);
  v << 3, 4, 0, 0;
  const double got = billiard::kinetic_energy(2, v);
  EXPECT_NEAR(got, 12.5, kRel * 12.5) << explain("<v^2> = (3^2 + 4^2 + 0^2 + 0^2) / 2 = 12.5 for velocities (3, 4) and (0, 0)",
                                                 text("returned ", got),
                                                 mean_square_hint(got, 12.5, 2));
}

GRADED_TEST(KineticEnergy, DividesByTheNumberOfCircles, 3, after_due_date) {
  // Four circles of speed 1 and 2: (1 + 1 + 4 + 4) / 4 = 2.5, not the sum 10.
  Velocities v(4, 2);
  v << 1, 0, 0, -1, 2, 0, 0, 2;
  const double got = billiard::kinetic_energy(4, v);
  EXPECT_NEAR(got, 2.5, kRel * 2.5) << explain("the mean <v^2> = (1 + 1 + 4 + 4) / 4 = 2.5", text("returned ", got),
                                               mean_square_hint(got, 2.5, 4));
}

GRADED_TEST(KineticEnergy, SquaresTheSpeeds, 2, after_due_date) {
  // One circle with velocity (3, 4): |v|^2 = 25, not |v| = 5.
  Velocities v(1, 2);
  v << 3, 4;
  const double got = billiard::kinetic_energy(1, v);
  EXPECT_NEAR(got, 25, kRel * 25) << explain("<v^2> = 3^2 + 4^2 = 25 for a single circle with velocity (3, 4)",
                                             text("returned ", got),
                                             std::abs(got - 5) < 1e-9
                                                 ? "you averaged the speeds |v|; the task asks for the squared speeds "
                                                   "|v|^2 = vx^2 + vy^2 (no square root)."
                                                 : kHintMean);
}

GRADED_TEST(KineticEnergy, MatchesDirectSumForRandomVelocities, 2, after_due_date) {
  for (const int n : {1, 7, 1000}) {
    Velocities v = billiard::testing::gaussian_velocities(n, 60 + static_cast<unsigned>(n));
    v *= 3.5;
    const double expected = mean_square(v);
    const double got = billiard::kinetic_energy(n, v);
    EXPECT_NEAR(got, expected, kRel * expected)
        << explain(text("<v^2> = ", expected, " for ", n, " random velocities"), text("returned ", got), kHintMean);
  }
}

GRADED_TEST(KineticEnergy, ZeroForNoCircles, 2, after_due_date) {
  const Velocities v(0, 2);
  const double got = billiard::kinetic_energy(0, v);
  EXPECT_EQ(got, 0.0) << explain("0 for n = 0 (no circles, no energy)", text("returned ", got),
                                 "dividing the empty sum 0 by n = 0 gives NaN: return 0 when n == 0.");
}

GRADED_TEST(KineticEnergy, ZeroForCirclesAtRest, 2, after_due_date) {
  const Velocities v = Velocities::Zero(5, 2);
  const double got = billiard::kinetic_energy(5, v);
  EXPECT_EQ(got, 0.0) << explain("0 for five circles at rest", text("returned ", got), kHintMean);
}

GRADED_TEST(KineticEnergy, RejectsRowCountMismatch, 1, after_due_date) {
  Velocities v(3, 2);
  v << 1, 0, 0, 1, 1, 1;
  expect_invalid_argument([&] { billiard::kinetic_energy(2, v); }, "velocities with 3 rows for n = 2", "velocities",
                          "check velocities.rows() == n and throw std::invalid_argument naming `velocities`.");
}

GRADED_TEST(KineticEnergy, RejectsNegativeN, 1, after_due_date) {
  const Velocities v(0, 2);
  expect_invalid_argument([&] { billiard::kinetic_energy(-1, v); }, "n = -1", "n",
                          "a negative number of circles is invalid: check n >= 0 first.");
}

// ---------------------------------------------------------------------------------------------
// correct_energy_drift

GRADED_TEST(CorrectEnergyDrift, ReachesTheTargetMeanSquare, 2, visible) {
  for (const double target : {2.5, 1e-4, 7e3}) {
    Velocities v = billiard::testing::gaussian_velocities(100, 62);
    billiard::correct_energy_drift(100, v, target);
    const double got = mean_square(v);
    EXPECT_NEAR(got, target, kRel * target)
        << explain(text("<v^2> = ", target, " after correct_energy_drift(100, v, ", target, ")"),
                   text("<v^2> afterwards is ", got),
                   "multiply every velocity by s = sqrt(target / <v^2>_now): that multiplies <v^2> by s^2.");
  }
}

GRADED_TEST(CorrectEnergyDrift, ScalesBySquareRootOfTheRatio, 3, after_due_date) {
  // <v^2> = (1 + 1) / 2 = 1; to reach 4 every velocity doubles: (2, 0) and (0, 2).
  Velocities v(2, 2);
  v << 1, 0, 0, 1;
  billiard::correct_energy_drift(2, v, 4);
  const double error = std::max(std::hypot(v(0, 0) - 2, v(0, 1)), std::hypot(v(1, 0), v(1, 1) - 2));
  EXPECT_LE(error, kRel) << explain(
      "velocities (1, 0) and (0, 1) (<v^2> = 1) rescaled to <v^2> = 4 to become (2, 0) and (0, 2)",
      text("they became ", row(v, 0), " and ", row(v, 1)),
      std::abs(v(0, 0) - 4) < 1e-9 ? "you multiplied by target / now = 4; <v^2> grows with the square of the factor, "
                                     "so the factor is sqrt(target / now) = 2."
                                   : "multiply every velocity by the same factor sqrt(target / now).");
}

GRADED_TEST(CorrectEnergyDrift, KeepsEveryDirection, 2, after_due_date) {
  Velocities v = billiard::testing::gaussian_velocities(50, 63);
  v.row(7).setZero();  // a circle at rest stays at rest
  const Velocities before = v;
  const double now = mean_square(before);
  const double target = 0.37;
  billiard::correct_energy_drift(50, v, target);
  const double factor = std::sqrt(target / now);
  for (int i = 0; i < 50; ++i) {
    // Each new velocity must be factor * old one: same direction, same sign, same factor.
    const double error = (v.row(i) - factor * before.row(i)).norm();
    if (!(error <= kRel * factor * (before.row(i).norm() + std::sqrt(now)))) {
      ADD_FAILURE() << explain(
          text("circle ", i, "'s velocity ", row(before, i), " to become sqrt(target / now) * v = ",
               row(Velocities(factor * before), i), " (factor ", factor, ")"),
          text("it became ", row(v, i)),
          "rescale every velocity by the same positive factor: directions must not change (no rotation, no sign "
          "flip), and circles at rest stay at rest.");
      return;
    }
  }
}

GRADED_TEST(CorrectEnergyDrift, TargetZeroStopsAllCircles, 2, after_due_date) {
  Velocities v = billiard::testing::gaussian_velocities(10, 64);
  billiard::correct_energy_drift(10, v, 0);
  EXPECT_TRUE(v.isZero(0)) << explain("all velocities exactly 0 for target_mean_square = 0",
                                      text("the largest remaining speed is ", v.rowwise().norm().maxCoeff()),
                                      "the factor sqrt(0 / now) is 0: every velocity becomes (0, 0).");
}

GRADED_TEST(CorrectEnergyDrift, NoCirclesWithTargetZeroIsFine, 2, after_due_date) {
  Velocities v(0, 2);
  try {
    billiard::correct_energy_drift(0, v, 0);
  } catch (const std::invalid_argument& error) {
    ADD_FAILURE() << explain("n = 0 with target_mean_square = 0 to be accepted (nothing to rescale)",
                             text("threw std::invalid_argument: \"", error.what(), "\""),
                             "with no circles <v^2> is 0, which already equals the target 0; do not divide 0 by 0.");
  }
  EXPECT_EQ(v.rows(), 0) << explain("the velocities to stay an empty array",
                                    text("they now have ", v.rows(), " rows"), "do not resize the velocities.");
}

GRADED_TEST(CorrectEnergyDrift, RestoresVelocitiesAfterSmallDrift, 2, after_due_date) {
  // Rounding makes <v^2> drift; here every velocity is too large by a known 1e-6 relative.
  const Velocities original = billiard::testing::gaussian_velocities(200, 65);
  const double target = mean_square(original);
  Velocities v = original * (1 + 1e-6);
  billiard::correct_energy_drift(200, v, target);
  const double got = mean_square(v);
  EXPECT_NEAR(got, target, kRel * target)
      << explain(text("<v^2> back at the original ", target, " after a drift of 1e-6"),
                 text("<v^2> afterwards is ", got), "multiply every velocity by sqrt(target / now).");
  const double difference = (v - original).norm() / original.norm();
  EXPECT_LE(difference, kRel) << explain(
      "the velocities to return to the original ones (they had all been scaled by 1 + 1e-6)",
      text("they differ by ", difference, " relative"), "rescale all velocities by one common factor.");
}

GRADED_TEST(CorrectEnergyDrift, CorrectsSinglePrecisionRounding, 2, after_due_date) {
  // Velocities rounded to float (about 1e-7 relative error each, in random directions) have a
  // slightly wrong <v^2>; the correction restores the double-precision target.
  const Velocities original = billiard::testing::gaussian_velocities(500, 66) * 1.7;
  const double target = mean_square(original);
  Velocities v = original.cast<float>().cast<double>();
  const Velocities rounded = v;
  billiard::correct_energy_drift(500, v, target);
  const double got = mean_square(v);
  EXPECT_NEAR(got, target, kRel * target) << explain(
      text("<v^2> = ", target, " after correcting velocities rounded to float (their <v^2> was ", mean_square(rounded),
           ")"),
      text("<v^2> afterwards is ", got), "multiply every velocity by sqrt(target / now), computed in double.");
}

GRADED_TEST(CorrectEnergyDrift, RejectsNegativeTarget, 1, after_due_date) {
  Velocities v = billiard::testing::gaussian_velocities(3, 67);
  expect_invalid_argument([&] { billiard::correct_energy_drift(3, v, -1); }, "target_mean_square = -1",
                          "target_mean_square",
                          "a mean of squares cannot be negative: check target_mean_square >= 0 and name it in the "
                          "message.");
}

GRADED_TEST(CorrectEnergyDrift, RejectsNonFiniteTarget, 1, after_due_date) {
  for (const double target : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Velocities v = billiard::testing::gaussian_velocities(3, 68);
    expect_invalid_argument([&] { billiard::correct_energy_drift(3, v, target); },
                            text("target_mean_square = ", target), "target_mean_square",
                            "check std::isfinite(target_mean_square): NaN fails every comparison, so `target < 0` "
                            "alone lets it through.");
  }
}

GRADED_TEST(CorrectEnergyDrift, RejectsPositiveTargetWhenAllAtRest, 1, after_due_date) {
  Velocities v = Velocities::Zero(4, 2);
  expect_invalid_argument([&] { billiard::correct_energy_drift(4, v, 1); },
                          "a positive target_mean_square while all circles are at rest", "",
                          "no factor turns zero velocities into moving ones (and sqrt(target / 0) is infinite): "
                          "throw std::invalid_argument.");
}

GRADED_TEST(CorrectEnergyDrift, RejectsRowCountMismatch, 1, after_due_date) {
  Velocities v = billiard::testing::gaussian_velocities(3, 69);
  expect_invalid_argument([&] { billiard::correct_energy_drift(2, v, 1); }, "velocities with 3 rows for n = 2",
                          "velocities", "check velocities.rows() == n and name `velocities` in the message.");
}

GRADED_TEST(CorrectEnergyDrift, RejectsNegativeN, 1, after_due_date) {
  Velocities v(0, 2);
  expect_invalid_argument([&] { billiard::correct_energy_drift(-2, v, 1); }, "n = -2", "n",
                          "a negative number of circles is invalid: check n >= 0 first.");
}

}  // namespace
