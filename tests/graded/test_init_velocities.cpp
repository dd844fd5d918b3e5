// Graded tests of task 2, init_velocities(n, coordinates, rng): random velocities with random
// directions, no preferred direction (every angle as likely), not all zero. The coordinates come from the test
// fixtures, never from the student's init_billiard.
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/student_messages.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace billiard::testing {
namespace {

constexpr double kR = 10, kA = 1;  // every table here: radius 10, circles of radius 1

std::string call(int n, std::uint64_t seed) {
  return text("init_velocities(", n, ", coordinates, rng) with rng seeded with ", seed);
}

Velocities draw(int n, std::uint64_t seed) {
  const Coordinates coordinates = scattered_circles(kR, kA, n, 77 + static_cast<std::uint64_t>(n));
  Rng rng(seed);
  return init_velocities(n, coordinates, rng);
}

bool check_shape(const Velocities& v, int n, std::uint64_t seed) {
  if (v.rows() != n) {
    ADD_FAILURE() << explain(text(call(n, seed), " to return ", n, " rows, one velocity per circle"),
                             text("it returned ", v.rows(), " rows"),
                             "create the result as Velocities(n, 2) and fill one row (vx, vy) per circle");
    return false;
  }
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    if (!v.row(i).allFinite()) {
      ADD_FAILURE() << explain(text(call(n, seed), " to return finite numbers"), text("row ", i, " is ", row(v, i)),
                               "look for a division by zero (e.g. normalising a zero vector) or a row that is never "
                               "filled in");
      return false;
    }
  }
  return true;
}

// --- Shape -----------------------------------------------------------------------------------

GRADED_TEST(InitVelocities, ReturnsOneFiniteRowPerCircle, 2, visible) {
  for (const int n : {1, 2, 10, 30}) {
    for (const std::uint64_t seed : {1, 2, 3}) {
      if (!check_shape(draw(n, seed), n, seed)) return;
    }
  }
}

GRADED_TEST(InitVelocities, ZeroCirclesGiveNoRows, 2, after_due_date) {
  Rng rng(1);
  const Velocities v = init_velocities(0, Coordinates(0, 2), rng);
  check_shape(v, 0, 1);
}

GRADED_TEST(InitVelocities, VelocitiesAreNotAllZero, 2, visible) {
  for (const int n : {1, 2, 10}) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const Velocities v = draw(n, seed);
      if (!check_shape(v, n, seed)) return;
      if (!(v.cwiseAbs().maxCoeff() > 0)) {
        ADD_FAILURE() << explain(text(call(n, seed), " to give the circles some motion"),
                                 "every velocity was (0, 0)",
                                 "draw a random speed or random components from rng; if you normalise a random "
                                 "vector, check the scale factor is not zero (e.g. integer division)");
        return;
      }
    }
  }
}

// --- Randomness ------------------------------------------------------------------------------

GRADED_TEST(InitVelocities, SameSeedGivesTheSameVelocities, 2, visible) {
  for (const int n : {1, 10}) {
    for (const std::uint64_t seed : {1, 2, 3, 42}) {
      const Velocities first = draw(n, seed), second = draw(n, seed);
      if (!check_shape(first, n, seed) || !check_shape(second, n, seed)) return;
      if (first != second) {
        Eigen::Index i = 0;
        (first - second).rowwise().norm().maxCoeff(&i);
        ADD_FAILURE() << explain(text("two calls of ", call(n, seed), " to give the same velocities"),
                                 text("circle ", i, " got ", row(first, i), " the first time and ", row(second, i),
                                      " the second time"),
                                 "draw every random number from the generator `rng` you are given; do not use "
                                 "std::random_device, rand() or the time, and do not make your own generator");
        return;
      }
    }
  }
}

