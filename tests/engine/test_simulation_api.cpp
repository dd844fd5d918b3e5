// The public API: bad input refused with std::invalid_argument naming the disc, the argument or
// the settings field and the value (state unchanged after a refused call), advancing by events or
// duration, the event log and its replays, N = 0 and N = 1.
#include "billiard/engine/replay.hpp"
#include "billiard/engine/simulation.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

using billiard::Vector;
using engine_test::make_disc;

namespace {
// Runs `call`, expects std::invalid_argument whose message contains every piece in `pieces`.
template <class Call>
void expect_refused(Call call, std::initializer_list<const char*> pieces) {
  try {
    call();
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    for (const char* piece : pieces) EXPECT_NE(std::string(e.what()).find(piece), std::string::npos) << e.what() << " lacks " << piece;
  }
}

billiard::Simulation two_discs() {
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(10, 10)));
  sim.add_disc(make_disc(Vector(2, 2), Vector(1, 0)));
  sim.add_disc(make_disc(Vector(6, 6), Vector(0, 1)));
  return sim;
}
}  // namespace

TEST(Api, BadDiscsAreRefusedNamingTheDiscAndTheValue) {
  billiard::Simulation sim = two_discs();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  expect_refused([&] { sim.add_disc(make_disc(Vector(nan, 1), Vector(0, 0))); }, {"disc 2", "position", "nan"});
  expect_refused([&] { sim.add_disc(make_disc(Vector(4, 4), Vector(inf, 0))); }, {"disc 2", "velocity", "inf"});
  expect_refused([&] { sim.add_disc(make_disc(Vector(4, 4), Vector(0, 0), -0.5)); }, {"disc 2", "radius", "-0.5"});
  expect_refused([&] { sim.add_disc(make_disc(Vector(4, 4), Vector(0, 0), 0.5, 0.0)); }, {"disc 2", "mass", "0"});
  expect_refused([&] { sim.add_disc(make_disc(Vector(2.5, 2.5), Vector(0, 0))); }, {"disc 2", "overlaps disc 0"});
  expect_refused([&] { sim.add_disc(make_disc(Vector(9.5, 5), Vector(0, 0))); }, {"disc 2", "overlaps wall"});
  expect_refused([&] { sim.add_disc(make_disc(Vector(15, 5), Vector(0, 0))); }, {"disc 2", "outside"});
  billiard::Disc bad_inertia = make_disc(Vector(4, 8), Vector(0, 0));
  bad_inertia.inertia = -1.0;
  expect_refused([&] { sim.add_disc(bad_inertia); }, {"disc 2", "inertia", "-1"});
  // No disc has a moment above a thin ring's, mass radius^2 (here 1; test_rough's discs have
  // exactly that).
  bad_inertia.inertia = 1 + 1e-9;
  expect_refused([&] { sim.add_disc(bad_inertia); }, {"disc 2", "inertia", "mass x radius^2 = 1"});
  // Nothing was added.
  EXPECT_EQ(sim.size(), 2);
  EXPECT_EQ(sim.current_state().positions.rows(), 2);
}

TEST(Api, BadSettingsAreRefusedAndChangeNothing) {
  billiard::Simulation sim = two_discs();
  expect_refused([&] { sim.set_restitution({1.5}); }, {"set_restitution: restitution.normal", "1.5"});
  expect_refused([&] { sim.set_restitution({1.0, -2.0}); }, {"set_restitution: restitution.tangential", "-2"});
  expect_refused([&] { sim.set_contact_duration(-1.0); }, {"set_contact_duration: duration", "-1"});
  expect_refused([&] { sim.set_elastic_impact_speed(std::nan("")); }, {"set_elastic_impact_speed: speed", "nan"});
  expect_refused([&] { sim.set_sleep_speed(-2.0); }, {"set_sleep_speed: speed", "-2"});
  expect_refused([&] { sim.advance(-1); }, {"max_events", "-1"});
  expect_refused([&] { sim.advance(1, -2.0); }, {"max_duration", "-2"});
  // Still the same valid simulation.
  EXPECT_EQ(sim.restitution().normal, 1.0);
  EXPECT_EQ(sim.restitution().tangential, -1.0);
  EXPECT_EQ(sim.container().walls().size(), 8u);  // 4 sides + 4 corners
  const auto result = sim.advance(10);
  EXPECT_EQ(result.collisions, 10);
  EXPECT_EQ(sim.validate(), std::nullopt);
}

