// Graded tests of task 1, init_billiard(table_radius, circle_radius, n, rng): random,
// non-overlapping circles fully inside the table. The tests check properties and statistics
// that every correct solution has, never particular random numbers.
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/student_messages.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace billiard::testing {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

struct Table {
  double R;  // table radius
  double a;  // circle radius
  int n;     // number of circles
};

// Tables with area fractions n a^2 / R^2 up to 0.3, of several sizes.
const std::vector<Table> kTables = {{10, 1, 1},   {10, 1, 2},      {10, 1, 10},  {10, 1, 30}, {5, 1, 6},
                                    {10, 2, 5},  {1, 0.05, 40},   {100, 3, 60}, {3.5, 0.25, 20}};
const std::vector<std::uint64_t> kSeeds = {1, 2, 3, 42, 20240611};

std::string call(const Table& t, std::uint64_t seed) {
  return text("init_billiard(", t.R, ", ", t.a, ", ", t.n, ", rng) with rng seeded with ", seed);
}

Coordinates place(const Table& t, std::uint64_t seed) {
  Rng rng(seed);
  return init_billiard(t.R, t.a, t.n, rng);
}

// Shape n x 2 and finite numbers; adds a failure and returns false otherwise.
bool check_shape(const Coordinates& c, const Table& t, std::uint64_t seed) {
  if (c.rows() != t.n) {
    ADD_FAILURE() << explain(text(call(t, seed), " to return ", t.n, " rows, one per circle"),
                             text("it returned ", c.rows(), " rows"),
                             "create the result as Coordinates(n, 2) and fill one row per circle");
    return false;
  }
  for (Eigen::Index i = 0; i < c.rows(); ++i) {
    if (!c.row(i).allFinite()) {
      ADD_FAILURE() << explain(text(call(t, seed), " to return finite numbers"),
                               text("row ", i, " is ", row(c, i)),
                               "look for a division by zero or a row that is never filled in");
      return false;
    }
  }
  return true;
}

// Every circle fully inside the table and no two overlapping, up to rounding (1e-9 R), as the
// contract says; adds a failure and returns false otherwise.
bool check_inside(const Coordinates& c, const Table& t, std::uint64_t seed) {
  int which = -1;
  const double protrusion = worst_protrusion(c, t.R, t.a, &which);
  if (protrusion > 1e-9 * t.R) {
    ADD_FAILURE() << explain(
        text(call(t, seed), " to place every circle fully inside the table: |r_i| <= table_radius - circle_radius = ",
             t.R - t.a),
        text("circle ", which, " at ", row(c, which), " has |r| = ", c.row(which).norm(), ", so it sticks out by ",
             protrusion),
        "the centre must stay circle_radius away from the wall: draw centres inside the disc of radius "
        "table_radius - circle_radius, not table_radius");
    return false;
  }
  return true;
}

bool check_no_overlap(const Coordinates& c, const Table& t, std::uint64_t seed) {
  int i = -1, j = -1;
  const double overlap = worst_overlap(c, t.a, &i, &j);
  if (overlap > 1e-9 * t.R) {
    ADD_FAILURE() << explain(
        text(call(t, seed), " to place circles that do not overlap: centres at least 2 circle_radius = ", 2 * t.a,
             " apart"),
        text("circles ", i, " at ", row(c, i), " and ", j, " at ", row(c, j), " are only ",
             (c.row(i) - c.row(j)).norm(), " apart"),
        "before accepting a new centre, compare it with every circle placed so far and draw again if it is closer "
        "than 2 circle_radius to any of them");
    return false;
  }
  return true;
}

// --- Shape -----------------------------------------------------------------------------------

GRADED_TEST(InitBilliard, ReturnsOneFiniteRowPerCircle, 2, visible) {
  for (const Table& t : kTables) {
    for (const std::uint64_t seed : kSeeds) {
      if (!check_shape(place(t, seed), t, seed)) return;
    }
  }
}

GRADED_TEST(InitBilliard, ZeroCirclesGiveNoRows, 2, after_due_date) {
  for (const Table& t : {Table{10, 1, 0}, Table{3.5, 0.25, 0}}) {
    if (!check_shape(place(t, 1), t, 1)) return;
  }
}

// --- Placement -------------------------------------------------------------------------------

GRADED_TEST(InitBilliard, EveryCircleLiesFullyInsideTheTable, 3, visible) {
  for (const Table& t : kTables) {
    for (const std::uint64_t seed : kSeeds) {
      const Coordinates c = place(t, seed);
      if (!check_shape(c, t, seed) || !check_inside(c, t, seed)) return;
    }
  }
}

GRADED_TEST(InitBilliard, NoTwoCirclesOverlap, 3, visible) {
  for (const Table& t : kTables) {
    for (const std::uint64_t seed : kSeeds) {
      const Coordinates c = place(t, seed);
      if (!check_shape(c, t, seed) || !check_no_overlap(c, t, seed)) return;
    }
  }
}

// One circle that almost fills the table: its centre must stay within 0.5 of the origin.
GRADED_TEST(InitBilliard, OneLargeCircleFitsInsideTheTable, 2, after_due_date) {
  const Table t{10, 9.5, 1};
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Coordinates c = place(t, seed);
    if (!check_shape(c, t, seed) || !check_inside(c, t, seed)) return;
  }
}

