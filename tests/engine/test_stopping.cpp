// Stopping a run between two events: Simulation::request_stop (from another thread, or before the
// run) and advance()'s should_stop check (which Python's binding uses for Ctrl-C). A stopped run
// leaves a valid state from which advance() goes on to exactly the future of an unstopped run.
#include "billiard/engine/simulation.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using billiard::Vector;

namespace {

// A gas of equal smooth discs in a periodic box (it never stops by itself).
billiard::Simulation gas() {
  billiard::Simulation sim(billiard::periodic_box(60, 60));
  sim.add_random_discs(500, 1.0, 1.0, 1.0, 7);
  sim.set_log_events(true);
  return sim;
}

// Rough inelastic discs falling in a box under gravity: the granular model's rules (contact
// duration, sleeping) keep state across events, and must carry over a stop as well.
billiard::Simulation granular_bed() {
  billiard::Settings settings;
  settings.gravity = {0, -1};
  settings.restitution = {0.8, 0.5};
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(40, 40)), settings);
  sim.add_random_discs(200, 1.0, 1.0, 1.0, 3);
  sim.set_log_events(true);
  return sim;
}

struct System {
  const char* name;
  std::function<billiard::Simulation()> make;
  std::int64_t events;  // of the whole run
};

const std::vector<System>& systems() {
  static const std::vector<System> all = {{"gas", gas, 2000}, {"granular bed", granular_bed, 20000}};
  return all;
}

// Stops the run as soon as it has done `collisions` collisions (asked after every event).
billiard::StopCheck stop_after(std::int64_t collisions) {
  return [collisions](const billiard::AdvanceResult& so_far) { return so_far.collisions >= collisions; };
}

// Two simulations in the same state, bit for bit, with the same history of events.
void expect_identical(const billiard::Simulation& a, const billiard::Simulation& b, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(a.time(), b.time());
  const billiard::State sa = a.current_state();
  const billiard::State sb = b.current_state();
  EXPECT_TRUE((sa.positions.array() == sb.positions.array()).all());
  EXPECT_TRUE((sa.velocities.array() == sb.velocities.array()).all());
  EXPECT_TRUE((sa.spins.array() == sb.spins.array()).all());
  EXPECT_EQ(a.totals().disc_collisions, b.totals().disc_collisions);
  EXPECT_EQ(a.totals().wall_collisions, b.totals().wall_collisions);
  EXPECT_EQ(a.totals().cell_crossings, b.totals().cell_crossings);
  EXPECT_EQ(a.totals().virial, b.totals().virial);
  EXPECT_EQ(a.totals().wall_momentum, b.totals().wall_momentum);
  EXPECT_EQ(a.sleeping_discs(), b.sleeping_discs());
  const auto& la = a.event_log();
  const auto& lb = b.event_log();
  ASSERT_EQ(la.size(), lb.size());
  for (std::size_t k = 0; k < la.size(); ++k) {
    ASSERT_TRUE(la[k].time == lb[k].time && la[k].kind == lb[k].kind && la[k].disc == lb[k].disc &&
                la[k].other == lb[k].other && la[k].wall == lb[k].wall)
        << "event " << k;
  }
}

}  // namespace

TEST(Stopping, AStoppedRunGoesOnExactlyAsAnUnstoppedOne) {
  for (const System& system : systems()) {
    billiard::Simulation whole = system.make();
    const billiard::AdvanceResult all = whole.advance(system.events);
    ASSERT_EQ(all.collisions, system.events);
    EXPECT_FALSE(all.stopped);
    for (const std::int64_t stop_at : {std::int64_t{1}, system.events / 3, system.events - 1}) {
      const std::string what = std::string(system.name) + ", stopped after " + std::to_string(stop_at);
      billiard::Simulation parts = system.make();
      const billiard::AdvanceResult first = parts.advance(system.events, billiard::kNever, stop_after(stop_at), 1);
      EXPECT_TRUE(first.stopped) << what;
      EXPECT_FALSE(first.stuck) << what;
      EXPECT_EQ(first.collisions, stop_at) << what;
      EXPECT_EQ(parts.validate(), std::nullopt) << what;
      const billiard::AdvanceResult rest = parts.advance(system.events - stop_at);
      EXPECT_FALSE(rest.stopped) << what;
      EXPECT_EQ(first.collisions + rest.collisions, system.events) << what;
      expect_identical(whole, parts, what);
    }
  }
}

