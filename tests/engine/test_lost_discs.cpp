// Settings at which the engine once lost discs (a disc outside its container, on a wall or out of
// its cell, found by validate()): perfectly inelastic beds sliding along curved walls, long runs
// in a periodic box under gravity, a huge spin turned into a huge speed, and the largest scales
// and gravity allowed. Each run must end valid (lib/DESIGN.md, "Discs are never lost").
#include "billiard/engine/simulation.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

using billiard::Container;
using billiard::Settings;
using billiard::Simulation;
using billiard::Vector;
using engine_test::make_disc;

namespace {

// 20 random discs of radius 0.13 in `table` under gravity (0, -1) with this restitution, each
// event's discs checked, for 2000 collisions; the seeds whose run ended invalid.
std::vector<std::string> lost_in_inelastic_beds(const Container& table, double normal, double tangential, int seeds) {
  std::vector<std::string> lost;
  for (int seed = 0; seed < seeds; ++seed) {
    Settings settings;
    settings.gravity = Vector(0, -1);
    settings.restitution = {normal, tangential};
    Simulation sim(table, settings);
    sim.add_random_discs(20, 0.13, 1.0, 1.0, static_cast<std::uint64_t>(seed));
    sim.set_check_event_discs(true);
    sim.advance(2000);
    if (const auto problem = sim.validate()) lost.push_back("seed " + std::to_string(seed) + ": " + *problem);
  }
  return lost;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string all;
  for (const std::string& line : lines) all += line + "\n";
  return all;
}

}  // namespace

// Perfectly inelastic discs (restitution 0, normal and tangential) settling in a circular table
// and in a stadium: they slide along the rim, pressed against it by gravity.
TEST(LostDiscs, InelasticBedsStayInCurvedContainers) {
  const auto in_table = lost_in_inelastic_beds(billiard::circular_table(6), 0.0, 0.0, 200);
  EXPECT_TRUE(in_table.empty()) << in_table.size() << " of 200 beds in the table invalid:\n" << joined(in_table);
  const auto in_stadium = lost_in_inelastic_beds(billiard::stadium(Vector(0, 0), 4, 4), 0.0, 0.0, 200);
  EXPECT_TRUE(in_stadium.empty()) << in_stadium.size() << " of 200 beds in the stadium invalid:\n" << joined(in_stadium);
}

// Smooth discs with restitution 0 in the table and in a stadium (arcs joined by segments).
TEST(LostDiscs, SmoothInelasticBedsStayInCurvedContainers) {
  const auto in_table = lost_in_inelastic_beds(billiard::circular_table(6), 0.0, -1.0, 200);
  EXPECT_TRUE(in_table.empty()) << in_table.size() << " of 200 beds in the table invalid:\n" << joined(in_table);
  const auto in_stadium = lost_in_inelastic_beds(billiard::stadium(Vector(0, 0), 4, 4), 0.0, -1.0, 200);
  EXPECT_TRUE(in_stadium.empty()) << in_stadium.size() << " of 200 beds in the stadium invalid:\n" << joined(in_stadium);
}

