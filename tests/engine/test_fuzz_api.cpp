// Fuzzing of the public Simulation API: thousands of random calls with bad or extreme arguments
// (nan, infinities, 1e308, denormals, -0.0, negative and out-of-range counts, mismatched arrays),
// from a fixed seed, on simulations in every kind of state. The contract (simulation.hpp):
//  - a bad argument: std::invalid_argument whose message names the argument;
//  - a setup call after the first advance, or advance() without a container: std::logic_error,
//    whatever the arguments (the call is the mistake);
//  - either way the simulation is unchanged, bit for bit, still valid, and advances exactly like
//    an untouched copy;
//  - a call that is valid, however extreme, returns quickly and leaves a valid simulation whose
//    discs stay finite as it advances.
#include "billiard/engine/replay.hpp"
#include "billiard/engine/simulation.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using billiard::Disc;
using billiard::Points;
using billiard::Simulation;
using billiard::Vec2;
using engine_test::make_disc;

namespace {

using Rng = std::mt19937_64;
constexpr std::uint64_t kSeed = 0x5eed;
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMax = std::numeric_limits<double>::max();
constexpr double kDenormal = std::numeric_limits<double>::denorm_min();
// A generous bound per call: the slowest legitimate call here takes milliseconds.
constexpr double kSecondsPerCall = 5.0;

// ---- Snapshots: everything the public API shows, as bits, with a label per entry ----

struct Snapshot {
  std::vector<std::uint64_t> bits;
  std::vector<const char*> labels;
  void add(const char* label, double x) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    bits.push_back(b);
    labels.push_back(label);
  }
  void add(const char* label, std::int64_t k) {
    bits.push_back(static_cast<std::uint64_t>(k));
    labels.push_back(label);
  }
  template <class Matrix>
  void add_all(const char* label, const Matrix& m) {
    add(label, static_cast<std::int64_t>(m.size()));
    for (Eigen::Index k = 0; k < m.size(); ++k) add(label, m.data()[k]);
  }
  void add(const char* label, const Vec2& v) {
    add(label, v.x());
    add(label, v.y());
  }
};

void add_state(Snapshot& s, const billiard::State& state) {
  s.add("state time", state.time);
  s.add_all("positions", state.positions);
  s.add_all("velocities", state.velocities);
  s.add_all("spins", state.spins);
}

Snapshot snapshot(const Simulation& sim) {
  Snapshot s;
  s.add("size", std::int64_t{sim.size()});
  s.add("time", sim.time());
  add_state(s, sim.current_state());
  add_state(s, sim.initial_state());
  s.add_all("radii", sim.radii());
  s.add_all("masses", sim.masses());
  s.add_all("inertias", sim.inertias());
  s.add("walls", static_cast<std::int64_t>(sim.walls().size()));
  for (const billiard::WallShape& w : sim.walls()) {
    s.add("wall kind", static_cast<std::int64_t>(w.kind));
    s.add("wall a", w.a);
    s.add("wall b", w.b);
    s.add("wall radius", w.radius);
  }
  s.add("gravity", sim.gravity());
  s.add("restitution", sim.restitution().normal);
  s.add("restitution", sim.restitution().tangential);
  s.add("contact duration", sim.contact_duration());
  s.add("elastic impact speed", sim.elastic_impact_speed());
  s.add("sleep speed", sim.sleep_speed());
  s.add("sleeping discs", static_cast<std::int64_t>(sim.sleeping_discs().size()));
  s.add("periodic", std::int64_t{sim.periodic()});
  s.add("period", sim.period());
  s.add("table radius", sim.table_radius());
  s.add("cells", std::int64_t{sim.cell_count()});
  const billiard::Totals t = sim.totals();
  s.add("totals", t.wall_momentum);
  s.add("totals", t.virial);
  s.add("totals", t.disc_collisions);
  s.add("totals", t.wall_collisions);
  s.add("totals", t.cell_crossings);
  s.add("event log", static_cast<std::int64_t>(sim.event_log().size()));
  for (const billiard::EventRecord& e : sim.event_log()) {
    s.add("event", e.time);
    s.add("event", std::int64_t{e.disc});
    s.add("event", std::int64_t{e.other});
    s.add("event", std::int64_t{e.wall});
    s.add("event", e.position);
    s.add("event", e.velocity);
    s.add("event", e.other_position);
    s.add("event", e.other_velocity);
  }
  s.add("kinetic energy", sim.kinetic_energy());
  s.add("potential energy", sim.potential_energy());
  s.add("last problem", static_cast<std::int64_t>(std::hash<std::string>()(sim.last_problem().value_or(""))));
  return s;
}

// "" if equal bit for bit, else the first difference.
std::string difference(const Snapshot& before, const Snapshot& after) {
  const std::size_t n = std::min(before.bits.size(), after.bits.size());
  for (std::size_t k = 0; k < n; ++k) {
    if (before.bits[k] != after.bits[k] || before.labels[k] != after.labels[k]) {
      return std::string("first difference at entry ") + std::to_string(k) + " (" + after.labels[k] + ")";
    }
  }
  if (before.bits.size() != after.bits.size()) return "the snapshots differ in length";
  return "";
}