TEST(Api, BadSettingsFieldsAreRefusedByTheSimulation) {
  // Each field of Settings, bad on its own: the simulation is not made, and the message names
  // the field and the value.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto refused = [](const std::function<void(billiard::Settings&)>& spoil, std::initializer_list<const char*> pieces) {
    billiard::Settings settings;
    spoil(settings);
    expect_refused([&] { billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(10, 10)), settings); }, pieces);
  };
  refused([&](billiard::Settings& s) { s.gravity = Vector(0, nan); }, {"settings.gravity", "nan"});
  refused([&](billiard::Settings& s) { s.gravity = Vector(-inf, 0); }, {"settings.gravity", "inf"});
  refused([](billiard::Settings& s) { s.gravity = Vector(1e51, 0); }, {"settings.gravity", "1e+51"});
  refused([](billiard::Settings& s) { s.gravity = Vector(0, -1e-60); }, {"settings.gravity", "1e-50"});  // |g|^2 underflows
  refused([](billiard::Settings& s) { s.restitution.normal = 1.5; }, {"settings.restitution.normal", "1.5"});
  refused([](billiard::Settings& s) { s.restitution.normal = -0.1; }, {"settings.restitution.normal", "-0.1"});
  refused([&](billiard::Settings& s) { s.restitution.normal = nan; }, {"settings.restitution.normal", "nan"});
  refused([](billiard::Settings& s) { s.restitution.tangential = -2; }, {"settings.restitution.tangential", "-2"});
  refused([](billiard::Settings& s) { s.restitution.tangential = 1.5; }, {"settings.restitution.tangential", "1.5"});
  refused([](billiard::Settings& s) { s.contact_duration = -1.0; }, {"settings.contact_duration", "-1"});
  refused([&](billiard::Settings& s) { s.contact_duration = inf; }, {"settings.contact_duration", "inf"});
  refused([&](billiard::Settings& s) { s.elastic_impact_speed = nan; }, {"settings.elastic_impact_speed", "nan"});
  refused([](billiard::Settings& s) { s.elastic_impact_speed = -3.0; }, {"settings.elastic_impact_speed", "-3"});
  refused([](billiard::Settings& s) { s.sleep_speed = -0.5; }, {"settings.sleep_speed", "-0.5"});
  refused([&](billiard::Settings& s) { s.sleep_speed = inf; }, {"settings.sleep_speed", "inf"});
  refused([](billiard::Settings& s) { s.cell_size = -1.0; }, {"settings.cell_size", "-1"});
  refused([&](billiard::Settings& s) { s.cell_size = nan; }, {"settings.cell_size", "nan"});
  refused([&](billiard::Settings& s) { s.cell_size = inf; }, {"settings.cell_size", "inf"});
  refused([](billiard::Settings& s) { s.prefetch = static_cast<billiard::Prefetch>(7); }, {"settings.prefetch", "7"});
  // (exchange_velocities is a bool: it has no bad values.) Good settings, however extreme, make a
  // simulation that runs.
  billiard::Settings good;
  good.gravity = Vector(1e-50, -1e50);
  good.restitution = {0.0, 1.0};
  good.exchange_velocities = true;
  good.contact_duration = 0.0;
  good.elastic_impact_speed = 1e50;
  good.sleep_speed = 0.0;
  good.cell_size = 3.0;
  good.prefetch = billiard::Prefetch::On;
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(10, 10)), good);
  EXPECT_EQ(sim.gravity(), good.gravity);
  EXPECT_EQ(sim.restitution().normal, 0.0);
  EXPECT_TRUE(sim.exchange_velocities());
  sim.add_disc(make_disc(Vector(2, 2), Vector(1, 0)));
  sim.advance(10, 1e-20);
  EXPECT_EQ(sim.validate(), std::nullopt);
}