// The gas of the report (two discs, seed 120, to t = 6000) and a denser one falling through
// a periodic box until it is 10^8 times faster than its thermal speed: both valid,
// checked after every event, their relative motion as precise as without gravity (the kinetic
// energy about the centre of mass, conserved by elastic collisions, to 1e-9), and falling as the
// lab frame says (total momentum p0 + M g t, centre of mass, from the unwrapped positions,
// r0 + p0 t / M + g t^2 / 2). (A duration, so that runs without a collision are not taken for
// stuck ones.)
TEST(LostDiscs, LongPeriodicRunsUnderGravityStayInTheBox) {
  struct Gas {
    int discs;
    double radius, duration;
    Vector gravity;
    std::int64_t collisions_at_least;
  };
  for (const Gas& gas : {Gas{2, 0.0617, 6000, Vector(0, -1), 10}, Gas{40, 0.5, 3000, Vector(1.1, -3.3) * 1e4, 10000}}) {
    Settings settings;
    settings.gravity = gas.gravity;
    const Vector period(10.77, 12.97);
    Simulation sim(billiard::periodic_box(period.x(), period.y()), settings);
    sim.add_random_discs(gas.discs, gas.radius, 1.0, 1.0, 120);
    sim.set_check_event_discs(true);
    const auto centre = [&](const billiard::State& state, const billiard::Images& images) {
      Vector sum = Vector::Zero();
      for (Eigen::Index i = 0; i < state.positions.rows(); ++i) {
        sum += state.positions.row(i) + Vector(static_cast<double>(images(i, 0)) * period.x(),
                                                         static_cast<double>(images(i, 1)) * period.y());
      }
      return Vector(sum / static_cast<double>(state.positions.rows()));
    };
    const auto internal_energy = [](const billiard::State& state) {
      const Vector mean = state.velocities.colwise().mean();
      return 0.5 * (state.velocities.rowwise() - mean).squaredNorm();
    };
    const billiard::State start = sim.current_state();
    const Vector centre0 = centre(start, sim.images());
    const Vector momentum0 = start.velocities.colwise().sum();  // (unit masses)
    const auto result = sim.advance(std::numeric_limits<std::int64_t>::max(), gas.duration);
    const std::string what = std::to_string(gas.discs) + " discs";
    EXPECT_FALSE(result.stuck) << what << ": " << result.stuck_reason;
    EXPECT_NEAR(sim.time(), gas.duration, 1e-12 * gas.duration);
    EXPECT_GE(result.collisions, gas.collisions_at_least) << what;
    EXPECT_EQ(sim.validate(), std::nullopt) << what << ": after " << result.collisions << " collisions and "
                                            << result.cell_crossings << " cell crossings, time " << sim.time();
    const billiard::State end = sim.current_state();
    const double t = sim.time(), n = gas.discs;
    const Vector fall_speed = gas.gravity * t;
    EXPECT_LT((Vector(end.velocities.colwise().sum()) - (momentum0 + n * fall_speed)).norm(),
              1e-12 * n * fall_speed.norm()) << what;
    const Vector expected_centre = centre0 + momentum0 * t / n + 0.5 * gas.gravity * t * t;
    // (To rounding of numbers as large as the fall, far below a period: a wrong image count shows.)
    EXPECT_LT((centre(end, sim.images()) - expected_centre).norm(), 1e-3 + 1e-14 * expected_centre.norm())
        << what << ": centre of mass (" << centre(end, sim.images()) << ") against (" << expected_centre << ")";
    EXPECT_NEAR(internal_energy(end), internal_energy(start), 1e-9 * internal_energy(start)) << what;
  }
}

// A lone disc crossing a periodic box 10^7 times: still in the box, and its unwrapped position
// (wrapped plus image counts times the period) where r0 + v t puts it, to 1e-9 of the distance
// travelled.
TEST(LostDiscs, LongPeriodicRunsKeepTheirPlace) {
  const Vector period(3.3, 2.9);
  Simulation sim(billiard::periodic_box(period.x(), period.y()));
  const Vector start(1.1, 0.7), velocity(0.8660254037844386, 0.5);
  sim.add_disc(make_disc(start, velocity, 0.05));
  sim.set_check_event_discs(true);
  const double duration = 8e6;
  const auto result = sim.advance(std::numeric_limits<std::int64_t>::max(), duration);
  EXPECT_GT(result.cell_crossings, 10000000);
  EXPECT_EQ(sim.validate(), std::nullopt) << "after " << result.cell_crossings << " cell crossings";
  const billiard::State state = sim.current_state();
  const billiard::Images images = sim.images();
  const Vector unwrapped(state.positions(0, 0) + static_cast<double>(images(0, 0)) * period.x(),
                      state.positions(0, 1) + static_cast<double>(images(0, 1)) * period.y());
  EXPECT_LT((unwrapped - (start + duration * velocity)).norm(), 1e-9 * duration) << "unwrapped (" << unwrapped.x() << ", "
                                                                                  << unwrapped.y() << ")";
}