bool started(const Simulation& sim) { return sim.cell_count() > 0; }

// ---- Starting states ----

struct Start {
  const char* name;
  Simulation sim;
  bool container = true;  // (walls alone, such as a segment, are no container)
};

std::vector<Start> starts() {
  std::vector<Start> out;
  out.push_back({"empty", Simulation(), false});
  {
    Simulation sim;
    sim.add_disc(make_disc(Vec2(1, 2), Vec2(0.5, -1)));  // discs before any container are allowed
    out.push_back({"discs without a container", sim, false});
  }
  {
    Simulation sim;
    sim.set_circular_table(5);
    out.push_back({"table without discs", sim});
  }
  {
    Simulation sim;
    sim.set_circular_table(10);
    sim.add_random_discs(20, 0.5, 1.0, 1.0, 1);
    out.push_back({"table", sim});
  }
  {
    Simulation sim;
    sim.add_box(Vec2(0, 0), Vec2(20, 10));
    sim.add_disc(make_disc(Vec2(1, 1), Vec2(1, 0), 0.3, 0.5));
    sim.add_random_discs(25, 0.4, 2.0, 1.0, 2);
    out.push_back({"box", sim});
  }
  {
    Simulation sim;
    sim.set_periodic_box(20, 15);
    sim.add_random_discs(30, 0.5, 1.0, 1.0, 3);
    out.push_back({"periodic box", sim});
  }
  {
    Simulation sim;
    Points hexagon(6, 2);
    for (int k = 0; k < 6; ++k) hexagon.row(k) << 10 * std::cos(k * M_PI / 3), 10 * std::sin(k * M_PI / 3);
    sim.add_polygon(hexagon);
    sim.add_segment(Vec2(-2, -2), Vec2(2, 3));
    sim.add_random_discs(15, 0.6, 1.0, 1.0, 4);
    out.push_back({"polygon and a segment", sim});
  }
  {
    Simulation sim;
    sim.add_box(Vec2(0, 0), Vec2(15, 15));
    sim.set_gravity(Vec2(0.1, -2));
    sim.add_random_discs(20, 0.5, 1.0, 1.0, 5);
    out.push_back({"box with gravity", sim});
  }
  {
    Simulation sim;
    sim.add_box(Vec2(0, 0), Vec2(20, 20));
    sim.add_random_discs(30, 0.5, 1.0, 1.0, 6);
    sim.enable_event_log(true);
    sim.advance(200);
    out.push_back({"box after 200 collisions, event log on", sim});
  }
  {
    Simulation sim;
    sim.set_periodic_box(15, 15);
    sim.set_restitution(0.9, 0.5);
    sim.add_random_discs(25, 0.5, 1.0, 1.0, 7);
    sim.enable_event_log(true);
    sim.advance(100);
    out.push_back({"rough periodic box after 100 collisions", sim});
  }
  {
    Simulation sim;
    sim.set_circular_table(3);
    sim.advance(10, 1.0);
    out.push_back({"table without discs, started", sim});
  }
  return out;
}

// ---- Values ----

// Not a number, infinite, or beyond the documented magnitudes (1e50; 1e-50 for scales).
const std::vector<double> kNotFinite = {kNan, -kNan, kInf, -kInf};
const std::vector<double> kTooLarge = {1e308, -1e308, kMax, -kMax, 1e51, -1e51, 1e300};
// Bad for a radius, mass or inertia: also zero, negative and below 1e-50.
const std::vector<double> kBadScale = {0.0, -0.0, -1.0, -1e-308, -kDenormal, 1e-308, kDenormal, 1e-51, -5.0};