namespace {
using engine_test::same_walls;

// Runs `call`, an add_ call on `container`: refused as expect_refused says, and the container
// unchanged.
template <class Call>
void expect_container_refused(const billiard::Container& container, Call call, std::initializer_list<const char*> pieces) {
  const std::vector<billiard::WallShape> walls = container.walls();
  const std::size_t outlines = container.outlines().size();
  expect_refused(call, pieces);
  EXPECT_TRUE(same_walls(container.walls(), walls)) << *pieces.begin();
  EXPECT_EQ(container.outlines().size(), outlines) << *pieces.begin();
}
}  // namespace

TEST(Api, BadContainersAreRefusedNamingTheFunctionAndTheArgument) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  // Every shape function.
  expect_refused([&] { billiard::circular_table(-3); }, {"circular_table: radius", "-3"});
  expect_refused([&] { billiard::circular_table(nan); }, {"circular_table: radius", "nan"});
  expect_refused([&] { billiard::periodic_box(0, 10); }, {"periodic_box: width", "0"});
  expect_refused([&] { billiard::periodic_box(10, inf); }, {"periodic_box: height", "inf"});
  expect_refused([&] { billiard::box(Vector(nan, 0), Vector(1, 1)); }, {"box: lower", "nan"});
  expect_refused([&] { billiard::box(Vector(0, 0), Vector(1e51, 1)); }, {"box: upper", "1e+51"});
  expect_refused([&] { billiard::box(Vector(0, 0), Vector(1, 0)); }, {"box: upper (1, 0) must exceed lower (0, 0)"});
  billiard::Coordinates two(2, 2);
  two << 0, 0, 1, 1;
  expect_refused([&] { billiard::polygon(two); }, {"polygon: vertices needs at least 3 rows", "2"});
  billiard::Coordinates triangle(3, 2);
  triangle << 0, 0, 1, 0, 0, inf;
  expect_refused([&] { billiard::polygon(triangle); }, {"polygon: vertex 2", "inf"});
  triangle << 0, 0, 1, 0, 1, 0;
  expect_refused([&] { billiard::polygon(triangle); }, {"polygon: vertices 1 and 2 coincide"});
  expect_refused([&] { billiard::stadium(Vector(0, nan), 1, 1); }, {"stadium: centre", "nan"});
  expect_refused([&] { billiard::stadium(Vector(0, 0), -1, 1); }, {"stadium: radius", "-1"});
  expect_refused([&] { billiard::stadium(Vector(0, 0), 1, 0); }, {"stadium: length", "circular_table"});
  expect_refused([&] { billiard::sinai_billiard(Vector(inf, 0), Vector(1, 1), 0.1); }, {"sinai_billiard: lower", "inf"});
  expect_refused([&] { billiard::sinai_billiard(Vector(0, 0), Vector(1, nan), 0.1); }, {"sinai_billiard: upper", "nan"});
  expect_refused([&] { billiard::sinai_billiard(Vector(0, 0), Vector(4, 4), 2); }, {"sinai_billiard: obstacle_radius", "2"});
  expect_refused([&] { billiard::mushroom(Vector(nan, 0), 5, 2, 4); }, {"mushroom: centre", "nan"});
  expect_refused([&] { billiard::mushroom(Vector(0, 0), 0, 2, 4); }, {"mushroom: cap_radius", "0"});
  expect_refused([&] { billiard::mushroom(Vector(0, 0), 5, 12, 4); }, {"mushroom: stem_width", "got 12"});
  expect_refused([&] { billiard::mushroom(Vector(0, 0), 5, 2, -4); }, {"mushroom: stem_height", "-4"});
  billiard::Coordinates centres(2, 2);
  centres << 0, 0, 3, 0;
  expect_refused([&] { billiard::union_of_circles(billiard::Coordinates(0, 2), {}); }, {"union_of_circles: centres"});
  expect_refused([&] { billiard::union_of_circles(centres, {1, 2, 3}); }, {"union_of_circles: radii has 3 entries"});
  expect_refused([&] { billiard::union_of_circles(centres, {1, nan}); }, {"union_of_circles: circle 1: radius", "nan"});
  // Every add_ call, leaving the container as it was.
  billiard::Container box = billiard::box(Vector(0, 0), Vector(10, 10));
  expect_container_refused(box, [&] { box.add_segment(Vector(nan, 1), Vector(2, 2)); }, {"add_segment: a", "nan"});
  expect_container_refused(box, [&] { box.add_segment(Vector(1, 1), Vector(2, -inf)); }, {"add_segment: b", "inf"});
  expect_container_refused(box, [&] { box.add_segment(Vector(1, 1), Vector(1, 1)); }, {"add_segment: a and b must differ"});
  expect_container_refused(box, [&] { box.add_arc(Vector(5, 1e51), 1, 0, 1); }, {"add_arc: centre", "1e+51"});
  expect_container_refused(box, [&] { box.add_arc(Vector(5, 5), 0, 0, 1); }, {"add_arc: radius", "0"});
  expect_container_refused(box, [&] { box.add_arc(Vector(5, 5), 1, nan, 1); }, {"add_arc: start_angle", "nan"});
  expect_container_refused(box, [&] { box.add_arc(Vector(5, 5), 1, 0, inf); }, {"add_arc: end_angle", "inf"});
  expect_container_refused(box, [&] { box.add_arc(Vector(5, 5), 1, 2, 1); }, {"add_arc: end_angle - start_angle", "-1"});
  expect_container_refused(box, [&] { box.add_obstacle(Vector(inf, 5), 1); }, {"add_obstacle: centre", "inf"});
  expect_container_refused(box, [&] { box.add_obstacle(Vector(5, 5), -1); }, {"add_obstacle: radius", "-1"});
  // Obstacles are outlines: not a table, nor a periodic box, nor a shape with free walls.
  expect_container_refused(box, [&] { box.add_obstacle(billiard::circular_table(1)); },
                           {"add_obstacle: shape must be an outline"});
  expect_container_refused(box, [&] { box.add_obstacle(billiard::periodic_box(1, 1)); },
                           {"add_obstacle: shape must be an outline"});
  billiard::Container walled = billiard::box(Vector(4, 4), Vector(6, 6));
  walled.add_segment(Vector(4.5, 4.5), Vector(5.5, 5.5));
  expect_container_refused(box, [&] { box.add_obstacle(walled); },
                           {"add_obstacle: shape has walls besides its outline"});
  // Walls inside a periodic box are not supported.
  billiard::Container periodic = billiard::periodic_box(10, 10);
  expect_container_refused(periodic, [&] { periodic.add_segment(Vector(1, 1), Vector(2, 2)); },
                           {"add_segment: walls inside a periodic box"});
  expect_container_refused(periodic, [&] { periodic.add_arc(Vector(5, 5), 1, 0, 1); },
                           {"add_arc: walls inside a periodic box"});
  expect_container_refused(periodic, [&] { periodic.add_obstacle(Vector(5, 5), 1); },
                           {"add_obstacle: walls inside a periodic box"});
  expect_container_refused(periodic, [&] { periodic.add_obstacle(billiard::box(Vector(4, 4), Vector(6, 6))); },
                           {"add_obstacle: walls inside a periodic box"});
  // The containers still work.
  EXPECT_EQ(box.walls().size(), 8u);  // 4 sides + 4 corners
  EXPECT_TRUE(periodic.walls().empty());
  billiard::Simulation sim(box);
  sim.add_disc(make_disc(Vector(2, 2), Vector(1, 0.5)));
  EXPECT_EQ(sim.advance(10).collisions, 10);
  EXPECT_EQ(sim.validate(), std::nullopt);
}