GRADED_TEST(InitVelocities, DifferentSeedsGiveDifferentVelocities, 2, after_due_date) {
  const int n = 10;
  std::vector<Velocities> draws;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    draws.push_back(draw(n, seed));
    if (!check_shape(draws.back(), n, seed)) return;
  }
  for (std::size_t i = 0; i < draws.size(); ++i) {
    for (std::size_t j = i + 1; j < draws.size(); ++j) {
      if (draws[i] == draws[j]) {
        ADD_FAILURE() << explain("different seeds of rng to give different velocities",
                                 text("seeds ", i + 1, " and ", j + 1, " gave the same velocities, e.g. circle 0 got ",
                                      row(draws[i], 0)),
                                 "the velocities must be random: draw them from `rng`");
        return;
      }
    }
  }
}

GRADED_TEST(InitVelocities, RepeatedCallsWithOneGeneratorGiveDifferentVelocities, 2, visible) {
  const int n = 10;
  const Coordinates coordinates = scattered_circles(kR, kA, n, 5);
  Rng rng(7);
  const Velocities first = init_velocities(n, coordinates, rng);
  const Velocities second = init_velocities(n, coordinates, rng);
  if (!check_shape(first, n, 7) || !check_shape(second, n, 7)) return;
  EXPECT_TRUE(first != second) << explain(
      "two calls of init_velocities(10, coordinates, rng) with the same generator object to give different velocities",
      text("both gave the same velocities, e.g. circle 0 got ", row(first, 0)),
      "use the generator `rng` itself (it is passed by reference); do not copy it (Rng copy = rng;) or re-seed it");
}

GRADED_TEST(InitVelocities, DifferentCirclesGetDifferentVelocities, 2, visible) {
  const int n = 20;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Velocities v = draw(n, seed);
    if (!check_shape(v, n, seed)) return;
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index j = i + 1; j < n; ++j) {
        if (v.row(i) == v.row(j)) {
          ADD_FAILURE() << explain(text(call(n, seed), " to give each circle its own random velocity"),
                                   text("circles ", i, " and ", j, " both got ", row(v, i)),
                                   "draw new random numbers for every circle inside the loop (not once before it), "
                                   "from continuous distributions rather than a few fixed directions");
          return;
        }
      }
    }
  }
}

// --- No preferred direction ------------------------------------------------------------------
// Statistics over S = 4000 seeds of n = 10 circles. The seeds are independent, the circles of
// one seed need not be (a solution may, e.g., remove the total momentum), so each seed gives
// one sample (its mean velocity, or its fraction of circles in a quadrant) and the standard
// error is the measured standard deviation of these samples over sqrt(S). Bounds are 5
// standard errors (plus 1e-9 of the scale, for solutions whose samples are all exactly equal).

constexpr int kStatisticsCircles = 10;
constexpr int kStatisticsSeeds = 4000;

// x rounded to `digits` decimals, for messages.
double round_to(double x, int digits) {
  const double scale = std::pow(10.0, digits);
  return std::round(x * scale) / scale;
}

std::vector<Velocities> many_draws() {
  std::vector<Velocities> draws;
  draws.reserve(kStatisticsSeeds);
  const Coordinates coordinates = scattered_circles(kR, kA, kStatisticsCircles, 99);
  for (int k = 0; k < kStatisticsSeeds; ++k) {
    const std::uint64_t seed = 1000 + static_cast<std::uint64_t>(k);
    Rng rng(seed);
    draws.push_back(init_velocities(kStatisticsCircles, coordinates, rng));
    if (!check_shape(draws.back(), kStatisticsCircles, seed)) return {};
  }
  return draws;
}