template <class T>
T pick(Rng& rng, const std::vector<T>& values) {
  return values[std::uniform_int_distribution<std::size_t>(0, values.size() - 1)(rng)];
}
double uniform(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
bool coin(Rng& rng) { return std::uniform_int_distribution<int>(0, 1)(rng) == 1; }

double bad_number(Rng& rng) { return coin(rng) ? pick(rng, kNotFinite) : pick(rng, kTooLarge); }
double bad_scale(Rng& rng) { return coin(rng) ? bad_number(rng) : pick(rng, kBadScale); }
double bad_nonnegative(Rng& rng) {  // bad where >= 0 and finite is required
  return coin(rng) ? pick(rng, kNotFinite) : pick(rng, std::vector<double>{-1.0, -kDenormal, -1e308, -kMax, -kInf});
}
Vec2 bad_point(Rng& rng) {  // one or both coordinates bad
  const double good = uniform(rng, -5, 5);
  switch (std::uniform_int_distribution<int>(0, 2)(rng)) {
    case 0: return Vec2(bad_number(rng), good);
    case 1: return Vec2(good, bad_number(rng));
    default: return Vec2(bad_number(rng), bad_number(rng));
  }
}
Vec2 point(Rng& rng, double reach) { return Vec2(uniform(rng, -reach, reach), uniform(rng, -reach, reach)); }

// ---- Calls ----

enum class Expect {
  Refused,  // std::invalid_argument naming one of `names`
  Either,   // valid or not (extreme values, conflicts with the state): if refused, as above
};

struct Call {
  std::string text;                 // what was called, for the failure messages
  Expect expect = Expect::Refused;
  bool setup = true;                // a setup call: std::logic_error once started
  std::vector<std::string> names;   // the message must contain one of these
  std::function<void(Simulation&)> run;
  bool advances = false;            // advance(): std::logic_error without a container
};

std::string show(double x) {
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}
std::string show(const Vec2& v) { return "(" + show(v.x()) + ", " + show(v.y()) + ")"; }

Call refused(std::string text, std::vector<std::string> names, std::function<void(Simulation&)> run, bool setup = true) {
  return Call{std::move(text), Expect::Refused, setup, std::move(names), std::move(run)};
}

// A disc with exactly one bad field; the others fine (what add_disc checks first is named).
Call bad_disc(Rng& rng, int size) {
  Disc d = make_disc(point(rng, 3), point(rng, 2), uniform(rng, 0.1, 1), uniform(rng, 0.5, 2));
  std::string field;
  switch (std::uniform_int_distribution<int>(0, 5)(rng)) {
    case 0: d.position = bad_point(rng); field = "position"; break;
    case 1: d.velocity = bad_point(rng); field = "velocity"; break;
    case 2: d.radius = bad_scale(rng); field = "radius"; break;
    case 3: d.mass = bad_scale(rng); field = "mass"; break;
    case 4: d.inertia = bad_scale(rng); field = "inertia"; break;
    default: d.spin = bad_number(rng); field = "spin"; break;
  }
  const std::string text = "add_disc(position " + show(d.position) + ", velocity " + show(d.velocity) + ", radius " + show(d.radius) +
                           ", mass " + show(d.mass) + ", inertia " + (d.inertia ? show(*d.inertia) : "none") + ", spin " + show(d.spin) + ")";
  return refused(text, {"disc " + std::to_string(size) + ": " + field}, [d](Simulation& s) { s.add_disc(d); });
}

Call bad_discs(Rng& rng) {
  const int rows = std::uniform_int_distribution<int>(0, 4)(rng);
  Points positions(rows, 2), velocities(rows, 2);
  for (int k = 0; k < rows; ++k) {
    positions.row(k) = point(rng, 4).transpose();
    velocities.row(k) = point(rng, 1).transpose();
  }
  double radius = uniform(rng, 0.05, 0.2), mass = 1.0;
  std::vector<std::string> names;
  switch (std::uniform_int_distribution<int>(0, 3)(rng)) {
    case 0: {  // mismatched rows
      velocities.conservativeResize(rows + std::uniform_int_distribution<int>(1, 3)(rng), 2);
      velocities.setZero();
      names = {"velocities has"};
      break;
    }
    case 1: radius = bad_scale(rng); names = {"radius"}; break;
    case 2: mass = bad_scale(rng); names = {"mass"}; break;
    default: {  // one bad row: named, unless an earlier row conflicts with the state first
      const int k = std::uniform_int_distribution<int>(0, rows)(rng);
      positions.conservativeResize(std::max(rows, k + 1), 2);
      velocities.conservativeResize(std::max(rows, k + 1), 2);
      if (coin(rng)) {
        positions.row(k) = bad_point(rng).transpose();
        velocities.row(k).setZero();
      } else {
        positions.row(k) << 0.5, 0.5;
        velocities.row(k) = bad_point(rng).transpose();
      }
      names = {"position", "velocity", "overlaps", "outside", "too small"};
      break;
    }
  }
  std::ostringstream text;
  text << "add_discs(" << positions.rows() << " positions, " << velocities.rows() << " velocities, radius " << show(radius)
       << ", mass " << show(mass) << ")";
  return refused(text.str(), names, [=](Simulation& s) { s.add_discs(positions, velocities, radius, mass); });
}

Call bad_random_discs(Rng& rng, bool container) {
  int n = std::uniform_int_distribution<int>(1, 50)(rng);
  double radius = uniform(rng, 0.05, 0.3), mass = 1.0, kT = 1.0;
  std::vector<std::string> names;
  switch (std::uniform_int_distribution<int>(0, 4)(rng)) {
    case 0: n = pick(rng, std::vector<int>{-1, INT_MIN, -std::uniform_int_distribution<int>(1, INT_MAX)(rng)}); names = {"n must"}; break;
    case 1: radius = bad_scale(rng); names = {"radius"}; break;
    case 2: mass = bad_scale(rng); names = {"mass"}; break;
    case 3: kT = bad_nonnegative(rng); names = {"kT"}; break;
    default:  // impossible packings: must be refused at once, however large n is
      n = pick(rng, std::vector<int>{INT_MAX, 1 << 30, 1000000, 100000});
      radius = uniform(rng, 0.5, 2);
      names = {"fit"};
      break;
  }
  // (A container whose coordinates are too large for the radius is refused first.)
  if (names[0] == "fit") names = container ? std::vector<std::string>{"fit", "too small"} : std::vector<std::string>{"container"};
  const std::string text = "add_random_discs(" + std::to_string(n) + ", " + show(radius) + ", " + show(mass) + ", " + show(kT) + ")";
  const std::uint64_t seed = rng();
  return refused(text, names, [=](Simulation& s) { s.add_random_discs(n, radius, mass, kT, seed); });
}

Call bad_polygon(Rng& rng) {
  const int rows = std::uniform_int_distribution<int>(0, 6)(rng);
  Points vertices(rows, 2);
  for (int k = 0; k < rows; ++k) vertices.row(k) << 30 * std::cos(k * 2 * M_PI / rows), 30 * std::sin(k * 2 * M_PI / rows);
  std::vector<std::string> names = {"vertices needs"};
  if (rows >= 3) {
    const int k = std::uniform_int_distribution<int>(0, rows - 1)(rng);
    if (coin(rng)) {
      vertices.row(k) = bad_point(rng).transpose();
      names = {"vertex " + std::to_string(k)};
    } else {  // a side of zero length (or one whose squared length underflows)
      const int next = (k + 1) % rows;
      vertices.row(next) = vertices.row(k);
      if (coin(rng)) vertices(next, 0) += kDenormal;
      names = {"coincide"};
    }
  }
  return refused("add_polygon(" + std::to_string(rows) + " vertices)", names, [=](Simulation& s) { s.add_polygon(vertices); });
}

// A random bad call of any kind, for a simulation in the state of `start`.
Call bad_call(Rng& rng, const Start& start) {
  const Simulation& sim = start.sim;
  const int kinds = 18;
  switch (std::uniform_int_distribution<int>(0, kinds - 1)(rng)) {
    case 0: {
      const double r = pick(rng, std::vector<double>{kNan, kInf, -kInf, 0.0, -0.0, -1.0, -kDenormal, 1e308, 1e51, kMax});
      return refused("set_circular_table(" + show(r) + ")", {"radius"}, [r](Simulation& s) { s.set_circular_table(r); });
    }
    case 1: {
      const bool width = coin(rng);
      const double bad = coin(rng) ? bad_number(rng) : pick(rng, std::vector<double>{0.0, -0.0, -1.0, -kDenormal});
      const double w = width ? bad : uniform(rng, 10, 50), h = width ? uniform(rng, 10, 50) : bad;
      return refused("set_periodic_box(" + show(w) + ", " + show(h) + ")", {width ? "width" : "height"},
                     [=](Simulation& s) { s.set_periodic_box(w, h); });
    }
    case 2: {
      Vec2 a = point(rng, 5), b = point(rng, 5);
      std::string name;
      switch (std::uniform_int_distribution<int>(0, 2)(rng)) {
        case 0: a = bad_point(rng); name = "add_segment: a "; break;
        case 1: b = bad_point(rng); name = "add_segment: b "; break;
        default: b = a + Vec2(coin(rng) ? 0.0 : kDenormal, 0.0); name = "a and b"; break;
      }
      return refused("add_segment(" + show(a) + ", " + show(b) + ")", {name}, [=](Simulation& s) { s.add_segment(a, b); });
    }
    case 3: {
      Vec2 lower(-30, -30), upper(30, 30);
      std::string name;
      switch (std::uniform_int_distribution<int>(0, 2)(rng)) {
        case 0: lower = bad_point(rng); name = "lower"; break;
        case 1: upper = bad_point(rng); name = "upper"; break;
        default:  // upper not above lower in x or y (or by less than an underflowing step)
          upper = lower + Vec2(pick(rng, std::vector<double>{0.0, -1.0, kDenormal, 60.0}), pick(rng, std::vector<double>{0.0, -0.0, -5.0}));
          if (coin(rng)) std::swap(upper.x(), upper.y());
          name = "must exceed";
          break;
      }
      return refused("add_box(" + show(lower) + ", " + show(upper) + ")", {name}, [=](Simulation& s) { s.add_box(lower, upper); });
    }
    case 4: return bad_polygon(rng);
    case 5: {
      const Vec2 g = bad_point(rng);
      return refused("set_gravity(" + show(g) + ")", {"g must"}, [g](Simulation& s) { s.set_gravity(g); });
    }
    case 6: {
      const bool normal = coin(rng);
      const double bad = pick(rng, std::vector<double>{kNan, kInf, -kInf, -0.1, 1.5, 1.0000000000000002, -kDenormal, 1e308, -1e308});
      const double tangential_bad = pick(rng, std::vector<double>{kNan, kInf, -kInf, -1.0000000000000002, 1.5, -2.0, 1e308, -1e308});
      const double n = normal ? bad : uniform(rng, 0, 1), t = normal ? uniform(rng, -1, 1) : tangential_bad;
      return refused("set_restitution(" + show(n) + ", " + show(t) + ")", {normal ? "normal" : "tangential"},
                     [=](Simulation& s) { s.set_restitution(n, t); }, false);
    }
    case 7: {
      const double size = bad_nonnegative(rng);
      return refused("set_cell_size(" + show(size) + ")", {"size"}, [size](Simulation& s) { s.set_cell_size(size); });
    }
    case 8: {
      const int mode = pick(rng, std::vector<int>{-1, 3, 7, INT_MAX, INT_MIN});
      return refused("set_prefetch_ahead(" + std::to_string(mode) + ")", {"mode"},
                     [mode](Simulation& s) { s.set_prefetch_ahead(static_cast<Simulation::Prefetch>(mode)); });
    }
    case 9:
    case 10: return bad_disc(rng, sim.size());
    case 11: return bad_discs(rng);
    case 12: return bad_random_discs(rng, start.container);
    case 13: {
      if (coin(rng)) {
        const std::int64_t events = pick(rng, std::vector<std::int64_t>{-1, INT64_MIN, INT_MIN, -(std::int64_t{1} << 40)});
        return refused("advance(" + std::to_string(events) + ")", {"max_events"}, [events](Simulation& s) { s.advance(events); }, false);
      }
      const double duration = pick(rng, std::vector<double>{kNan, -kNan, -kInf, -1.0, -kDenormal, -1e308});
      return refused("advance(10, " + show(duration) + ")", {"max_duration"}, [duration](Simulation& s) { s.advance(10, duration); }, false);
    }
    case 14: {
      const std::size_t size = sim.event_log().size();
      const std::size_t k = pick(rng, std::vector<std::size_t>{size, size + 1, SIZE_MAX, std::size_t{1} << 40, static_cast<std::size_t>(-1) / 2});
      return refused("Replay::after_event(" + std::to_string(k) + ")", {"k must"}, [k](const Simulation& s) { billiard::Replay(s).after_event(k); }, false);
    }
    case 16: {
      const double value = bad_nonnegative(rng);
      if (coin(rng)) {
        return refused("set_contact_duration(" + show(value) + ")", {"duration"}, [value](Simulation& s) { s.set_contact_duration(value); }, false);
      }
      if (coin(rng)) {
        return refused("set_sleep_speed(" + show(value) + ")", {"speed"}, [value](Simulation& s) { s.set_sleep_speed(value); }, false);
      }
      return refused("set_elastic_impact_speed(" + show(value) + ")", {"speed"}, [value](Simulation& s) { s.set_elastic_impact_speed(value); }, false);
    }
    case 15: {
      const double t = pick(rng, std::vector<double>{kNan, kInf, -kInf, -1.0, -kDenormal, -1e308});
      return refused("Replay::at(" + show(t) + ")", {"t must"}, [t](const Simulation& s) { billiard::Replay(s).at(t); }, false);
    }
    default: {
      const double tolerance = bad_nonnegative(rng);
      return refused("validate(" + show(tolerance) + ")", {"tolerance"}, [tolerance](Simulation& s) { s.validate(tolerance); }, false);
    }
  }
}

// A valid call with random, sometimes extreme values: it may be accepted or refused (a disc
// outside the container, overlapping another or a wall, a container that leaves discs out).
Call plausible_call(Rng& rng) {
  auto any = [](std::string text, bool setup, std::function<void(Simulation&)> run) {
    return Call{std::move(text), Expect::Either, setup, {}, std::move(run)};
  };
  // Extreme but allowed: the documented limits, tiny and negative zero.
  auto extreme = [&](double typical) {
    return coin(rng) ? uniform(rng, -typical, typical) : pick(rng, std::vector<double>{0.0, -0.0, kDenormal, -1e-308, 1e50, -1e50, 1e-50, typical});
  };
  auto extreme_scale = [&](double typical) {
    return coin(rng) ? uniform(rng, 0.1, 1) * typical : pick(rng, std::vector<double>{1e-50, 1e50, 1e-20, 1e20, typical});
  };
  switch (std::uniform_int_distribution<int>(0, 9)(rng)) {
    case 9: {
      const std::optional<double> value = coin(rng) ? std::nullopt : std::optional<double>(pick(rng, std::vector<double>{0.0, 1e-3, 1.0, 1e308}));
      const std::string text = value ? show(*value) : "automatic";
      if (coin(rng)) return any("set_contact_duration(" + text + ")", false, [value](Simulation& s) { s.set_contact_duration(value); });
      if (coin(rng)) return any("set_sleep_speed(" + text + ")", false, [value](Simulation& s) { s.set_sleep_speed(value); });
      return any("set_elastic_impact_speed(" + text + ")", false, [value](Simulation& s) { s.set_elastic_impact_speed(value); });
    }
    case 0:
    case 1:
    case 2: {
      Disc d = make_disc(Vec2(extreme(10), extreme(10)), Vec2(extreme(3), extreme(3)), extreme_scale(0.5), extreme_scale(1));
      if (coin(rng)) d.inertia = extreme_scale(0.5);
      if (coin(rng)) d.spin = extreme(2);
      return any("add_disc(position " + show(d.position) + ", velocity " + show(d.velocity) + ", radius " + show(d.radius) + ", mass " +
                     show(d.mass) + ", inertia " + (d.inertia ? show(*d.inertia) : "none") + ", spin " + show(d.spin) + ")",
                 true, [d](Simulation& s) { s.add_disc(d); });
    }
    case 3: {
      const Vec2 g(extreme(5), extreme(5));
      return any("set_gravity(" + show(g) + ")", true, [g](Simulation& s) { s.set_gravity(g); });
    }
    case 4: {
      const Vec2 a(extreme(20), extreme(20)), b(extreme(20), extreme(20));
      return any("add_segment(" + show(a) + ", " + show(b) + ")", true, [=](Simulation& s) { s.add_segment(a, b); });
    }
    case 5: {
      const double size = pick(rng, std::vector<double>{0.0, -0.0, kDenormal, 1e-300, 0.5, 3.0, 1e50, 1e308, kMax});
      return any("set_cell_size(" + show(size) + ")", true, [size](Simulation& s) { s.set_cell_size(size); });
    }
    case 6: {
      const int n = std::uniform_int_distribution<int>(0, 30)(rng);
      const double radius = pick(rng, std::vector<double>{1e-50, 1e-10, 0.1, 0.3}), kT = pick(rng, std::vector<double>{0.0, 1e-300, 1.0, 1e50});
      const std::uint64_t seed = rng();
      return any("add_random_discs(" + std::to_string(n) + ", " + show(radius) + ", 1, " + show(kT) + ")", true,
                 [=](Simulation& s) { s.add_random_discs(n, radius, 1.0, kT, seed); });
    }
    case 7: {
      const double n = pick(rng, std::vector<double>{0.0, kDenormal, 1e-3, 1.0, 0.5, 0.9}), t = pick(rng, std::vector<double>{-1.0, 1.0, 0.0, -0.0, -kDenormal});
      return any("set_restitution(" + show(n) + ", " + show(t) + ")", false, [=](Simulation& s) { s.set_restitution(n, t); });
    }
    default: {
      const std::int64_t events = pick(rng, std::vector<std::int64_t>{0, 1, 50});
      const double duration = pick(rng, std::vector<double>{0.0, -0.0, kDenormal, 1e-300, 0.5, kInf});
      Call call = any("advance(" + std::to_string(events) + ", " + show(duration) + ")", false,
                      [=](Simulation& s) { s.advance(events, duration); });
      call.advances = true;
      return call;
    }
  }
}

// ---- The check of one call ----

struct Counts {
  int calls = 0;
  int refused = 0;       // std::invalid_argument
  int wrong_phase = 0;   // std::logic_error: setup after the first advance
  int accepted = 0;
  double slowest = 0;    // seconds
};

// Advances a little (a few collisions, bounded time) and returns the snapshot, or what was thrown.
std::string advanced(Simulation& sim, Snapshot& out) {
  try {
    sim.advance(20);
  } catch (const std::exception& e) {
    return e.what();
  }
  out = snapshot(sim);
  return "";
}

bool finite_state(const Simulation& sim) {
  const billiard::State s = sim.current_state();
  return s.positions.allFinite() && s.velocities.allFinite() && s.spins.allFinite() && std::isfinite(sim.time());
}

void check(const Start& start, const Call& call, Counts& counts) {
  SCOPED_TRACE(std::string(start.name) + ": " + call.text);
  Simulation sim = start.sim;  // (start.sim itself stays untouched, for the comparison below)
  const Snapshot before = snapshot(sim);
  const bool wrong_phase = call.setup && started(sim);
  enum { Accepted, InvalidArgument, LogicError } outcome = Accepted;
  std::string message;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    call.run(sim);
  } catch (const std::invalid_argument& e) {  // (before std::logic_error, its base)
    outcome = InvalidArgument;
    message = e.what();
  } catch (const std::logic_error& e) {
    outcome = LogicError;
    message = e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected exception: " << e.what();
    return;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  counts.slowest = std::max(counts.slowest, seconds);
  EXPECT_LT(seconds, kSecondsPerCall);
  ++counts.calls;

  if (wrong_phase) {
    ASSERT_EQ(outcome, LogicError) << "a setup call after the first advance must throw std::logic_error; message: " << message;
    EXPECT_NE(message.find("started"), std::string::npos) << message;
    ++counts.wrong_phase;
  } else if (call.expect == Expect::Either && call.advances && !start.container) {
    ASSERT_EQ(outcome, LogicError) << "advance() without a container must throw std::logic_error; message: " << message;
    EXPECT_NE(message.find("no container"), std::string::npos) << message;
    ++counts.wrong_phase;
  } else if (call.expect == Expect::Refused) {
    ASSERT_EQ(outcome, InvalidArgument) << "must throw std::invalid_argument; message: " << message;
    bool named = false;
    for (const std::string& name : call.names) named = named || message.find(name) != std::string::npos;
    EXPECT_TRUE(named) << "the message names none of the expected arguments: " << message;
    ++counts.refused;
  } else if (outcome == Accepted) {
    ++counts.accepted;
    EXPECT_EQ(sim.validate(), std::nullopt);
    ASSERT_TRUE(finite_state(sim));
    Snapshot ignored;
    const auto t1 = std::chrono::steady_clock::now();
    const std::string thrown = advanced(sim, ignored);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count(), kSecondsPerCall);
    if (thrown.empty()) {
      EXPECT_EQ(sim.validate(), std::nullopt);
      EXPECT_TRUE(finite_state(sim)) << "an accepted call led to non-finite discs";
    } else {
      EXPECT_NE(thrown.find("no container"), std::string::npos) << thrown;
    }
    return;
  } else {
    // Refused valid-looking call: the message starts with the call's name, or "disc k:".
    ASSERT_EQ(outcome, InvalidArgument) << message;
    const std::string function = call.text.substr(0, call.text.find('('));
    EXPECT_TRUE(message.rfind(function + ":", 0) == 0 || message.rfind("disc ", 0) == 0 || message.rfind("add_polygon:", 0) == 0)
        << message;
    ++counts.refused;
  }
  // Refused: nothing changed, the simulation is valid and runs on exactly like an untouched copy.
  EXPECT_EQ(difference(before, snapshot(sim)), "") << message;
  EXPECT_EQ(sim.validate(), std::nullopt);
  Simulation copy = start.sim;
  copy.validate();  // (validate() records what it finds, as on `sim` above)
  Snapshot after_sim, after_copy;
  const std::string thrown_sim = advanced(sim, after_sim);
  const std::string thrown_copy = advanced(copy, after_copy);
  EXPECT_EQ(thrown_sim, thrown_copy);
  EXPECT_EQ(difference(after_copy, after_sim), "") << "the refused call changed what happens next";
}

}  // namespace

