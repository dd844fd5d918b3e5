// The engine's trajectories, kept: a fixed set of runs (one per kind of container and of
// physics) and a checksum of each run's event log, every bit of every logged number. A change
// to how a system is described or set up must leave them all alone; a change to the physics or
// its arithmetic shows here first, and then the checksums are updated on purpose (the failure
// prints the new ones) with the reason in the commit.
//
// Each run: random discs (the engine's own seeded placement and velocities), 3000 events.
// Checksum: FNV-1a, 64 bits, over each record's fields in order.
#include "billiard/engine/simulation.hpp"

#include "helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

using billiard::Vector;

namespace {

constexpr std::int64_t kEvents = 3000;

class Checksum {
 public:
  template <typename T>
  void add(const T& value) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    for (const unsigned char byte : bytes) hash_ = (hash_ ^ byte) * 1099511628211ULL;
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 14695981039346656037ULL;
};

std::uint64_t checksum_of(const std::vector<billiard::EventRecord>& log) {
  Checksum sum;
  for (const auto& e : log) {
    sum.add(e.time);
    sum.add(static_cast<int>(e.kind));
    sum.add(e.disc);
    sum.add(e.other);
    sum.add(e.wall);
    for (const Vector* v : {&e.position, &e.velocity, &e.other_position, &e.other_velocity}) {
      sum.add(v->x());
      sum.add(v->y());
    }
    sum.add(e.spin);
    sum.add(e.other_spin);
  }
  return sum.value();
}

struct FixedRun {
  const char* name;
  std::uint64_t checksum;  // of this build's log; see the top of the file
  std::function<billiard::Simulation()> make;
  int discs;
  double radius;
};

// A regular hexagon of circumradius r about the origin.
billiard::Coordinates hexagon(double r) {
  billiard::Coordinates vertices(6, 2);
  for (int k = 0; k < 6; ++k) vertices.row(k) << r * std::cos(k * M_PI / 3), r * std::sin(k * M_PI / 3);
  return vertices;
}

const std::vector<FixedRun>& runs() {
  using billiard::Simulation;
  static const std::vector<FixedRun> all = {
      {"table", 0x3ce768ab6644dfddULL, [] { return Simulation(billiard::circular_table(10)); }, 40, 0.4},
      {"box", 0xf15fa5d3756a22c6ULL, [] { return Simulation(billiard::box(Vector(0, 0), Vector(20, 20))); }, 60, 0.5},
      {"periodic", 0xdac3eacdb051b83aULL, [] { return Simulation(billiard::periodic_box(20, 20)); }, 80, 0.5},
      {"polygon", 0x3c03490c46b33bc2ULL, [] { return Simulation(billiard::polygon(hexagon(10))); }, 40, 0.4},
      {"stadium", 0xc1adb2799600ea83ULL, [] { return Simulation(billiard::stadium(Vector(0, 0), 5, 8)); }, 30, 0.3},
      {"gravity", 0x5ec6aad2301f945fULL,
       [] { return Simulation(billiard::box(Vector(0, 0), Vector(20, 20)), engine_test::physics(Vector(0.3, -1))); }, 40, 0.5},
      {"rough", 0xc66099e1e4db5531ULL, [] { return Simulation(billiard::box(Vector(0, 0), Vector(20, 20)), engine_test::physics(Vector::Zero(), {1.0, 1.0})); }, 40, 0.5},
      {"granular", 0x67430b30221933afULL,
       [] { return Simulation(billiard::box(Vector(0, 0), Vector(20, 20)), engine_test::physics(Vector(0, -1), {0.9, -1})); }, 60, 0.5},
  };
  return all;
}

TEST(EventLogs, FixedRunsKeepTheirTrajectoriesToTheLastBit) {
  std::string changed;
  std::uint64_t seed = 0;
  for (const FixedRun& run : runs()) {
    billiard::Simulation sim = run.make();
    sim.add_random_discs(run.discs, run.radius, 1.0, 1.0, ++seed);
    sim.set_log_events(true);
    sim.advance(kEvents);
    ASSERT_GE(sim.event_log().size(), static_cast<std::size_t>(kEvents) / 2) << run.name;
    const std::uint64_t got = checksum_of(sim.event_log());
    if (got != run.checksum) {
      char line[96];
      std::snprintf(line, sizeof line, "  {\"%s\", 0x%016llxULL, ...}\n", run.name, static_cast<unsigned long long>(got));
      changed += line;
    }
  }
  EXPECT_TRUE(changed.empty()) << "these runs' event logs changed (their checksums now):\n" << changed
                               << "Description or set-up changes must not change them; if the physics or its "
                                  "arithmetic changed on purpose, put the new values in this file.";
}

TEST(EventLogs, TheChecksumSeesEveryField) {
  // A log differing in one bit of any one field has another checksum.
  billiard::EventRecord record;
  record.time = 1.5;
  record.position = Vector(1, 2);
  const std::uint64_t base = checksum_of({record});
  std::vector<std::function<void(billiard::EventRecord&)>> changes = {
      [](auto& r) { r.time = std::nextafter(r.time, 2.0); },
      [](auto& r) { r.kind = billiard::EventKind::DiscWall; },
      [](auto& r) { r.disc = 1; },
      [](auto& r) { r.other = 1; },
      [](auto& r) { r.wall = 0; },
      [](auto& r) { r.position.y() = std::nextafter(2.0, 3.0); },
      [](auto& r) { r.velocity.x() = 1e-300; },
      [](auto& r) { r.spin = -0.0; },
      [](auto& r) { r.other_position.x() = 1; },
      [](auto& r) { r.other_velocity.y() = 1; },
      [](auto& r) { r.other_spin = 1; }};
  for (std::size_t k = 0; k < changes.size(); ++k) {
    billiard::EventRecord changed = record;
    changes[k](changed);
    EXPECT_NE(checksum_of({changed}), base) << "change " << k;
  }
}

}  // namespace