// Area fraction n a^2 / R^2 = 0.5 (the densest packing of discs is 0.9069): the circles must be
// placed, inside and without overlap, in reasonable time (a hang is stopped by the test's time
// limit).
GRADED_TEST(InitBilliard, DenseTablesAreFilled, 3, visible) {
  for (const Table& t : {Table{10, 1, 50}, Table{20, 1, 200}}) {
    for (const std::uint64_t seed : {1, 2, 3}) {
      Coordinates c;
      try {
        c = place(t, seed);
      } catch (const NotImplemented&) {
        throw;
      } catch (const std::exception& error) {
        ADD_FAILURE() << explain(text(call(t, seed), " to place the circles (area fraction n a^2 / R^2 = 0.5, "
                                                     "far below the densest packing 0.9069)"),
                                 text("it threw \"", error.what(), "\""),
                                 "drawing centres at random and rejecting overlaps gets stuck near area fraction "
                                 "0.5; start from a regular arrangement (e.g. a hexagonal grid cut to the table) "
                                 "and shuffle it with many small random moves that keep circles apart, or restart "
                                 "when stuck");
        return;
      }
      if (!check_shape(c, t, seed) || !check_inside(c, t, seed) || !check_no_overlap(c, t, seed)) return;
    }
  }
}

GRADED_TEST(InitBilliard, DenseTablesAreNotARegularArrangement, 2, visible) {
  // In a random table the distance from each circle to its nearest neighbour varies from circle
  // to circle; on a lattice (with some sites left empty) it takes only a few values. Count the
  // distinct nearest-neighbour distances (to 1e-6): a random table of 50 circles has about 50,
  // a lattice at most 3 or so. Half of n leaves a wide margin.
  const Table t{10, 1, 50};
  for (const std::uint64_t seed : {1, 2, 3}) {
    const Coordinates c = place(t, seed);
    if (!check_shape(c, t, seed)) return;
    std::vector<long long> nearest;
    for (int i = 0; i < t.n; ++i) {
      double best = std::numeric_limits<double>::infinity();
      for (int j = 0; j < t.n; ++j) {
        if (j != i) best = std::min(best, (c.row(i) - c.row(j)).norm());
      }
      nearest.push_back(std::llround(best * 1e6));
    }
    std::sort(nearest.begin(), nearest.end());
    const auto distinct = std::unique(nearest.begin(), nearest.end()) - nearest.begin();
    if (distinct < t.n / 2) {
      ADD_FAILURE() << explain(
          text(call(t, seed), " (area fraction 0.5) to place the circles at random, so that the distances "
               "from each circle to its nearest neighbour vary (at least ", t.n / 2, " different values)"),
          text("only ", distinct, " different nearest-neighbour distances: the circles sit on a regular grid"),
          "starting from a lattice is fine for dense tables, but then move the circles at random (many small "
          "random moves, each kept only if the circle stays inside and overlaps nobody) until the grid is "
          "forgotten");
      return;
    }
  }
}

