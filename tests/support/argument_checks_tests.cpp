// Tests of the course's argument checks (lib/src/course/argument_checks.cpp), which every task's
// refusals go through: checks::placement compares each circle with its neighbours only, and must
// report exactly what checking every row against every later one, in row order, reports.
#include "billiard/argument_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>

namespace {

using billiard::Coordinates;

// What placement throws, or nothing.
std::optional<std::string> refusal(double R, double a, const Coordinates& c) {
  try {
    billiard::checks::placement(R, a, c);
  } catch (const std::invalid_argument& error) {
    return std::string(error.what());
  }
  return std::nullopt;
}

// The first failure in row order, found the slow way: (row that sticks out, -1) or the
// overlapping rows (i, j); (-1, -1) when there is none.
std::pair<int, int> first_failure(double R, double a, const Coordinates& c) {
  const double tolerance = 1e-9 * R, reach = R - a + tolerance, diameter = 2 * a - tolerance;
  for (int i = 0; i < c.rows(); ++i) {
    if (c.row(i).squaredNorm() > reach * reach) return {i, -1};
    for (int j = i + 1; j < c.rows(); ++j) {
      if ((c.row(i) - c.row(j)).squaredNorm() < diameter * diameter) return {i, j};
    }
  }
  return {-1, -1};
}

TEST(ArgumentChecks, PlacementReportsTheFirstFailureInRowOrder) {
  std::mt19937_64 rng(17);
  int overlaps = 0, outside = 0, valid = 0;
  for (int round = 0; round < 3000; ++round) {
    const double R = std::uniform_real_distribution<double>(2, 20)(rng);
    const double a = std::uniform_real_distribution<double>(0.05, 1)(rng);
    const int n = std::uniform_int_distribution<int>(0, 40)(rng);
    // Centres spread a little beyond the table, so that some stick out and some overlap.
    std::uniform_real_distribution<double> coordinate(-1.05 * R, 1.05 * R);
    Coordinates c(n, 2);
    for (int i = 0; i < n; ++i) c.row(i) << coordinate(rng), coordinate(rng);
    if (n > 1 && round % 3 == 0) c.row(n - 1) = c.row(round % (n - 1)) + billiard::Vector(a, 0);  // touching: allowed
    const auto [i, j] = first_failure(R, a, c);
    const std::optional<std::string> got = refusal(R, a, c);
    if (i < 0) {
      ++valid;
      EXPECT_FALSE(got) << "round " << round << ": " << *got;
    } else if (j < 0) {
      ++outside;
      ASSERT_TRUE(got) << "round " << round << ": row " << i << " sticks out";
      EXPECT_EQ(got->rfind("coordinates row " + std::to_string(i) + " = (", 0), 0U) << *got;
    } else {
      ++overlaps;
      ASSERT_TRUE(got) << "round " << round << ": rows " << i << " and " << j << " overlap";
      EXPECT_EQ(got->rfind("coordinates rows " + std::to_string(i) + " and " + std::to_string(j) + ":", 0), 0U)
          << *got;
    }
  }
  // Each kind of outcome occurred often enough to count.
  EXPECT_GT(overlaps, 300);
  EXPECT_GT(outside, 300);
  EXPECT_GT(valid, 100);
}

TEST(ArgumentChecks, PlacementOfALargeTableFindsItsOnlyOverlap) {
  // 200,000 circles on a lattice, the last one moved onto a circle near the middle of the rows.
  const int side = 448, n = 200000;
  const double a = 0.5, spacing = 2.5, R = spacing * side;
  Coordinates c(n, 2);
  for (int i = 0; i < n; ++i) c.row(i) << spacing * (i % side - side / 2), spacing * (i / side - side / 2);
  EXPECT_FALSE(refusal(R, a, c));
  c.row(n - 1) = c.row(n / 2) + billiard::Vector(0.3, 0.4);
  const std::optional<std::string> got = refusal(R, a, c);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->rfind("coordinates rows " + std::to_string(n / 2) + " and " + std::to_string(n - 1) + ":", 0), 0U)
      << *got;
}

}  // namespace