GRADED_TEST(InitVelocities, MeanVelocityIsZero, 3, visible) {
  // For velocities with no preferred direction E[v] = 0. The bound for each component is 5
  // standard errors of the mean; for independent, unit-variance components it is about
  // 5 / sqrt(S n) = 0.008 of the rms speed.
  const auto draws = many_draws();
  if (draws.empty()) return;
  const double S = kStatisticsSeeds;
  std::array<double, 2> sum{0, 0}, sum2{0, 0};
  double speed2 = 0;
  for (const Velocities& v : draws) {
    for (int axis = 0; axis < 2; ++axis) {
      const double m = v.col(axis).mean();
      sum[axis] += m;
      sum2[axis] += m * m;
    }
    speed2 += v.rowwise().squaredNorm().mean() / S;
  }
  const double rms = std::sqrt(speed2);
  for (int axis = 0; axis < 2; ++axis) {
    const double mean = sum[axis] / S;
    const double sd = std::sqrt(std::max(0.0, sum2[axis] / S - mean * mean));
    const double bound = 5 * sd / std::sqrt(S) + 1e-9 * rms;
    EXPECT_LE(std::abs(mean), bound) << explain(
        text("velocities with no preferred direction: over ", kStatisticsSeeds, " seeds of ", kStatisticsCircles,
             " circles the mean ", axis == 0 ? "vx" : "vy", " is 0 within ", bound, " (the rms speed is ", rms, ")"),
        text("the mean ", axis == 0 ? "vx" : "vy", " was ", mean, ", i.e. ", mean / rms, " of the rms speed"),
        "draw each component symmetrically around 0 (e.g. std::normal_distribution<double>(0, 1), or a uniform "
        "angle in [0, 2 pi) with cos and sin); a range like [0, 1] makes every circle move the same way");
  }
}

GRADED_TEST(InitVelocities, DirectionsFallInTheFourQuadrantsEquallyOften, 2, after_due_date) {
  // Each quadrant of direction (signs of vx and vy) has probability 1/4. Per seed, the fraction
  // of the 10 circles in a quadrant has standard deviation about sqrt(1/4 * 3/4 / 10) = 0.14,
  // so over S = 4000 seeds the bound 5 standard errors is about 0.011.
  const auto draws = many_draws();
  if (draws.empty()) return;
  const double S = kStatisticsSeeds;
  std::array<double, 4> sum{0, 0, 0, 0}, sum2{0, 0, 0, 0};
  for (const Velocities& v : draws) {
    std::array<double, 4> fraction{0, 0, 0, 0};
    for (Eigen::Index i = 0; i < v.rows(); ++i) {
      fraction[(v(i, 0) < 0 ? 1 : 0) + (v(i, 1) < 0 ? 2 : 0)] += 1.0 / kStatisticsCircles;
    }
    for (int q = 0; q < 4; ++q) {
      sum[q] += fraction[q];
      sum2[q] += fraction[q] * fraction[q];
    }
  }
  const char* names[4] = {"vx > 0, vy > 0", "vx < 0, vy > 0", "vx > 0, vy < 0", "vx < 0, vy < 0"};
  for (int q = 0; q < 4; ++q) {
    const double mean = sum[q] / S;
    const double sd = std::sqrt(std::max(0.0, sum2[q] / S - mean * mean));
    const double bound = 5 * sd / std::sqrt(S) + 1e-9;
    EXPECT_NEAR(mean, 0.25, bound) << explain(
        text("each quadrant of direction to hold 1/4 of the velocities over ", kStatisticsSeeds, " seeds (within ",
             bound, ")"),
        text("the quadrant ", names[q], " held a fraction ", mean),
        "the direction must be uniformly random over the full circle: e.g. an angle uniform in [0, 2 pi) (not "
        "[0, pi) or [0, 90)), or both components symmetric around 0");
  }
}