TEST(Api, DiscsOutsideTheContainerOrOverAWallAreRefused) {
  // The container comes first, so a container or a wall can no longer be refused for the discs
  // it would leave outside or cross: the disc is refused instead, by the same rules.
  billiard::Simulation table(billiard::circular_table(2));
  expect_refused([&] { table.add_disc(make_disc(Vector(2, 2), Vector(1, 0))); }, {"disc 0", "outside the table"});
  billiard::Container walled = billiard::box(Vector(0, 0), Vector(10, 10));
  const int segment = walled.add_segment(Vector(0, 2), Vector(5, 2));
  billiard::Simulation sim(walled);
  const std::string over_segment = "overlaps wall " + std::to_string(segment);
  expect_refused([&] { sim.add_disc(make_disc(Vector(2, 2), Vector(1, 0))); }, {"disc 0", over_segment.c_str()});
  EXPECT_EQ(table.size(), 0);
  EXPECT_EQ(sim.size(), 0);
}

TEST(Api, AddDiscsIsAllOrNothing) {
  billiard::Simulation sim(billiard::circular_table(10));
  billiard::Coordinates positions(3, 2), velocities(3, 2);
  positions << 0, 0, 3, 0, 3.5, 0;  // the third overlaps the second
  velocities.setZero();
  expect_refused([&] { sim.add_discs(positions, velocities, 1.0); }, {"disc 2", "overlaps disc 1"});
  EXPECT_EQ(sim.size(), 0);
  positions(2, 0) = -3;
  EXPECT_EQ(sim.add_discs(positions, velocities, 1.0), 0);
  EXPECT_EQ(sim.size(), 3);
}

