// The engine's public headers stand on their own: none of them includes the course contract
// (billiard/course.hpp), so an engine user gets neither its names nor its <random> and
// <filesystem>. If one did, the declarations below would clash with the course's and this file
// would not compile.
#include "collide.hpp"
#include "billiard/engine/disc.hpp"
#include "billiard/engine/replay.hpp"
#include "billiard/engine/simulation.hpp"
#include "time_of_impact.hpp"
#include "billiard/engine/plane.hpp"
#include "billiard/engine/wall.hpp"

#include <gtest/gtest.h>

namespace billiard {
// Names the course contract declares, declared here as something else.
struct Collision {
  int wall_hits = 0;
};
using Rng = int;
}  // namespace billiard

namespace {

// The engine alone, through these headers: a disc sent at the table's wall hits it at t = 1.
TEST(Layers, EngineHeadersWorkWithoutTheCourse) {
  billiard::Simulation sim(billiard::circular_table(3.0));
  billiard::Disc disc;
  disc.velocity = {2.0, 0.0};
  sim.add_disc(disc);
  sim.set_log_events(true);
  sim.advance(1);
  ASSERT_EQ(sim.event_log().size(), 1u);
  const billiard::EventRecord& hit = sim.event_log()[0];
  billiard::Collision counted;
  counted.wall_hits += hit.kind == billiard::EventKind::DiscWall && hit.other == billiard::kWall;
  EXPECT_EQ(counted.wall_hits, 1);
  EXPECT_NEAR(hit.time, 1.0, 1e-12);  // (3 - 1) / 2
}

}  // namespace