// --- Randomness ------------------------------------------------------------------------------

GRADED_TEST(InitBilliard, SameSeedGivesTheSameTable, 2, after_due_date) {
  for (const Table& t : {Table{10, 1, 10}, Table{100, 3, 60}}) {
    for (const std::uint64_t seed : kSeeds) {
      const Coordinates first = place(t, seed), second = place(t, seed);
      if (!check_shape(first, t, seed) || !check_shape(second, t, seed)) return;
      if (first != second) {
        Eigen::Index i = 0;
        (first - second).rowwise().norm().maxCoeff(&i);
        ADD_FAILURE() << explain(text("two calls of ", call(t, seed), " to give the same table"),
                                 text("circle ", i, " was at ", row(first, i), " the first time and at ",
                                      row(second, i), " the second time"),
                                 "draw every random number from the generator `rng` you are given (e.g. "
                                 "std::uniform_real_distribution<double>(...)(rng)); do not use std::random_device, "
                                 "rand() or the time, and do not make your own generator");
        return;
      }
    }
  }
}

GRADED_TEST(InitBilliard, DifferentSeedsGiveDifferentTables, 2, visible) {
  const Table t{10, 1, 10};
  std::vector<Coordinates> tables;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    tables.push_back(place(t, seed));
    if (!check_shape(tables.back(), t, seed)) return;
  }
  for (std::size_t i = 0; i < tables.size(); ++i) {
    for (std::size_t j = i + 1; j < tables.size(); ++j) {
      if (tables[i] == tables[j]) {
        ADD_FAILURE() << explain("different seeds of rng to give different tables",
                                 text("seeds ", i + 1, " and ", j + 1, " gave the same table, e.g. circle 0 at ",
                                      row(tables[i], 0)),
                                 "the positions must be random: draw them from `rng`, not from a fixed pattern");
        return;
      }
    }
  }
}

// The generator is passed by reference so that it advances: two calls in a row with the same
// generator object must give different tables.
GRADED_TEST(InitBilliard, RepeatedCallsWithOneGeneratorGiveDifferentTables, 2, visible) {
  const Table t{10, 1, 10};
  Rng rng(7);
  const Coordinates first = init_billiard(t.R, t.a, t.n, rng);
  const Coordinates second = init_billiard(t.R, t.a, t.n, rng);
  if (!check_shape(first, t, 7) || !check_shape(second, t, 7)) return;
  EXPECT_TRUE(first != second) << explain(
      "two calls of init_billiard(10, 1, 10, rng) with the same generator object to give different tables",
      text("both gave the same table, e.g. circle 0 at ", row(first, 0)),
      "use the generator `rng` itself (it is passed by reference); do not copy it (Rng copy = rng;) or "
      "re-seed it inside the function");
}

// --- Statistics ------------------------------------------------------------------------------
// A single circle must be uniform over the disc its centre can reach, of radius rho = R - a.
// For that distribution E[x] = E[y] = 0, Var x = Var y = rho^2 / 4, E[r^2] = rho^2 / 2,
// Var r^2 = E[r^4] - E[r^2]^2 = rho^4 / 3 - rho^4 / 4 = rho^4 / 12, and each quadrant has
// probability 1/4. Every sample uses its own fixed seed; bounds are 5 standard errors (a correct
// solution fails with probability below 1e-6 per check). The first three tests name the common
// mistakes, whose effects are many standard errors wide already with 5000 samples (each sample is
// a call of init_billiard, the tests' own cost); the chi-square test after them, with 64000
// samples, is the one that catches small departures from uniformity.

