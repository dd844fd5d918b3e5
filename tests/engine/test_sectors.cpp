// Stage 4: cells. The run with cells must give the same first events as the run without them
// (one cell holding everything, i.e. all pairs), until rounding differences grow, and the same
// statistics afterwards. Also: three discs touching at once.
#include "sectors.hpp"
#include "billiard/engine/simulation.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

using billiard::Vector;
using engine_test::make_disc;

namespace {
struct Setup {
  bool periodic;
  double cell;  // 0: automatic
  billiard::Prefetch prefetch = billiard::Prefetch::Automatic;
};

billiard::Simulation make(const Setup& setup, std::uint64_t seed, int n, double side) {
  billiard::Settings settings;
  settings.cell_size = setup.cell;
  settings.prefetch = setup.prefetch;
  billiard::Simulation sim(setup.periodic ? billiard::periodic_box(side, side) : billiard::box(Vector(0, 0), Vector(side, side)),
                           settings);
  std::mt19937_64 rng(seed);
  const auto discs = engine_test::random_discs(rng, n, 0.6, 1.0, Vector(0, 0), Vector(side, side), [&](const Vector& p, double a) {
    // Away from the edges in both cases (in the periodic box, so that no disc overlaps an
    // image of another across the boundary).
    return p.x() >= a && p.x() <= side - a && p.y() >= a && p.y() <= side - a;
  });
  engine_test::add_all(sim, discs);
  sim.set_log_events(true);
  return sim;
}

// Number of leading events that agree (same discs or wall, times within 1e-9).
std::size_t agreeing_prefix(const std::vector<billiard::EventRecord>& a, const std::vector<billiard::EventRecord>& b) {
  std::size_t k = 0;
  for (; k < std::min(a.size(), b.size()); ++k) {
    const auto key = [](const billiard::EventRecord& e) {
      return std::make_pair(std::min(e.disc, e.other < 0 ? e.disc : e.other), e.other < 0 ? -1 - e.wall : std::max(e.disc, e.other));
    };
    if (key(a[k]) != key(b[k]) || std::abs(a[k].time - b[k].time) > 1e-9) break;
  }
  return k;
}
}  // namespace

TEST(Sectors, AutomaticCellsAreUsed) {
  billiard::Simulation sim = make({false, 0}, 1, 200, 60);
  sim.advance(1);
  EXPECT_GT(sim.cell_count(), 100);
}

TEST(Sectors, SameFirstEventsWithAndWithoutCellsInABox) {
  // 150 discs in a 50 x 50 box. One cell (cell size larger than the box) is the all-pairs
  // search; the automatic grid has ~15 x 15 cells. The first 300 collisions must agree (chaos
  // amplifies rounding differences by a factor of order 10 per mean free time, so agreement
  // over a few collisions per disc is what "until rounding differences grow" allows).
  billiard::Simulation all_pairs = make({false, 1e9}, 2, 150, 50);
  billiard::Simulation cells = make({false, 0}, 2, 150, 50);
  all_pairs.advance(300);
  cells.advance(300);
  EXPECT_EQ(agreeing_prefix(all_pairs.event_log(), cells.event_log()), 300u);
}

TEST(Sectors, SameFirstEventsForDifferentCellSizesInAPeriodicBox) {
  // A periodic grid needs at least 3 cells per side: 3 x 3 against the automatic choice.
  billiard::Simulation coarse = make({true, 50.0 / 3}, 3, 150, 50);
  billiard::Simulation fine = make({true, 0}, 3, 150, 50);
  coarse.advance(300);
  fine.advance(300);
  EXPECT_EQ(agreeing_prefix(coarse.event_log(), fine.event_log()), 300u);
}

TEST(Sectors, SameStatisticsAfterChaosTakesOver) {
  // After 300 000 collisions the two runs are different trajectories of the same system;
  // their statistics must agree: collision rate per disc and unit time, and the pressure from
  // the collision virial. Each is an average over ~10^5 correlated events: 3% tolerance is
  // several standard errors.
  billiard::Simulation a = make({true, 50.0 / 3}, 4, 300, 50);
  billiard::Simulation b = make({true, 0}, 4, 300, 50);
  a.set_log_events(false);
  b.set_log_events(false);
  a.advance(300000);
  b.advance(300000);
  const double rate_a = 300000 / a.time(), rate_b = 300000 / b.time();
  EXPECT_NEAR(rate_a / rate_b, 1.0, 0.03);
  const double virial_a = a.totals().virial / a.time(), virial_b = b.totals().virial / b.time();
  EXPECT_NEAR(virial_a / virial_b, 1.0, 0.03);
}

TEST(Sectors, ThreeDiscsTouchingAtOnce) {
  // A at x = -3 moving +1, B at rest at 0, C at x = 3 moving -1 (radius 1): A and C touch B at
  // t = 1 together. Processed one after another at the same instant (A-B, B-C, then A-B again,
  // or the mirror order), equal smooth discs end with A -1, B 0, C +1: three events at t = 1.
  billiard::Simulation sim(billiard::box(Vector(-20, -20), Vector(20, 20)));
  sim.add_disc(make_disc(Vector(-3, 0), Vector(1, 0)));
  sim.add_disc(make_disc(Vector(0, 0), Vector(0, 0)));
  sim.add_disc(make_disc(Vector(3, 0), Vector(-1, 0)));
  sim.set_log_events(true);
  sim.set_validate_every_event(true);
  sim.advance(billiard::kAllEvents, 5.0);
  EXPECT_EQ(sim.last_problem(), std::nullopt);
  ASSERT_EQ(sim.event_log().size(), 3u);
  for (const auto& e : sim.event_log()) EXPECT_DOUBLE_EQ(e.time, 1.0);
  const billiard::State s = sim.current_state();
  EXPECT_DOUBLE_EQ(s.velocities(0, 0), -1.0);
  EXPECT_DOUBLE_EQ(s.velocities(1, 0), 0.0);
  EXPECT_DOUBLE_EQ(s.velocities(2, 0), 1.0);
}