TEST(Stopping, ManyStopsInOneRunChangeNothing) {
  for (const System& system : systems()) {
    billiard::Simulation whole = system.make();
    whole.advance(system.events);
    billiard::Simulation parts = system.make();
    std::int64_t done = 0;
    int stops = 0;
    while (done < system.events) {
      const billiard::AdvanceResult r = parts.advance(system.events - done, billiard::kNever, stop_after(7), 1);
      done += r.collisions;
      stops += r.stopped;
    }
    EXPECT_EQ(stops, (system.events - 1) / 7) << system.name;  // (the last part ends by its limit)
    EXPECT_EQ(parts.validate(), std::nullopt) << system.name;
    expect_identical(whole, parts, system.name);
  }
}

TEST(Stopping, RequestStopFromAnotherThreadStopsARunningAdvance) {
  using Clock = std::chrono::steady_clock;
  billiard::Simulation sim = gas();
  sim.set_log_events(false);
  sim.advance(100);
  // The run reports its progress, so that the request comes while it runs (and, should
  // request_stop fail, gives up after a minute rather than run for ever).
  std::atomic<std::int64_t> progress{0};
  const Clock::time_point started = Clock::now();
  const billiard::StopCheck report = [&](const billiard::AdvanceResult& so_far) {
    progress.store(so_far.collisions);
    return Clock::now() - started > std::chrono::seconds(60);
  };
  std::atomic<Clock::rep> requested_at{0};
  std::thread stopper([&] {
    while (progress.load() < 10000) std::this_thread::yield();
    requested_at.store(Clock::now().time_since_epoch().count());
    sim.request_stop();
  });
  const billiard::AdvanceResult r = sim.advance(billiard::kAllEvents, billiard::kNever, report, 100);
  const Clock::time_point returned = Clock::now();
  stopper.join();
  EXPECT_TRUE(r.stopped);
  EXPECT_FALSE(r.stuck);
  EXPECT_GE(r.collisions, 10000);
  const double latency = std::chrono::duration<double>(returned.time_since_epoch() -
                                                       Clock::duration(requested_at.load())).count();
  EXPECT_LT(latency, 0.5) << "seconds from request_stop to the return of advance";
  EXPECT_EQ(sim.validate(), std::nullopt);
  EXPECT_EQ(sim.totals().disc_collisions + sim.totals().wall_collisions, 100 + r.collisions);
  // The request was used up: the next run goes on to its limit.
  const billiard::AdvanceResult next = sim.advance(1000);
  EXPECT_FALSE(next.stopped);
  EXPECT_EQ(next.collisions, 1000);
  EXPECT_EQ(sim.validate(), std::nullopt);
}

TEST(Stopping, RequestStopStopsARunWithoutACheck) {
  using Clock = std::chrono::steady_clock;
  billiard::Simulation sim = gas();
  sim.set_log_events(false);
  sim.advance(100);
  std::atomic<Clock::rep> requested_at{0};
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    requested_at.store(Clock::now().time_since_epoch().count());
    sim.request_stop();
  });
  // About 20 seconds of events, should the request be missed.
  const billiard::AdvanceResult r = sim.advance(50000000);
  const Clock::time_point returned = Clock::now();
  stopper.join();
  EXPECT_TRUE(r.stopped);
  EXPECT_LT(r.collisions, 50000000);
  const double latency = std::chrono::duration<double>(returned.time_since_epoch() -
                                                       Clock::duration(requested_at.load())).count();
  EXPECT_LT(latency, 0.5) << "seconds from request_stop to the return of advance";
  EXPECT_EQ(sim.validate(), std::nullopt);
  EXPECT_EQ(sim.advance(1000).collisions, 1000);
}