constexpr Table kSingle{10, 1, 1};  // rho = 9

std::vector<std::array<double, 2>> single_circle_samples(int count, std::uint64_t first_seed) {
  std::vector<std::array<double, 2>> samples;
  samples.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(k);
    const Coordinates c = place(kSingle, seed);
    if (!check_shape(c, kSingle, seed)) return {};
    samples.push_back({c(0, 0), c(0, 1)});
  }
  return samples;
}

// Centres farther out than R - a skew every statistic of the positions, so the hint of a
// statistical test names that mistake before it guesses at the distribution.
double farthest_centre(const std::vector<std::array<double, 2>>& samples) {
  double farthest = 0;
  for (const auto& s : samples) farthest = std::max(farthest, std::hypot(s[0], s[1]));
  return farthest;
}
std::string reach_first(double farthest, double rho, const std::string& guess) {
  if (farthest <= rho * (1 + 1e-9)) return guess;
  return text("first fix where the centres may lie: some are ", farthest, " from the middle, beyond R - a = ", rho,
              ", so those circles stick out of the table (EveryCircleLiesFullyInsideTheTable says the same); draw "
              "centres within R - a, then this statistic changes too");
}

GRADED_TEST(InitBilliard, SingleCircleIsCentredOnAverage, 2, after_due_date) {
  // S = 5000 samples: standard error of the mean of x is (rho / 2) / sqrt(S) = 4.5 / 70.7 =
  // 0.064, so the bound is 5 * 0.064 = 0.32 (3.5% of rho). Drawing x or y over half its range
  // shifts the mean by rho / 2 or more; a range shifted by the circle radius, by 0.5.
  constexpr int S = 5000;
  const auto samples = single_circle_samples(S, 1000);
  if (samples.empty()) return;
  const double rho = kSingle.R - kSingle.a;
  const double bound = 5 * (rho / 2) / std::sqrt(double(S));
  std::array<double, 2> mean{0, 0};
  for (const auto& s : samples) {
    mean[0] += s[0] / S;
    mean[1] += s[1] / S;
  }
  for (int axis = 0; axis < 2; ++axis) {
    EXPECT_LE(std::abs(mean[axis]), bound) << explain(
        text("a single circle on a table of radius 10 (circle radius 1) to be uniform over the disc of radius 9, so "
             "its mean ", axis == 0 ? "x" : "y", " over ", S, " seeds is 0 within ", bound),
        text("the mean ", axis == 0 ? "x" : "y", " was ", mean[axis]),
        "draw both coordinates symmetrically, e.g. x and y uniform in [-(R - a), R - a] and reject points outside "
        "the disc; check the lower limit of your distribution");
  }
}

GRADED_TEST(InitBilliard, SingleCircleIsUniformInArea, 3, after_due_date) {
  // E[r^2] = rho^2 / 2 = 40.5 for uniform-in-area; the common mistake of drawing the distance
  // from the centre uniformly in [0, rho] gives rho^2 / 3 = 27, and x uniform with y uniform
  // between the circle's edges at that x gives 5 rho^2 / 9 = 45. Standard error of the mean of
  // r^2 with S = 5000: (rho^2 / sqrt(12)) / sqrt(S) = 23.4 / 70.7 = 0.33; bound 5 * 0.33 = 1.65.
  constexpr int S = 5000;
  const auto samples = single_circle_samples(S, 50000);
  if (samples.empty()) return;
  const double rho = kSingle.R - kSingle.a;
  const double expected = rho * rho / 2;
  const double bound = 5 * (rho * rho / std::sqrt(12.0)) / std::sqrt(double(S));
  double mean_r2 = 0;
  for (const auto& s : samples) mean_r2 += (s[0] * s[0] + s[1] * s[1]) / S;
  EXPECT_NEAR(mean_r2, expected, bound) << explain(
      text("a single circle (table radius 10, circle radius 1) to be uniform in area over the disc of radius 9, so "
           "the mean of r^2 = x^2 + y^2 over ", S, " seeds is rho^2 / 2 = ", expected, " within ", bound),
      text("the mean of r^2 was ", mean_r2,
           mean_r2 < expected ? " (too many centres near the middle)" : " (too many centres near the wall)"),
      reach_first(farthest_centre(samples), rho,
                  mean_r2 < expected
                      ? "drawing the distance r uniformly in [0, rho] and a random angle crowds the centre (mean r^2 "
                        "= rho^2 / 3); draw x and y uniformly in the square and reject points outside the disc, or "
                        "use r = rho * sqrt(u) with u uniform in [0, 1]"
                      : "something pushes the centres outwards (for example r = rho * u^(1/4), or points of the "
                        "square kept without rejecting those outside the disc): draw x and y uniformly in the "
                        "square and reject points outside the disc of radius rho"));
}