TEST(Api, PeriodicOverlapThroughTheBoundaryIsRefused) {
  billiard::Simulation sim(billiard::periodic_box(10, 10));
  sim.add_disc(make_disc(Vector(0.5, 5), Vector(0, 0)));
  expect_refused([&] { sim.add_disc(make_disc(Vector(9.5, 5), Vector(0, 0))); }, {"disc 1", "overlaps disc 0"});
  expect_refused([&] { sim.add_disc(make_disc(Vector(10, 5), Vector(0, 0))); }, {"disc 1", "outside"});
}

TEST(Api, SetupIsFixedAfterTheFirstAdvance) {
  billiard::Simulation sim = two_discs();
  sim.advance(1);
  EXPECT_THROW(sim.add_disc(make_disc(Vector(8, 2), Vector(0, 0), 0.5)), std::logic_error);
  billiard::Coordinates positions(1, 2), velocities(1, 2);
  positions << 8, 2;
  velocities << 0, 0;
  EXPECT_THROW(sim.add_discs(positions, velocities, 0.5), std::logic_error);
  EXPECT_THROW(sim.add_random_discs(1, 0.5), std::logic_error);
  EXPECT_EQ(sim.size(), 2);
  sim.set_restitution({0.9});  // allowed at any time
  EXPECT_EQ(sim.advance(5).collisions, 5);
}

// A simulation without a container cannot be made: neither it nor an empty container can be
// constructed.
static_assert(!std::is_default_constructible_v<billiard::Simulation>);
static_assert(!std::is_default_constructible_v<billiard::Container>);