// A rough disc spinning at the largest spin allowed meets another: the collision turns spin into a
// speed near 1e50.
TEST(LostDiscs, HugeSpinsStayInTheirCells) {
  for (const double spin : {1e50, -1e50, 1e30}) {
    for (const double tangential : {1.0, 0.0}) {
      Settings settings;
      settings.restitution = {1.0, tangential};
      Simulation sim(billiard::box(Vector(0, 0), Vector(20, 20)), settings);
      billiard::Disc spinning = make_disc(Vector(5, 10), Vector(1, 0), 0.5);
      spinning.spin = spin;
      sim.add_disc(spinning);
      sim.add_disc(make_disc(Vector(8, 10), Vector(-1, 0), 0.5));
      sim.add_random_discs(20, 0.3, 1.0, 1.0, 7);
      sim.set_check_event_discs(true);
      const auto result = sim.advance(2000);
      EXPECT_FALSE(result.stuck) << "spin " << spin << ", tangential restitution " << tangential << ": " << result.stuck_reason;
      EXPECT_EQ(sim.validate(), std::nullopt) << "spin " << spin << ", tangential restitution " << tangential << ", after "
                                              << result.collisions << " collisions";
    }
  }
}

// The largest lengths and gravity allowed with nearly inelastic discs: a union of circles scaled by
// 1e20 under gravity 1e50, restitution 1e-3.
TEST(LostDiscs, HugeUnionOfCirclesUnderHugeGravity) {
  billiard::Coordinates centres(3, 2);
  centres << 0, 0, 5e20, 1e20, -3e20, 4e20;
  const std::vector<double> radii = {6e20, 4e20, 5e20};
  for (const Vector& gravity : {Vector(0, -1e50), Vector(1e50, -1e50), Vector(-1e50, 0)}) {
    for (int seed = 0; seed < 10; ++seed) {
      Settings settings;
      settings.gravity = gravity;
      settings.restitution = {1e-3, -1};
      Simulation sim(billiard::union_of_circles(centres, radii), settings);
      sim.add_random_discs(20, 1e19, 1.0, 1.0, static_cast<std::uint64_t>(seed));
      sim.set_check_event_discs(true);
      const auto result = sim.advance(2000);
      EXPECT_EQ(sim.validate(), std::nullopt) << "gravity (" << gravity.x() << ", " << gravity.y() << "), seed " << seed << ", after "
                                              << result.collisions << " collisions";
    }
  }
}

// A rough inelastic gas cooling for ever (restitution 0.5, no gravity) reaches speeds whose
// squares underflow in the times of impact (1e-162 after 1,200 collisions): a disc then passed
// through the Sinai obstacle. The run must stop, stuck, with a valid state, and stay stopped.
TEST(LostDiscs, AGasCooledBelowTheTimesOfImpactStopsValid) {
  Container table = billiard::sinai_billiard(Vector(0, 0), Vector(20, 20), 5);
  table.add_segment(Vector(1e-50, 4.9406564584124654e-324), Vector(-1.0356457581396015, 11.328882758487847));
  table.add_segment(Vector(0, 3.6400437656281923), Vector(-15.124859933326603, 5.4112438149963857));
  Settings settings;
  settings.restitution = {0.5, -0.0};
  Simulation sim(table, settings);
  sim.add_random_discs(2, 0.59870793727314464, 1e20, 1e20, 18244385805452784802ULL);
  sim.set_check_event_discs(true);
  const auto result = sim.advance(200000);
  EXPECT_EQ(sim.last_problem(), std::nullopt);
  EXPECT_EQ(sim.validate(), std::nullopt);
  EXPECT_TRUE(result.stuck);
  EXPECT_NE(result.stuck_reason.find("underflow"), std::string::npos) << result.stuck_reason;
  EXPECT_TRUE(sim.advance(10).stuck);
  EXPECT_EQ(sim.validate(), std::nullopt);
}