TEST(FuzzApi, BadCallsAreRefusedNamingTheArgumentAndChangeNothing) {
  // BILLIARD_FUZZ_SEED=k explores another corpus (or reproduces one printed before).
  const char* chosen = std::getenv("BILLIARD_FUZZ_SEED");
  const std::uint64_t seed = chosen ? std::stoull(chosen) : kSeed;
  std::cout << "api fuzz seed " << seed << "\n";
  Rng rng(seed);
  const std::vector<Start> states = starts();
  for (const Start& s : states) ASSERT_EQ(Simulation(s.sim).validate(), std::nullopt) << s.name;
  Counts counts;
  const int calls = 6000;
  for (int k = 0; k < calls; ++k) {
    const Start& chosen_start = states[std::uniform_int_distribution<std::size_t>(0, states.size() - 1)(rng)];
    // Often a few valid calls first (kept where accepted), so that the states vary more.
    Start start{chosen_start.name, chosen_start.sim, chosen_start.container};
    std::string history = chosen_start.name;
    for (int step = std::uniform_int_distribution<int>(-2, 2)(rng); step > 0; --step) {
      const Call before = plausible_call(rng);
      try {
        before.run(start.sim);
        history += ", " + before.text;
      } catch (const std::exception&) {
      }
    }
    const Call call = k % 5 == 4 ? plausible_call(rng) : bad_call(rng, start);
    start.name = history.c_str();
    check(start, call, counts);
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::cout << "api fuzz: " << counts.calls << " calls on " << states.size() << " starting states, " << counts.refused
            << " refused (std::invalid_argument), " << counts.wrong_phase
            << " refused for the state (std::logic_error: setup after the start, advance without a container), "
            << counts.accepted << " accepted (valid, some extreme); every refusal left the simulation unchanged; slowest call "
            << counts.slowest << " s\n";
  EXPECT_EQ(counts.calls, calls);
  EXPECT_GT(counts.refused, calls / 2);
  EXPECT_GT(counts.wrong_phase, 100);
  EXPECT_GT(counts.accepted, 100);
}

namespace {
// Seconds taken by `call`.
template <class Call>
double seconds(Call call) {
  const auto t0 = std::chrono::steady_clock::now();
  call();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

TEST(FuzzApi, ImpossibleOrExtremeRequestsReturnQuickly) {
  // Far too many discs: refused from the area alone, not after 60 n placement attempts.
  for (const int n : {INT_MAX, 1 << 20, 400}) {
    Simulation sim;
    sim.set_circular_table(10);
    const Snapshot before = snapshot(sim);
    EXPECT_LT(seconds([&] { EXPECT_THROW(sim.add_random_discs(n, 1.0), std::invalid_argument); }), 1.0) << n;
    EXPECT_EQ(difference(before, snapshot(sim)), "");
  }
  // A small disc then one 4 x 10^5 times larger: the overlap test must not scan 10^11 cells of
  // the small disc's size.
  {
    Simulation sim;
    sim.set_circular_table(1e6);
    sim.add_disc(make_disc(Vec2(0, 0), Vec2(1, 0), 1.0));
    EXPECT_LT(seconds([&] { sim.add_disc(make_disc(Vec2(5e5, 0), Vec2(0, 1), 4e5)); }), 1.0);
    EXPECT_LT(seconds([&] { EXPECT_THROW(sim.add_disc(make_disc(Vec2(-4e5, 0), Vec2(0, 0), 4e5)), std::invalid_argument); }), 1.0);
    EXPECT_EQ(sim.size(), 2);
    EXPECT_EQ(sim.validate(), std::nullopt);
  }
  // The smallest radii allowed: two at the same place overlap (below them, squares underflow and
  // the overlap would go unseen).
  {
    Simulation sim;
    sim.set_circular_table(1e-45);
    sim.add_disc(make_disc(Vec2(1e-46, 0), Vec2(0, 0), 1e-50));
    EXPECT_THROW(sim.add_disc(make_disc(Vec2(1e-46, 0), Vec2(0, 0), 1e-50)), std::invalid_argument);
    EXPECT_THROW(sim.add_disc(make_disc(Vec2(0, 0), Vec2(0, 0), 1e-300)), std::invalid_argument);
  }
  // A gigantic table, the lightest discs and the largest temperature allowed.
  {
    Simulation sim;
    sim.set_circular_table(1e50);
    EXPECT_LT(seconds([&] { sim.add_random_discs(100, 1e46, 1e-50, 1e50, 3); }), 5.0);
    EXPECT_EQ(sim.size(), 100);
    EXPECT_LT(seconds([&] { sim.advance(200); }), 5.0);
    EXPECT_EQ(sim.validate(), std::nullopt);
    EXPECT_TRUE(finite_state(sim));
  }
  // A thin polygon in a huge bounding box: the lattice over the box would not fit in memory.
  {
    Simulation sim;
    Points sliver(3, 2);
    sliver << 0, 0, 1e6, 1e6, 1e6, 1e6 + 1;
    sim.add_polygon(sliver);
    const Snapshot before = snapshot(sim);
    EXPECT_LT(seconds([&] {
                try {
                  sim.add_random_discs(1000, 0.2, 1.0, 1.0, 4);
                } catch (const std::invalid_argument&) {
                  EXPECT_EQ(difference(before, snapshot(sim)), "");
                }
              }),
              5.0);
    EXPECT_EQ(sim.validate(), std::nullopt);
  }
  // No discs: advance without any limit has nothing to do and returns.
  {
    Simulation sim;
    sim.set_periodic_box(1e-300, 1e-300);
    EXPECT_LT(seconds([&] { EXPECT_EQ(sim.advance(billiard::kAllEvents).collisions, 0); }), 1.0);
    EXPECT_EQ(sim.validate(), std::nullopt);
  }
}

TEST(FuzzApi, ACopyRunsOnLikeTheOriginal) {
  // The fuzzing compares refused calls with untouched copies, so copies of running simulations
  // must be independent of their originals: advancing or destroying the original changes nothing.
  auto running = [] {
    Simulation sim;
    sim.add_box(Vec2(0, 0), Vec2(20, 20));
    sim.add_random_discs(40, 0.5, 1.0, 1.0, 8);
    sim.advance(300);
    return sim;
  };
  Simulation reference = running();
  reference.advance(500);
  auto original = std::make_unique<Simulation>(running());
  Simulation copied(*original);
  Simulation assigned;
  assigned = *original;
  original->advance(50);  // moves the original's schedules on
  original.reset();
  copied.advance(500);
  assigned.advance(500);
  EXPECT_EQ(difference(snapshot(reference), snapshot(copied)), "");
  EXPECT_EQ(difference(snapshot(reference), snapshot(assigned)), "");
  EXPECT_EQ(copied.validate(), std::nullopt);
}

// Inelastic discs in the table, down to a normal restitution of 0, with and without the TC model:
// after a hit on the rim with restitution 0 a disc moves along it (r.v = 0 exactly), which is no
// graze inside a circle (the straight line leaves it at once), so the disc must bounce again, not
// fly out.
TEST(FuzzApi, InelasticDiscsStayOnTheTable) {
  struct Case {
    double normal, tangential;
    std::optional<double> contact_duration;  // (nullopt: automatic)
  };
  for (const Case c : {Case{0.0, -1.0, std::nullopt}, Case{0.0, -0.5, std::nullopt}, Case{0.0, 0.0, std::nullopt},
                       Case{0.5, 0.0, 0.0}, Case{0.01, -1.0, 0.0}}) {
    Simulation sim;
    sim.set_circular_table(10);
    sim.add_random_discs(20, 0.5, 1.0, 1.0, 1);
    sim.set_restitution(c.normal, c.tangential);
    sim.set_contact_duration(c.contact_duration);
    for (int k = 0; k < 50; ++k) {
      sim.advance(20);
      ASSERT_EQ(sim.validate(), std::nullopt) << "restitution " << c.normal << ", " << c.tangential << ", contact duration "
                                    << (c.contact_duration ? std::to_string(*c.contact_duration) : "automatic") << ", after "
                                    << 20 * (k + 1) << " collisions";
    }
  }
}

// A disc whose next event lies about 1e20 time units ahead (speed 1e-20 in a table of radius 5),
// and an advance stopped by its duration: the queue's buckets must stay wider than the rounding
// of such times, or the heap's horizon cannot pass them and the queue is out of order.
TEST(FuzzApi, SlowDiscsKeepTheQueueValid) {
  for (const double speed : {1e-20, 1e-50}) {
    Simulation sim;
    sim.set_circular_table(5);
    sim.add_disc(make_disc(Vec2(0, 0.1), Vec2(speed, 0), 0.3));
    sim.advance(1, 1.0);
    EXPECT_EQ(sim.validate(), std::nullopt) << "speed " << speed;
  }
}