GRADED_TEST(InitBilliard, SingleCircleQuadrantsAreEquallyLikely, 2, after_due_date) {
  // Each quadrant has probability 1/4; with S = 5000 the standard error of a fraction is
  // sqrt(1/4 * 3/4 / S) = 0.0061, so the bound is 5 * 0.0061 = 0.031. An angle drawn over half
  // the circle leaves two quadrants empty.
  constexpr int S = 5000;
  const auto samples = single_circle_samples(S, 100000);
  if (samples.empty()) return;
  std::array<double, 4> fraction{0, 0, 0, 0};
  for (const auto& s : samples) fraction[(s[0] < 0 ? 1 : 0) + (s[1] < 0 ? 2 : 0)] += 1.0 / S;
  const double bound = 5 * std::sqrt(0.25 * 0.75 / S);
  const char* names[4] = {"x > 0, y > 0", "x < 0, y > 0", "x > 0, y < 0", "x < 0, y < 0"};
  for (int q = 0; q < 4; ++q) {
    EXPECT_NEAR(fraction[q], 0.25, bound) << explain(
        text("a single circle to land in each quadrant of the table in 1/4 of ", S, " seeds (within ", bound, ")"),
        text("the quadrant ", names[q], " got a fraction ", fraction[q]),
        "the position must have no preferred direction: draw x and y (or the angle) over their full range");
  }
}