TEST(Api, NoDiscsAndOneDisc) {
  billiard::Simulation empty(billiard::circular_table(1));
  const auto r = empty.advance(100, 3.0);
  EXPECT_EQ(r.collisions, 0);
  EXPECT_EQ(empty.current_state().positions.rows(), 0);
  // No event ever comes, so the duration passes and the clock stops exactly at it.
  EXPECT_EQ(empty.time(), 3.0);
  EXPECT_EQ(r.elapsed, 3.0);
  billiard::Simulation one(billiard::circular_table(5));
  one.add_disc(make_disc(Vector(0, 0), Vector(0, 1)));
  EXPECT_EQ(one.advance(7).collisions, 7);
  EXPECT_EQ(one.validate(), std::nullopt);
}

TEST(Api, AdvanceStopsAtEventsOrDurationWhicheverFirst) {
  // One disc in the table of radius 10 bouncing along a diameter (radius 1, speed 2):
  // collisions at 4.5, 13.5, 22.5, ...
  billiard::Simulation sim(billiard::circular_table(10));
  sim.add_disc(make_disc(Vector(0, 0), Vector(2, 0)));
  auto r = sim.advance(100, 10.0);  // duration first: one collision, clock at 10
  EXPECT_EQ(r.collisions, 1);
  EXPECT_DOUBLE_EQ(sim.time(), 10.0);
  EXPECT_DOUBLE_EQ(r.elapsed, 10.0);
  EXPECT_NEAR(sim.current_state().positions(0, 0), 9 - 2 * 5.5, 1e-14);
  r = sim.advance(1, 100.0);  // events first: stops at the collision at 13.5
  EXPECT_EQ(r.collisions, 1);
  EXPECT_DOUBLE_EQ(sim.time(), 13.5);
}

TEST(Api, ReplayReproducesTheRunByEventAndAtFixedTimeSteps) {
  // The log (positions and velocities after every collision) and the initial state rebuild the
  // state after any event and at any time; compared with the live run to 1e-12 (positions are
  // extrapolated over different intervals, so they differ by rounding only).
  std::mt19937_64 rng(41);
  billiard::Settings settings;
  settings.gravity = Vector(0, -0.5);
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(20, 20)), settings);
  const auto discs = engine_test::random_discs(rng, 20, 0.5, 1.0, Vector(0, 0), Vector(20, 20), [](const Vector& p, double a) {
    return p.x() >= a && p.x() <= 20 - a && p.y() >= a && p.y() <= 20 - a;
  });
  engine_test::add_all(sim, discs);
  sim.set_log_events(true);
  const billiard::State start = sim.initial_state();
  sim.advance(500);
  const billiard::State after500 = sim.current_state();
  sim.advance(billiard::kAllEvents, 0.25);
  const billiard::State later = sim.current_state();
  // By event: the last logged event is the 500th collision.
  const billiard::State replayed = billiard::Replay(sim).after_event(499);
  EXPECT_DOUBLE_EQ(replayed.time, after500.time);
  EXPECT_LT((replayed.positions - after500.positions).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((replayed.velocities - after500.velocities).cwiseAbs().maxCoeff(), 1e-12);
  // At fixed time steps: t = 0 is the initial state, and the current time matches the live run.
  const billiard::State zero = billiard::Replay(sim).at(0.0);
  EXPECT_EQ(zero.positions, start.positions);
  const billiard::State at_end = billiard::Replay(sim).at(later.time);
  EXPECT_LT((at_end.positions - later.positions).cwiseAbs().maxCoeff(), 1e-12);
  // Replay at steps of 0.1 never shows an overlap (a disc replayed correctly between events).
  for (double t = 0; t < later.time; t += 0.1) {
    const billiard::State s = billiard::Replay(sim).at(t);
    for (int i = 0; i < s.positions.rows(); ++i) {
      for (int j = i + 1; j < s.positions.rows(); ++j) {
        const double d = (s.positions.row(i) - s.positions.row(j)).norm();
        ASSERT_GE(d, discs.radii[i] + discs.radii[j] - 1e-9) << "t = " << t;
      }
    }
  }
}