TEST(Sectors, LowAndHighDensityRunsStayValid) {
  // Crossing events dominate at low density, collisions at high density; both must keep the
  // discs in their cells and apart. 1000 discs, 100 000 collisions: the discs of every collision
  // checked against their neighbours, the whole system every 10 000.
  for (double fraction : {0.05, 0.6}) {
    const double side = std::sqrt(1000 * M_PI / fraction);
    billiard::Simulation sim(billiard::periodic_box(side, side));
    billiard::Coordinates positions(1000, 2), velocities(1000, 2);
    std::mt19937_64 rng(5);
    std::normal_distribution<double> normal;
    for (int k = 0; k < 1000; ++k) {
      positions.row(k) << (k % 32 + 0.5) * side / 32, (k / 32 + 0.5) * side / 32;
      velocities.row(k) << normal(rng), normal(rng);
    }
    sim.add_discs(positions, velocities, 1.0);
    sim.set_check_event_discs(true);
    for (int round = 0; round < 10; ++round) {
      ASSERT_EQ(sim.advance(10000).collisions, 10000) << sim.last_problem().value_or("");
      ASSERT_EQ(sim.validate(), std::nullopt) << "area fraction " << fraction;
    }
  }
}

// Requesting the next event's data ahead (on by itself only from about 87,000 discs) is a hint
// to the caches, but it drops entries from the queue's heap early, which can change the order in
// which two entries of the same instant come out (the two discs of one collision: the same event,
// computed from the other side, equal up to rounding). Forced on and off, a dense and a dilute box
// must give the same first 2,000 events (same discs, times within 1e-9), and the run with it on
// must stay valid after every event.
TEST(Sectors, PrefetchingAheadChangesNoEvent) {
  for (double side : {40.0, 120.0}) {
    std::vector<std::vector<billiard::EventRecord>> logs;
    for (auto mode : {billiard::Prefetch::On, billiard::Prefetch::Off}) {
      billiard::Simulation sim = make(::Setup{false, 0.0, mode}, 21, 300, side);
      sim.set_validate_every_event(mode == billiard::Prefetch::On);
      ASSERT_EQ(sim.advance(20000).collisions, 20000) << sim.last_problem().value_or("");
      logs.push_back(sim.event_log());
    }
    EXPECT_GE(agreeing_prefix(logs[0], logs[1]), 2000u) << "box side " << side;
  }
}

// The cell records: up to three discs inline, more in a spill block, the block returned when the
// cell is back to three, every cell's capacity doubled when one is full. Random insertions and
// removals against a plain set per cell; the walls' flag must survive them.
TEST(Sectors, CellRecordsKeepEveryDiscThroughSpillsAndGrowth) {
  billiard::Grid grid = billiard::make_grid(Vector(0, 0), Vector(4, 4), 1.0, false);
  ASSERT_EQ(grid.nx * grid.ny, 16);
  billiard::set_capacity(grid, 5);
  // One wall along the bottom edge: listed in the bottom row of cells only.
  billiard::WallShape bottom;
  bottom.kind = billiard::WallKind::Segment;
  bottom.a = Vector(0, 0);
  bottom.b = Vector(4, 0);
  billiard::assign_walls(grid, {bottom}, 0.5);
  std::vector<std::multiset<int>> expected(16);
  std::mt19937_64 rng(3);
  int next_disc = 0;
  for (int step = 0; step < 20000; ++step) {
    const int c = static_cast<int>(rng() % 16);
    // Mostly around 2-5 discs per cell (inline and spilled), sometimes up to 12 (growth).
    const bool grow = expected[c].size() < (step % 1000 < 50 ? 12u : 4u);
    if (expected[c].empty() || (grow && rng() % 2 == 0)) {
      billiard::insert_disc(grid, c, next_disc);
      expected[c].insert(next_disc++);
    } else {
      auto it = expected[c].begin();
      std::advance(it, static_cast<long>(rng() % expected[c].size()));
      billiard::remove_disc(grid, c, *it);
      expected[c].erase(it);
    }
    for (int cell : {c, static_cast<int>(rng() % 16)}) {
      const int count = billiard::cell_disc_count(grid, cell);
      ASSERT_EQ(count, static_cast<int>(expected[cell].size())) << "cell " << cell << " at step " << step;
      const int* items = billiard::cell_discs(grid, cell);
      ASSERT_EQ(std::multiset<int>(items, items + count), expected[cell]) << "cell " << cell << " at step " << step;
      ASSERT_EQ(billiard::cell_has_walls(grid, cell), cell < 4) << "cell " << cell;
      ASSERT_LE(count, grid.capacity);
    }
  }
  EXPECT_GT(grid.capacity, 5) << "a cell held more than 5 discs: the capacity should have grown";
  EXPECT_EQ(billiard::cell_walls_end(grid, 0) - billiard::cell_walls_begin(grid, 0), 1);
  EXPECT_EQ(billiard::cell_walls_end(grid, 5) - billiard::cell_walls_begin(grid, 5), 0);
}