GRADED_TEST(InitBilliard, SingleCircleFillsEqualAreasEquallyOften, 2, visible) {
  // Cut the reachable disc into 8 rings of equal area (r^2 in steps of rho^2 / 8) and 8 equal
  // sectors: 64 cells, each with probability 1/64. With S = 64000 samples each cell expects
  // E = 1000, and chi^2 = sum (count - E)^2 / E follows a chi^2 law with 63 degrees of
  // freedom (mean 63, standard deviation 11.2). By the Wilson-Hilferty approximation
  // P(chi^2 > 140) is about 1e-7. A placement restricted to a grid, or crowded towards the
  // centre or the wall, gives chi^2 in the thousands.
  constexpr int S = 64000, kRings = 8, kSectors = 8;
  const auto samples = single_circle_samples(S, 200000);
  if (samples.empty()) return;
  const double rho = kSingle.R - kSingle.a;
  std::array<double, kRings * kSectors> count{};
  for (const auto& s : samples) {
    const double r2 = (s[0] * s[0] + s[1] * s[1]) / (rho * rho);
    const int ring = std::min(kRings - 1, static_cast<int>(r2 * kRings));
    const double angle = std::atan2(s[1], s[0]) + kPi;  // 0 to 2 pi
    const int sector = std::min(kSectors - 1, static_cast<int>(angle / (2 * kPi) * kSectors));
    count[static_cast<std::size_t>(ring * kSectors + sector)] += 1;
  }
  const double expected = double(S) / (kRings * kSectors);
  const auto ring_count = [](const auto& counts, int ring) {
    double total = 0;
    for (int sector = 0; sector < kSectors; ++sector) total += counts[static_cast<std::size_t>(ring * kSectors + sector)];
    return total;
  };
  double chi2 = 0, fullest = 0, emptiest = double(S);
  for (const double c : count) {
    chi2 += (c - expected) * (c - expected) / expected;
    fullest = std::max(fullest, c);
    emptiest = std::min(emptiest, c);
  }
  EXPECT_LE(chi2, 140.0) << explain(
      text("a single circle to be uniform over the reachable disc: in ", S, " seeds, each of 64 equal-area cells "
           "(8 rings x 8 sectors) gets about ", expected, " centres (chi^2 below 140)"),
      text("the counts ranged from ", emptiest, " to ", fullest, ", chi^2 = ", chi2, "; the innermost ring got ",
           ring_count(count, 0), " and the outermost ", ring_count(count, kRings - 1), " of the ",
           expected * kSectors, " each ring expects"),
      reach_first(farthest_centre(samples), rho,
                  "draw continuous random positions (not grid points or a few fixed spots), uniform in area: x and "
                  "y uniform in the square [-(R - a), R - a]^2 with rejection of points outside the disc"));
  // The rings alone and the sectors alone, 7 degrees of freedom each (P(chi^2 > 48) is about
  // 1e-7): a slight crowding towards the wall or the middle, or towards some directions, spread
  // over 8 of the 64 cells each, stands out several times more clearly there.
  std::array<double, kRings> rings{};
  std::array<double, kSectors> sectors{};
  for (int ring = 0; ring < kRings; ++ring) {
    for (int sector = 0; sector < kSectors; ++sector) {
      rings[static_cast<std::size_t>(ring)] += count[static_cast<std::size_t>(ring * kSectors + sector)];
      sectors[static_cast<std::size_t>(sector)] += count[static_cast<std::size_t>(ring * kSectors + sector)];
    }
  }
  const auto chi2_of = [](const auto& counts, double each) {
    double sum = 0;
    for (const double c : counts) sum += (c - each) * (c - each) / each;
    return sum;
  };
  const auto listed = [](const auto& counts) {
    std::string list;
    for (const double c : counts) list += (list.empty() ? "" : ", ") + text(c);
    return list;
  };
  const double chi2_rings = chi2_of(rings, double(S) / kRings), chi2_sectors = chi2_of(sectors, double(S) / kSectors);
  const bool outwards = rings[kRings - 1] > rings[0];
  EXPECT_LE(chi2_rings, 48.0) << explain(
      text("the ", kRings, " rings of equal area of the reachable disc to get about ", S / kRings, " of ", S,
           " single circles each (chi^2 over the rings below 48)"),
      text("from the middle outwards they got ", listed(rings), ": chi^2 = ", chi2_rings),
      reach_first(farthest_centre(samples), rho,
                  text("the centres are crowded towards the ", outwards ? "wall" : "middle",
                       ": every spot of the disc must be equally likely, also near the wall (x and y uniform in the "
                       "square with rejection, or r = (R - a) sqrt(u)); if you move circles after placing them, "
                       "every move must be as likely as its reverse (a step size that keeps changing with the "
                       "state breaks that)")));
  EXPECT_LE(chi2_sectors, 48.0) << explain(
      text("the ", kSectors, " equal sectors of the reachable disc to get about ", S / kSectors, " of ", S,
           " single circles each (chi^2 over the sectors below 48)"),
      text("counterclockwise from the negative x axis they got ", listed(sectors), ": chi^2 = ", chi2_sectors),
      reach_first(farthest_centre(samples), rho,
                  "some directions are favoured: draw the angle over the whole circle, or x and y over the same "
                  "symmetric range"));
}

// For a dilute table (n = 5, R = 20, a = 1, area fraction 0.0125) every circle, whatever its
// row, must be spread over the whole table.
constexpr Table kDilute{20, 1, 5};