TEST(Api, ParallelDiscsInAPeriodicBoxDoNotHangAdvance) {
  // No collision can ever happen: advance(1) without a duration must return (stuck), not spin.
  billiard::Simulation sim(billiard::periodic_box(10, 10));
  sim.add_disc(make_disc(Vector(5, 5), Vector(1, 0.3)));
  const auto r = sim.advance(1);
  EXPECT_EQ(r.collisions, 0);
  EXPECT_TRUE(r.stuck);
}

// The check of the discs each collision changed (set_check_event_discs, O(1) per event) is
// what the 10^8-collision stress run relies on: in valid runs in every kind of container it must
// report nothing (a wrong image shift, or a disc compared with itself, would report an overlap)
// and stop no run early. (That it finds real overlaps was checked by hand with a broken engine
// that ignores pairs across the periodic boundary: it stopped at collision 56 of a run of 400
// discs, validate() after every event at collision 4.)
TEST(Api, CheckingTheEventDiscsFindsNothingInValidRuns) {
  auto container_of = [](int container) {
    if (container == 0) return billiard::circular_table(30.0);
    if (container == 1) return billiard::box(Vector(0, 0), Vector(50, 50));
    if (container == 2) return billiard::periodic_box(50, 50);
    billiard::Coordinates notched(5, 2);  // with a notch: a corner pointing inwards
    notched << 0, 0, 60, 0, 60, 60, 30, 25, 0, 60;
    return billiard::polygon(notched);
  };
  for (int container = 0; container < 4; ++container) {
    billiard::Simulation sim(container_of(container));
    sim.add_random_discs(container == 3 ? 300 : 400, 1.0, 1.0, 1.0, 11);
    sim.set_check_event_discs(true);
    const auto result = sim.advance(30000);
    EXPECT_EQ(sim.last_problem(), std::nullopt) << "container " << container;
    EXPECT_EQ(result.collisions, 30000) << "container " << container;
    EXPECT_EQ(sim.validate(), std::nullopt) << "container " << container;
  }
}

TEST(Api, InitialStateIsKept) {
  billiard::Simulation sim = two_discs();
  const billiard::State before = sim.initial_state();
  sim.advance(20);
  EXPECT_EQ(sim.initial_state().positions, before.positions);
  EXPECT_EQ(sim.initial_state().velocities, before.velocities);
  EXPECT_EQ(sim.initial_state().time, 0.0);
}

TEST(Api, WallMomentumGivesTheIdealGasPressure) {
  // A single disc bouncing between x walls of a box [0, 10] (radius 1: free length 8) at speed
  // 2: each hit gives momentum 4, one hit every 4 time units: 1 per unit time. Over 100 time
  // units: 100 (one boundary hit may straddle the end: +-4).
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(10, 10)));
  sim.add_disc(make_disc(Vector(5, 5), Vector(2, 0)));
  sim.advance(billiard::kAllEvents, 100.0);
  EXPECT_NEAR(sim.totals().wall_momentum, 100.0, 4.0);
  EXPECT_EQ(sim.totals().wall_collisions, 25);
}

TEST(Api, MemoryPerDiscIsSmall) {
  const double side = std::sqrt(10000 * M_PI / 0.5);
  billiard::Simulation sim(billiard::periodic_box(side, side));
  billiard::Coordinates positions(10000, 2), velocities(10000, 2);
  for (int k = 0; k < 10000; ++k) positions.row(k) << (k % 100 + 0.5) * side / 100, (k / 100 + 0.5) * side / 100;
  std::mt19937_64 rng(42);
  std::normal_distribution<double> normal;
  for (int k = 0; k < 10000; ++k) velocities.row(k) << normal(rng), normal(rng);
  sim.add_discs(positions, velocities, 1.0);
  sim.advance(1000);
  EXPECT_LT(sim.memory_bytes() / 10000, 1024.0);
}