TEST(Stopping, ARequestBetweenRunsStopsTheNextBeforeItsFirstEvent) {
  billiard::Simulation sim = gas();
  sim.advance(100);
  const double time = sim.time();
  sim.request_stop();
  billiard::Simulation copy(sim);  // a copy starts without the request
  const billiard::AdvanceResult stopped = sim.advance(1000, 5.0);
  EXPECT_TRUE(stopped.stopped);
  EXPECT_EQ(stopped.collisions, 0);
  EXPECT_EQ(stopped.cell_crossings + stopped.stale_events, 0);
  EXPECT_EQ(stopped.elapsed, 0.0);
  EXPECT_EQ(sim.time(), time);
  const billiard::AdvanceResult next = sim.advance(1000);
  EXPECT_FALSE(next.stopped);
  EXPECT_EQ(next.collisions, 1000);
  const billiard::AdvanceResult copied = copy.advance(1000);
  EXPECT_FALSE(copied.stopped);
  EXPECT_EQ(copied.collisions, 1000);
  expect_identical(sim, copy, "the copy made while a stop was requested");
}

TEST(Stopping, ACheckThatThrowsStopsTheRunAndKeepsItsCounts) {
  billiard::Simulation whole = gas();
  whole.advance(2000);
  billiard::Simulation parts = gas();
  billiard::AdvanceResult seen;
  const billiard::StopCheck throw_at_500 = [&](const billiard::AdvanceResult& so_far) -> bool {
    seen = so_far;
    if (so_far.collisions >= 500) throw std::runtime_error("enough");
    return false;
  };
  EXPECT_THROW(parts.advance(2000, billiard::kNever, throw_at_500, 1), std::runtime_error);
  EXPECT_EQ(seen.collisions, 500);
  // The totals hold the events done before the throw, and the state is valid.
  EXPECT_EQ(parts.totals().disc_collisions, seen.disc_collisions);
  EXPECT_EQ(parts.totals().wall_collisions, seen.wall_collisions);
  EXPECT_EQ(parts.totals().cell_crossings, seen.cell_crossings);
  EXPECT_EQ(parts.validate(), std::nullopt);
  EXPECT_EQ(parts.advance(1500).collisions, 1500);
  expect_identical(whole, parts, "after a throwing check");
}

TEST(Stopping, TheCheckIsAskedEveryCheckIntervalQueueEntries) {
  billiard::Simulation sim = gas();
  std::int64_t asked = 0;
  const billiard::StopCheck count = [&](const billiard::AdvanceResult&) {
    ++asked;
    return false;
  };
  const billiard::AdvanceResult r = sim.advance(10000, billiard::kNever, count, 100);
  EXPECT_FALSE(r.stopped);
  EXPECT_EQ(r.collisions, 10000);
  EXPECT_GT(r.cell_crossings, 0);
  // Before the first event, then after every 100.
  EXPECT_EQ(asked, 1 + (r.collisions + r.cell_crossings + r.stale_events - 1) / 100);
  // No check at all (an empty function) is fine; an interval below 1 is refused, naming it.
  EXPECT_EQ(sim.advance(100, billiard::kNever, nullptr).collisions, 100);
  try {
    sim.advance(100, billiard::kNever, count, 0);
    ADD_FAILURE() << "check_interval 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("check_interval must be >= 1, got 0"), std::string::npos) << e.what();
  }
}

TEST(Stopping, ANanDurationIsRefusedAsNotANumber) {
  billiard::Simulation sim = gas();
  const auto message = [&](double duration) -> std::string {
    try {
      sim.advance(10, duration);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  };
  const std::string nan = message(std::nan(""));
  EXPECT_NE(nan.find("advance: max_duration must be a number >= 0, got "), std::string::npos) << nan;
  EXPECT_NE(nan.find("nan (not a number)"), std::string::npos) << nan;
  const std::string negative = message(-2.0);
  EXPECT_EQ(negative, "advance: max_duration must be a number >= 0, got -2");
  EXPECT_EQ(sim.time(), 0.0);
}