GRADED_TEST(InitBilliard, EveryCircleIsCentredOnAverage, 2, after_due_date) {
  // The law of the table is unchanged by rotations about the centre, so each row's mean
  // position is exactly 0. Over S = 4000 seeds the standard error of row i's mean x is
  // sd(x_i) / sqrt(S) with sd(x_i) about rho / 2 = 9.5, i.e. 0.15; we use the measured
  // standard deviation and a bound of 5 standard errors (about 0.75, 4% of rho). Circles given
  // regions of their own (left to right, say) have means of several units.
  constexpr int S = 4000;
  const int n = kDilute.n;
  std::vector<std::array<double, 4>> sums(static_cast<std::size_t>(n), {0, 0, 0, 0});  // x, y, x^2, y^2
  for (int k = 0; k < S; ++k) {
    const std::uint64_t seed = 300000 + static_cast<std::uint64_t>(k);
    const Coordinates c = place(kDilute, seed);
    if (!check_shape(c, kDilute, seed)) return;
    for (int i = 0; i < n; ++i) {
      auto& s = sums[static_cast<std::size_t>(i)];
      s[0] += c(i, 0);
      s[1] += c(i, 1);
      s[2] += c(i, 0) * c(i, 0);
      s[3] += c(i, 1) * c(i, 1);
    }
  }
  for (int i = 0; i < n; ++i) {
    const auto& s = sums[static_cast<std::size_t>(i)];
    for (int axis = 0; axis < 2; ++axis) {
      const double mean = s[axis] / S;
      const double sd = std::sqrt(std::max(0.0, s[axis + 2] / S - mean * mean));
      const double bound = 5 * sd / std::sqrt(double(S)) + 1e-12;
      if (std::abs(mean) > bound) {
        ADD_FAILURE() << explain(
            text("each circle of init_billiard(20, 1, 5, rng) to be anywhere on the table, so that the mean ",
                 axis == 0 ? "x" : "y", " of circle ", i, " over ", S, " seeds is 0 within ", bound),
            text("circle ", i, " has mean ", axis == 0 ? "x" : "y", " = ", mean),
            "every circle must be drawn uniformly over the whole table; do not give circles fixed regions, "
            "rows or an order (e.g. left to right)");
        return;
      }
    }
  }
}

GRADED_TEST(InitBilliard, DiluteTableIsUniformInArea, 2, after_due_date) {
  // Uniform in area over the reachable disc of radius rho = R - a = 19 puts half the centres
  // inside r = rho / sqrt(2). Excluded volume shifts this a little: another circle blocks a
  // disc of radius 2a = 2, which is less often cut by the wall in the inner half, so the inner
  // fraction drops by about 4 * (4 pi / (pi rho^2)) * (fraction of blocking discs cut by the
  // wall, about 0.04) / 2, i.e. about 0.001; we allow 0.005 for it. Statistics: per seed the
  // fraction of the 5 circles inside has standard deviation about sqrt(0.25 / 5) = 0.22, so
  // over S = 4000 seeds the standard error is about 0.0035; we use the measured standard
  // deviation, 5 standard errors (about 0.017) plus the 0.005. Drawing r uniformly instead of
  // r^2 gives 0.707.
  constexpr int S = 4000;
  const double rho = kDilute.R - kDilute.a;
  const double split = rho / std::sqrt(2.0);
  double sum = 0, sum2 = 0, farthest = 0;
  for (int k = 0; k < S; ++k) {
    const std::uint64_t seed = 400000 + static_cast<std::uint64_t>(k);
    const Coordinates c = place(kDilute, seed);
    if (!check_shape(c, kDilute, seed)) return;
    double inside = 0;
    for (Eigen::Index i = 0; i < c.rows(); ++i) {
      inside += c.row(i).norm() < split ? 1.0 / kDilute.n : 0.0;
      farthest = std::max(farthest, c.row(i).norm());
    }
    sum += inside;
    sum2 += inside * inside;
  }
  const double fraction = sum / S;
  const double sd = std::sqrt(std::max(0.0, sum2 / S - fraction * fraction));
  const double bound = 5 * sd / std::sqrt(double(S)) + 0.005;
  EXPECT_NEAR(fraction, 0.5, bound) << explain(
      text("the circles of init_billiard(20, 1, 5, rng) to be uniform in area, so that over ", S,
           " seeds half of them are closer to the centre than (R - a) / sqrt(2) = ", split, " (within ", bound, ")"),
      text("a fraction ", fraction, " was closer", fraction > 0.5 ? " (crowded towards the centre)" : " (crowded towards the wall)"),
      reach_first(farthest, rho,
                  "choose x and y uniformly in the square [-(R - a), R - a]^2 and reject points outside the disc (or "
                  "use r = (R - a) sqrt(u)); drawing the distance from the centre uniformly crowds the middle"));
}

