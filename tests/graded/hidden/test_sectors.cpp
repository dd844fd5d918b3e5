// Instructor-only graded tests of task 9 (`propagate_sectors`), hidden from students: left out
// of the student release, and the grader shows neither their names nor their feedback. They
// hold out states a student cannot tune a solution to, compared step by step with the
// independent oracle (support/oracle.hpp) from a shared state, as in the visible suite (same
// tolerances: 1e-9 of the time, length and speed scales, far above rounding).
#include "graded/sectors_support.hpp"
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/oracle.hpp"
#include "support/student_messages.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {

using billiard::Coordinates;
using billiard::Velocities;
using billiard::testing::SectorTable;
using billiard::testing::text;

const char* const kHint =
    "return what all-pairs propagate returns: wall times, pairs in the 3x3 block, and the pairs found after every "
    "crossing that comes before the earliest collision.";

GRADED_TEST(SectorsHeldOut, RandomTablesAndCellSizesMatchTheOracle, 3, hidden) {
  // 20 tables: radius 2 to 80, 4 to 90 circles at 2% to 30%, cell sizes from 2a to 8a (some
  // with one cell for everything), Gaussian velocities scaled by 0.1 to 10; 50 steps each.
  std::mt19937_64 rng(0x5ec7025ULL);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 20; ++k) {
    const double R = 2 + 78 * unit(rng);
    const int n = 4 + static_cast<int>(86 * unit(rng));
    const double fraction = 0.02 + 0.28 * unit(rng);
    const double a = std::min(R * std::sqrt(fraction / n), 0.45 * R);
    const double cell = k % 7 == 0 ? 2 * R : std::min(2 * a * (1 + 3 * unit(rng)), 2 * R);
    const auto seed = static_cast<std::uint64_t>(91000 + k);
    SectorTable t{R, a, cell, billiard::testing::scattered_circles(R, a, n, seed),
                  billiard::testing::gaussian_velocities(n, seed) * std::pow(10.0, 2 * unit(rng) - 1)};
    if (!billiard::testing::sectors_run_matches_oracle(
            t, 50, text("held-out table ", k, " (R = ", R, ", n = ", n, ", a = ", a, ", cell_size = ", cell, ")"),
            kHint)) {
      return;
    }
  }
}

GRADED_TEST(SectorsHeldOut, GridAlignedMoversMatchTheOracle, 2, hidden) {
  // Circles on cell faces and corners (cell_size = 1, a = 0.45, faces at the integers from -R),
  // moving along the axes, the diagonals and the knight's directions, many at rest: crossings
  // at t = 0, through corners, along faces; 60 steps each. (2a = 0.9 is none of the lattice's
  // distances, so no two paths graze, where rounding alone decides a contact.)
  for (int k = 0; k < 6; ++k) {
    std::mt19937_64 rng(92000 + static_cast<std::uint64_t>(k));
    std::uniform_int_distribution<int> site(-5, 5), direction(-2, 2);
    const double R = 7 + k % 3;
    std::vector<std::pair<int, int>> sites;
    for (int tries = 0; tries < 300 && sites.size() < 24; ++tries) {
      const std::pair<int, int> s{site(rng), site(rng)};
      bool free = std::hypot(s.first, s.second) <= R - 0.45;  // on the table
      for (const auto& o : sites) free = free && std::max(std::abs(o.first - s.first), std::abs(o.second - s.second)) >= 1;
      if (free) sites.push_back(s);
    }
    SectorTable t{R, 0.45, 1, Coordinates(static_cast<Eigen::Index>(sites.size()), 2),
                  Velocities(static_cast<Eigen::Index>(sites.size()), 2)};
    for (int i = 0; i < t.n(); ++i) {
      t.c.row(i) << sites[static_cast<std::size_t>(i)].first, sites[static_cast<std::size_t>(i)].second;
      t.v.row(i) << direction(rng), direction(rng);
      if (i % 3 == 0) t.v.row(i).setZero();
    }
    if (t.v.squaredNorm() == 0) t.v.row(1) << 1, 1;
    if (!billiard::testing::sectors_run_matches_oracle(t, 60, text("held-out grid table ", k, " (R = ", R, ")"), kHint)) {
      return;
    }
  }
}

}  // namespace