GRADED_TEST(InitVelocities, DirectionsAreAsCommonNearTheDiagonalsAsNearTheAxes, 2, visible) {
  // No preferred direction means every angle is as likely: each of 8 sectors of 45 degrees,
  // centred on the axes (0, 90, 180, 270 degrees) and on the diagonals (45, 135, ...), holds
  // 1/8 of the directions. Per seed, the fraction of the 10 circles in a sector has standard
  // deviation about sqrt(1/8 * 7/8 / 10) = 0.10, so over S = 4000 seeds the bound 5 standard
  // errors is about 0.008. Components uniform in a square put 0.146 near each diagonal and
  // 0.104 near each axis (the square's corners reach sqrt(2) times further than its sides).
  const auto draws = many_draws();
  if (draws.empty()) return;
  const double S = kStatisticsSeeds;
  constexpr int kSectors = 8;
  const double sector_angle = 2 * std::acos(-1.0) / kSectors;
  std::array<double, kSectors> sum{}, sum2{};
  for (const Velocities& v : draws) {
    std::array<double, kSectors> fraction{};
    for (Eigen::Index i = 0; i < v.rows(); ++i) {
      const double angle = std::atan2(v(i, 1), v(i, 0)) + sector_angle / 2;  // sector 0 is centred on +x
      const int sector = static_cast<int>(std::floor(angle / sector_angle) + kSectors) % kSectors;
      fraction[static_cast<std::size_t>(sector)] += 1.0 / kStatisticsCircles;
    }
    for (std::size_t k = 0; k < kSectors; ++k) {
      sum[k] += fraction[k];
      sum2[k] += fraction[k] * fraction[k];
    }
  }
  // Each sector's fraction, and the sector furthest from 1/8 in standard errors.
  std::array<double, kSectors> mean{};
  std::size_t worst = 0;
  double worst_bound = 0, worst_excess = 0, axes = 0, diagonals = 0;
  for (std::size_t k = 0; k < kSectors; ++k) {
    mean[k] = sum[k] / S;
    const double sd = std::sqrt(std::max(0.0, sum2[k] / S - mean[k] * mean[k]));
    const double bound = 5 * sd / std::sqrt(S) + 1e-9;
    const double excess = std::abs(mean[k] - 1.0 / kSectors) / bound;
    if (excess > worst_excess) worst = k, worst_bound = bound, worst_excess = excess;
    (k % 2 == 0 ? axes : diagonals) += mean[k] / (kSectors / 2);
  }
  if (worst_excess <= 1) return;
  std::string fractions;
  for (std::size_t k = 0; k < kSectors; ++k) fractions += text(k ? ", " : "", k * 45, ": ", round_to(mean[k], 3));
  // The square's mark: more directions near all four diagonals than near the axes.
  const bool square = diagonals - axes > 2 * worst_bound;
  ADD_FAILURE() << explain(
      text("every direction to be as likely: each 45-degree sector around an axis or a diagonal holds 1/8 = 0.125 of ",
           "the velocities, over ", kStatisticsSeeds, " seeds (within ", round_to(worst_bound, 4), ")"),
      text("the fractions around 0, 45, 90, ... 315 degrees were ", fractions,
           square ? text(" (near the diagonals ", round_to(diagonals, 3), " each, near the axes ", round_to(axes, 3), ")")
                  : text(" (", worst * 45, " degrees is the furthest off)")),
      square ? "drawing vx and vy each uniformly in [-1, 1] fills a square, and a square favours the diagonals: its "
               "corners reach sqrt(2) times further than its sides, so directions near a diagonal come up to twice as "
               "often. Draw each component from std::normal_distribution<double>(0, 1) (its 2-D density depends only "
               "on the speed), or draw an angle uniform in [0, 2 pi) and a speed, and use cos and sin"
             : "the direction must be uniformly random over the full circle: draw an angle uniform in [0, 2 pi) "
               "(not a few fixed angles), or each component from std::normal_distribution<double>(0, 1)");
}

// --- Invalid arguments -------------------------------------------------------------------------

GRADED_TEST(InitVelocities, RejectsCoordinatesWithWrongRowCount, 1, after_due_date) {
  struct Case {
    int n;
    int rows;
  };
  for (const Case c : {Case{3, 2}, Case{3, 4}, Case{0, 1}}) {
    const Coordinates coordinates = scattered_circles(kR, kA, c.rows, 3);
    expect_invalid_argument(
        [&] {
          Rng rng(1);
          init_velocities(c.n, coordinates, rng);
        },
        text("n = ", c.n, " with coordinates of ", c.rows, " rows"), "coordinates",
        "check coordinates.rows() == n at the start and throw std::invalid_argument naming `coordinates` "
        "otherwise");
  }
}

GRADED_TEST(InitVelocities, RejectsNegativeNumberOfCircles, 1, after_due_date) {
  for (const int n : {-1, -4}) {
    expect_invalid_argument(
        [&] {
          Rng rng(1);
          init_velocities(n, Coordinates(0, 2), rng);
        },
        text("n = ", n), "n", "check n >= 0 at the start and throw std::invalid_argument naming n otherwise");
  }
}

}  // namespace
}  // namespace billiard::testing