// --- Invalid arguments -------------------------------------------------------------------------

GRADED_TEST(InitBilliard, RejectsTableRadiusThatIsNotPositiveAndFinite, 1, after_due_date) {
  for (const double R : {0.0, -1.0, -kInf, kNaN, kInf}) {
    expect_invalid_argument(
        [&] {
          Rng rng(1);
          init_billiard(R, 1, 3, rng);
        },
        text("table_radius = ", R), "table_radius",
        "check at the start that table_radius is finite (std::isfinite) and positive, and throw "
        "std::invalid_argument(\"table_radius = ...: must be ...\") otherwise; note that NaN > 0 is false");
  }
}

GRADED_TEST(InitBilliard, RejectsCircleRadiusThatIsNotPositiveAndFinite, 1, after_due_date) {
  for (const double a : {0.0, -0.5, -kInf, kNaN, kInf}) {
    expect_invalid_argument(
        [&] {
          Rng rng(1);
          init_billiard(10, a, 3, rng);
        },
        text("circle_radius = ", a), "circle_radius",
        "check at the start that circle_radius is finite (std::isfinite) and positive, and throw "
        "std::invalid_argument naming circle_radius otherwise; note that NaN > 0 is false");
  }
}

GRADED_TEST(InitBilliard, RejectsCircleRadiusNotSmallerThanTableRadius, 1, after_due_date) {
  for (const Table& t : {Table{10, 10, 1}, Table{10, 12, 3}, Table{2.5, 2.5000001, 2}}) {
    expect_invalid_argument(
        [&] {
          Rng rng(1);
          init_billiard(t.R, t.a, t.n, rng);
        },
        text("circle_radius = ", t.a, " >= table_radius = ", t.R, " with n = ", t.n), "circle_radius",
        "a circle only fits on the table if circle_radius < table_radius; throw std::invalid_argument naming "
        "circle_radius when n > 0 and it does not");
  }
}

GRADED_TEST(InitBilliard, RejectsNegativeNumberOfCircles, 1, after_due_date) {
  for (const int n : {-1, -7}) {
    expect_invalid_argument(
        [&] {
          Rng rng(1);
          init_billiard(10, 1, n, rng);
        },
        text("n = ", n), "n", "check n >= 0 before creating the array (Coordinates(n, 2) with n < 0 is an error)");
  }
}

// Area fractions 10 and 1.0, both above the densest packing of discs, pi / sqrt(12) = 0.9069:
// impossible, so the function must say so instead of searching forever.
GRADED_TEST(InitBilliard, RejectsImpossiblePackings, 1, after_due_date) {
  for (const Table& t : {Table{10, 1, 1000}, Table{10, 1, 100}}) {
    expect_invalid_argument(
        [&] {
          Rng rng(1);
          init_billiard(t.R, t.a, t.n, rng);
        },
        text(t.n, " circles of radius ", t.a, " on a table of radius ", t.R, " (area fraction ",
             t.n * t.a * t.a / (t.R * t.R), ", more than the densest possible packing 0.9069)"),
        "n",
        "n circles cover n a^2 / R^2 of the table, which can never exceed pi / sqrt(12) = 0.9069; reject such "
        "n at once, and also give up (throw std::invalid_argument) after a bounded number of failed attempts "
        "instead of looping forever");
  }
}

}  // namespace
}  // namespace billiard::testing
