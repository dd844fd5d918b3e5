// Fuzzing of the public API: thousands of random systems described in random ways and random
// calls on them, with bad or extreme arguments (nan, infinities, 1e308, denormals, -0.0, negative
// and out-of-range counts, mismatched arrays), from a fixed seed. Each system is a random
// container (a shape function and add_ calls), random settings and random discs, each step
// possibly refused. The contract (container.hpp, settings.hpp, simulation.hpp):
//  - a bad argument or settings field: std::invalid_argument whose message names it;
//  - adding discs after the first advance: std::logic_error, whatever the arguments (the call is
//    the mistake);
//  - either way the container or the simulation is unchanged, bit for bit, still valid, and a
//    simulation advances exactly like an untouched copy;
//  - a call that is valid, however extreme, returns quickly and leaves a valid simulation whose
//    discs stay finite as it advances.
#include "billiard/engine/replay.hpp"
#include "billiard/engine/simulation.hpp"
#include "container_geometry.hpp"
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

using billiard::Container;
using billiard::Disc;
using billiard::Coordinates;
using billiard::Settings;
using billiard::Simulation;
using billiard::Vector;
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
  void add(const char* label, const Vector& v) {
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

void add_wall(Snapshot& s, const billiard::WallShape& w) {
  s.add("wall kind", static_cast<std::int64_t>(w.kind));
  s.add("wall a", w.a);
  s.add("wall b", w.b);
  s.add("wall radius", w.radius);
  s.add("wall start angle", w.start_angle);
  s.add("wall sweep", w.sweep);
}

void add_container(Snapshot& s, const Container& c) {
  s.add("walls", static_cast<std::int64_t>(c.walls().size()));
  for (const billiard::WallShape& w : c.walls()) add_wall(s, w);
  s.add("outlines", static_cast<std::int64_t>(c.outlines().size()));
  for (const billiard::Outline& outline : c.outlines()) {
    s.add("outline hole", std::int64_t{outline.hole});
    s.add("outline pieces", static_cast<std::int64_t>(outline.pieces.size()));
    for (const billiard::WallShape& w : outline.pieces) add_wall(s, w);
  }
  s.add("table", std::int64_t{c.has_table()});
  s.add("table radius", c.table_radius());
  s.add("periodic", std::int64_t{c.periodic()});
  s.add("period", c.period());
}

Snapshot snapshot(const Container& container) {
  Snapshot s;
  add_container(s, container);
  return s;
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
  add_container(s, sim.container());
  s.add("gravity", sim.gravity());
  s.add("restitution", sim.restitution().normal);
  s.add("restitution", sim.restitution().tangential);
  s.add("exchange velocities", std::int64_t{sim.exchange_velocities()});
  s.add("contact duration", sim.contact_duration());
  s.add("elastic impact speed", sim.elastic_impact_speed());
  s.add("sleep speed", sim.sleep_speed());
  s.add("sleeping discs", static_cast<std::int64_t>(sim.sleeping_discs().size()));
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
int integer(Rng& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
bool coin(Rng& rng) { return integer(rng, 0, 1) == 1; }

double bad_number(Rng& rng) { return coin(rng) ? pick(rng, kNotFinite) : pick(rng, kTooLarge); }
double bad_scale(Rng& rng) { return coin(rng) ? bad_number(rng) : pick(rng, kBadScale); }
double bad_nonnegative(Rng& rng) {  // bad where >= 0 and finite is required
  return coin(rng) ? pick(rng, kNotFinite) : pick(rng, std::vector<double>{-1.0, -kDenormal, -1e308, -kMax, -kInf});
}
double bad_length(Rng& rng) {  // bad for a container's length: not positive, or not finite and at most 1e50
  return coin(rng) ? bad_number(rng) : pick(rng, std::vector<double>{0.0, -0.0, -1.0, -kDenormal, -5.0});
}
Vector bad_point(Rng& rng) {  // one or both coordinates bad
  const double good = uniform(rng, -5, 5);
  switch (integer(rng, 0, 2)) {
    case 0: return Vector(bad_number(rng), good);
    case 1: return Vector(good, bad_number(rng));
    default: return Vector(bad_number(rng), bad_number(rng));
  }
}
Vector point(Rng& rng, double reach) { return Vector(uniform(rng, -reach, reach), uniform(rng, -reach, reach)); }
// Extreme but allowed: the documented limits, tiny and negative zero.
double extreme(Rng& rng, double typical) {
  return coin(rng) ? uniform(rng, -typical, typical) : pick(rng, std::vector<double>{0.0, -0.0, kDenormal, -1e-308, 1e50, -1e50, 1e-50, typical});
}
double extreme_scale(Rng& rng, double typical) {
  return coin(rng) ? uniform(rng, 0.1, 1) * typical : pick(rng, std::vector<double>{1e-50, 1e50, 1e-20, 1e20, typical});
}
// A length for a container: mostly near `typical`, sometimes as small or as large as allowed
// (below 1e-50 a length is refused: the bad shapes above).
double length(Rng& rng, double typical) {
  return integer(rng, 0, 3) > 0 ? uniform(rng, 0.5, 1.5) * typical : pick(rng, std::vector<double>{1e-50, 1e-20, 1e20, 1e50});
}
// A normal restitution over the whole accepted range, 0 and a denormal included, with or
// without gravity (engine.LostDiscs.InelasticBedsStayInCurvedContainers checks the beds that slide
// along curved walls).
double normal_restitution(Rng& rng) { return pick(rng, std::vector<double>{0.0, kDenormal, 1e-3, 1.0, 0.5, 0.9}); }
// A place for a container: mostly near the origin, sometimes far.
Vector place(Rng& rng, double reach) {
  return integer(rng, 0, 3) > 0 ? point(rng, reach) : Vector(extreme(rng, reach), extreme(rng, reach));
}

std::string show(double x) {
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}
std::string show(const Vector& v) { return "(" + show(v.x()) + ", " + show(v.y()) + ")"; }

enum class Expect {
  Refused,  // std::invalid_argument naming one of `names`
  Either,   // valid or not (extreme values, conflicts with the state): if refused, as above
};

// Whether `message` names one of `names`.
bool names_one_of(const std::string& message, const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    if (message.find(name) != std::string::npos) return true;
  }
  return false;
}

// The name of the function in a call's text, "add_arc" of "add_arc(...)".
std::string function_of(const std::string& text) { return text.substr(0, text.find('(')); }

// ---- Containers: shape functions and add_ calls ----

struct ShapeCall {
  std::string text;
  Expect expect = Expect::Refused;
  std::vector<std::string> names;
  std::function<Container()> make;
};

// An add_ call on a container; returns the index the call returns (add_segment, add_arc), or -1.
struct Addition {
  std::string text;
  Expect expect = Expect::Refused;
  std::vector<std::string> names;
  std::function<int(Container&)> run;
};

ShapeCall bad_shape(std::string text, std::vector<std::string> names, std::function<Container()> make) {
  return ShapeCall{std::move(text), Expect::Refused, std::move(names), std::move(make)};
}

ShapeCall bad_polygon(Rng& rng) {
  const int rows = integer(rng, 0, 6);
  Coordinates vertices(rows, 2);
  for (int k = 0; k < rows; ++k) vertices.row(k) << 30 * std::cos(k * 2 * M_PI / rows), 30 * std::sin(k * 2 * M_PI / rows);
  std::vector<std::string> names = {"polygon: vertices needs"};
  if (rows >= 3) {
    const int k = integer(rng, 0, rows - 1);
    if (coin(rng)) {
      vertices.row(k) = bad_point(rng);
      names = {"polygon: vertex " + std::to_string(k)};
    } else {  // a side of zero length (or one whose squared length underflows)
      const int next = (k + 1) % rows;
      vertices.row(next) = vertices.row(k);
      if (coin(rng)) vertices(next, 0) += kDenormal;
      names = {"coincide"};
    }
  }
  return bad_shape("polygon(" + std::to_string(rows) + " vertices)", names, [=] { return billiard::polygon(vertices); });
}

// A shape function with one bad argument.
ShapeCall bad_shape_call(Rng& rng) {
  switch (integer(rng, 0, 7)) {
    case 0: {
      const double r = pick(rng, std::vector<double>{kNan, kInf, -kInf, 0.0, -0.0, -1.0, -kDenormal, kDenormal, 1e-200, 1e308, 1e51, kMax});
      return bad_shape("circular_table(" + show(r) + ")", {"circular_table: radius"}, [r] { return billiard::circular_table(r); });
    }
    case 1: {
      const bool width = coin(rng);
      const double bad = coin(rng) ? bad_number(rng) : pick(rng, std::vector<double>{0.0, -0.0, -1.0, -kDenormal});
      const double w = width ? bad : uniform(rng, 10, 50), h = width ? uniform(rng, 10, 50) : bad;
      return bad_shape("periodic_box(" + show(w) + ", " + show(h) + ")", {width ? "periodic_box: width" : "periodic_box: height"},
                       [=] { return billiard::periodic_box(w, h); });
    }
    case 2: {
      Vector lower(-30, -30), upper(30, 30);
      std::string name;
      switch (integer(rng, 0, 2)) {
        case 0: lower = bad_point(rng); name = "box: lower must"; break;
        case 1: upper = bad_point(rng); name = "box: upper must"; break;
        default:  // upper not above lower in x or y (or by less than an underflowing step)
          upper = lower + Vector(pick(rng, std::vector<double>{0.0, -1.0, kDenormal, 60.0}), pick(rng, std::vector<double>{0.0, -0.0, -5.0}));
          if (coin(rng)) std::swap(upper.x(), upper.y());
          name = "must exceed lower";
          break;
      }
      return bad_shape("box(" + show(lower) + ", " + show(upper) + ")", {name}, [=] { return billiard::box(lower, upper); });
    }
    case 3: return bad_polygon(rng);
    case 4: {
      Vector centre = point(rng, 5);
      double radius = uniform(rng, 1, 5), length = uniform(rng, 1, 8);
      std::string name;
      switch (integer(rng, 0, 2)) {
        case 0: centre = bad_point(rng); name = "stadium: centre"; break;
        case 1: radius = bad_length(rng); name = "stadium: radius"; break;
        default: length = bad_length(rng); name = "stadium: length"; break;
      }
      return bad_shape("stadium(" + show(centre) + ", " + show(radius) + ", " + show(length) + ")", {name},
                       [=] { return billiard::stadium(centre, radius, length); });
    }
    case 5: {
      Vector lower(0, 0), upper(20, 30);
      double radius = uniform(rng, 1, 9);
      std::string name;
      switch (integer(rng, 0, 3)) {
        case 0: lower = bad_point(rng); name = "sinai_billiard: lower"; break;
        case 1: upper = bad_point(rng); name = "sinai_billiard: upper"; break;
        case 2:  // upper not above lower
          upper = Vector(pick(rng, std::vector<double>{0.0, -1.0, 20.0}), pick(rng, std::vector<double>{0.0, -0.0, -5.0}));
          if (coin(rng)) std::swap(upper.x(), upper.y());
          name = "sinai_billiard: upper";
          break;
        default:  // not positive, or too large for the box (half its smaller side is 10)
          radius = pick(rng, std::vector<double>{kNan, kInf, -kInf, 0.0, -0.0, -1.0, -kDenormal, kDenormal, 1e-60, 10.0, 25.0, 1e308});
          name = "sinai_billiard: obstacle_radius";
          break;
      }
      return bad_shape("sinai_billiard(" + show(lower) + ", " + show(upper) + ", " + show(radius) + ")", {name},
                       [=] { return billiard::sinai_billiard(lower, upper, radius); });
    }
    case 6: {
      Vector centre = point(rng, 5);
      double cap = uniform(rng, 2, 6), width = uniform(rng, 0.5, 2), height = uniform(rng, 1, 5);
      std::string name;
      switch (integer(rng, 0, 3)) {
        case 0: centre = bad_point(rng); name = "mushroom: centre"; break;
        case 1: cap = bad_length(rng); name = "mushroom: cap_radius"; break;
        case 2:  // not positive, or not narrower than the cap
          width = pick(rng, std::vector<double>{kNan, kInf, 0.0, -0.0, -1.0, -kDenormal, 2 * cap, 3 * cap, 1e308});
          name = "mushroom: stem_width";
          break;
        default: height = bad_length(rng); name = "mushroom: stem_height"; break;
      }
      return bad_shape("mushroom(" + show(centre) + ", " + show(cap) + ", " + show(width) + ", " + show(height) + ")", {name},
                       [=] { return billiard::mushroom(centre, cap, width, height); });
    }
    default: {
      const int n = integer(rng, 1, 4);
      Coordinates centres(n, 2);
      std::vector<double> radii;
      for (int k = 0; k < n; ++k) {
        centres.row(k) = point(rng, 6);
        radii.push_back(uniform(rng, 2, 5));
      }
      std::string name;
      const int k = integer(rng, 0, n - 1);
      switch (integer(rng, 0, 4)) {
        case 0: centres.resize(0, 2); radii.clear(); name = "union_of_circles: centres"; break;
        case 1: radii.resize(coin(rng) ? n + 1 : n - 1); name = "union_of_circles: radii has"; break;
        case 2: centres.row(k) = bad_point(rng); name = "union_of_circles: circle " + std::to_string(k) + ": centre"; break;
        case 3: radii[k] = bad_length(rng); name = "union_of_circles: circle " + std::to_string(k) + ": radius"; break;
        default:  // two equal circles
          centres.conservativeResize(n + 1, 2);
          centres.row(n) = centres.row(k);
          radii.push_back(radii[k]);
          name = "coincide";
          break;
      }
      return bad_shape("union_of_circles(" + std::to_string(centres.rows()) + " centres, " + std::to_string(radii.size()) + " radii)",
                       {name}, [=] { return billiard::union_of_circles(centres, radii); });
    }
  }
}

// A regular polygon of `sides` sides and circumradius r about `centre`.
Coordinates regular_polygon(const Vector& centre, double r, int sides, double turn) {
  Coordinates vertices(sides, 2);
  for (int k = 0; k < sides; ++k) {
    const double angle = turn + 2 * M_PI * k / sides;
    vertices.row(k) << centre.x() + r * std::cos(angle), centre.y() + r * std::sin(angle);
  }
  return vertices;
}

// A shape function with valid arguments, sometimes extreme: accepted, or refused naming the
// function (a shape too small for where it is, or reaching beyond 1e50).
ShapeCall plausible_shape_call(Rng& rng) {
  auto any = [](std::string text, std::function<Container()> make) { return ShapeCall{std::move(text), Expect::Either, {}, std::move(make)}; };
  switch (integer(rng, 0, 7)) {
    case 0: {
      const double r = length(rng, 10);
      return any("circular_table(" + show(r) + ")", [r] { return billiard::circular_table(r); });
    }
    case 1: {
      const double w = length(rng, 20), h = length(rng, 15);
      return any("periodic_box(" + show(w) + ", " + show(h) + ")", [=] { return billiard::periodic_box(w, h); });
    }
    case 2: {
      const Vector lower = place(rng, 10), upper = lower + Vector(length(rng, 20), length(rng, 15));
      return any("box(" + show(lower) + ", " + show(upper) + ")", [=] { return billiard::box(lower, upper); });
    }
    case 3: {
      Coordinates vertices;
      std::string text;
      if (coin(rng)) {
        const int sides = integer(rng, 3, 8);
        const Vector centre = place(rng, 5);
        const double r = length(rng, 10);
        vertices = regular_polygon(centre, r, sides, uniform(rng, 0, M_PI));
        text = "polygon(" + std::to_string(sides) + " sides about " + show(centre) + ", circumradius " + show(r) + ")";
      } else {  // with a notch: a corner pointing inwards
        const double scale = length(rng, 1);
        vertices.resize(5, 2);
        vertices << 0, 0, 60, 0, 60, 60, 30, 25, 0, 60;
        vertices *= scale;
        text = "polygon(notched, scale " + show(scale) + ")";
      }
      return any(text, [=] { return billiard::polygon(vertices); });
    }
    case 4: {
      const Vector centre = place(rng, 5);
      const double r = length(rng, 5), l = length(rng, 8);
      return any("stadium(" + show(centre) + ", " + show(r) + ", " + show(l) + ")", [=] { return billiard::stadium(centre, r, l); });
    }
    case 5: {
      const Vector lower = place(rng, 10), size(length(rng, 20), length(rng, 20));
      const Vector upper = lower + size;
      const double radius = uniform(rng, 0.05, 0.45) * size.minCoeff();
      return any("sinai_billiard(" + show(lower) + ", " + show(upper) + ", " + show(radius) + ")",
                 [=] { return billiard::sinai_billiard(lower, upper, radius); });
    }
    case 6: {
      const Vector centre = place(rng, 5);
      const double cap = length(rng, 8), width = uniform(rng, 0.05, 0.95) * 2 * cap, height = length(rng, 6);
      return any("mushroom(" + show(centre) + ", " + show(cap) + ", " + show(width) + ", " + show(height) + ")",
                 [=] { return billiard::mushroom(centre, cap, width, height); });
    }
    default: {
      const int n = integer(rng, 1, 4);
      const double scale = length(rng, 1);
      Coordinates centres(n, 2);
      std::vector<double> radii;
      for (int k = 0; k < n; ++k) {
        centres.row(k) = scale * point(rng, 8);
        radii.push_back(scale * uniform(rng, 3, 8));
      }
      return any("union_of_circles(" + std::to_string(n) + " circles, scale " + show(scale) + ")",
                 [=] { return billiard::union_of_circles(centres, radii); });
    }
  }
}

// A container that is accepted, when the random one was refused: the kinds the engine tests use.
std::pair<std::string, Container> ordinary_container(Rng& rng) {
  switch (integer(rng, 0, 4)) {
    case 0: return {"circular_table(10)", billiard::circular_table(10)};
    case 1: return {"box((0, 0), (20, 10))", billiard::box(Vector(0, 0), Vector(20, 10))};
    case 2: return {"periodic_box(20, 15)", billiard::periodic_box(20, 15)};
    case 3: return {"polygon(hexagon)", billiard::polygon(regular_polygon(Vector(0, 0), 10, 6, 0))};
    default: return {"sinai_billiard((0, 0), (20, 20), 5)", billiard::sinai_billiard(Vector(0, 0), Vector(20, 20), 5)};
  }
}

Addition bad_addition(std::string text, std::vector<std::string> names, std::function<int(Container&)> run) {
  return Addition{std::move(text), Expect::Refused, std::move(names), std::move(run)};
}

// An outlined shape for an obstacle, small and near the origin; never refused.
std::pair<std::string, Container> obstacle_shape(Rng& rng) {
  const Vector c = point(rng, 8);
  const double s = uniform(rng, 0.5, 3);
  switch (integer(rng, 0, 4)) {
    case 0: return {"box about " + show(c), billiard::box(c - Vector(s, s), c + Vector(s, 0.5 * s))};
    case 1: return {"triangle about " + show(c), billiard::polygon(regular_polygon(c, s, 3, uniform(rng, 0, M_PI)))};
    case 2: return {"stadium about " + show(c), billiard::stadium(c, s, uniform(rng, 0.5, 3))};
    case 3: return {"mushroom about " + show(c), billiard::mushroom(c, s, s, s)};
    default: {
      Coordinates centres(2, 2);
      centres << c.x(), c.y(), c.x() + s, c.y();
      return {"two circles about " + show(c), billiard::union_of_circles(centres, {s, 0.8 * s})};
    }
  }
}

// An add_ call with one bad argument, or a wall of any kind in a periodic box.
Addition bad_addition_call(Rng& rng, const Container& container) {
  if (container.periodic() && coin(rng)) {  // valid arguments, but walls inside a periodic box are not supported
    switch (integer(rng, 0, 3)) {
      case 0: return bad_addition("add_segment((1, 1), (3, 2))", {"add_segment: walls inside a periodic box"},
                                  [](Container& c) { return c.add_segment(Vector(1, 1), Vector(3, 2)); });
      case 1: return bad_addition("add_arc((5, 5), 1, 0, 1)", {"add_arc: walls inside a periodic box"},
                                  [](Container& c) { return c.add_arc(Vector(5, 5), 1, 0, 1); });
      case 2: return bad_addition("add_obstacle((5, 5), 1)", {"add_obstacle: walls inside a periodic box"}, [](Container& c) {
        c.add_obstacle(Vector(5, 5), 1);
        return -1;
      });
      default: {
        const auto [text, shape] = obstacle_shape(rng);
        return bad_addition("add_obstacle(" + text + ")", {"add_obstacle: walls inside a periodic box"}, [shape = shape](Container& c) {
          c.add_obstacle(shape);
          return -1;
        });
      }
    }
  }
  switch (integer(rng, 0, 3)) {
    case 0: {
      Vector a = point(rng, 5), b = point(rng, 5);
      std::string name;
      switch (integer(rng, 0, 2)) {
        case 0: a = bad_point(rng); name = "add_segment: a "; break;
        case 1: b = bad_point(rng); name = "add_segment: b "; break;
        default: b = a + Vector(coin(rng) ? 0.0 : kDenormal, 0.0); name = "add_segment: a and b"; break;
      }
      return bad_addition("add_segment(" + show(a) + ", " + show(b) + ")", {name}, [=](Container& c) { return c.add_segment(a, b); });
    }
    case 1: {
      Vector centre = point(rng, 5);
      double radius = uniform(rng, 0.5, 3), start = uniform(rng, -7, 7), end = start + uniform(rng, 0.1, 2 * M_PI);
      std::string name;
      switch (integer(rng, 0, 4)) {
        case 0: centre = bad_point(rng); name = "add_arc: centre"; break;
        case 1: radius = bad_length(rng); name = "add_arc: radius"; break;
        case 2: start = pick(rng, std::vector<double>{kNan, kInf, -kInf, 1.5e6, -1e308}); name = "add_arc: start_angle"; break;
        case 3: end = pick(rng, std::vector<double>{kNan, -kNan, kInf, -1e7, 1e308}); name = "add_arc: end_angle"; break;
        default:  // sweeping backwards, not at all, or more than once around
          end = start + pick(rng, std::vector<double>{0.0, -1.0, -kDenormal, 2 * M_PI + 1e-3, 2 * M_PI + 1, 100.0});
          name = "add_arc: end_angle - start_angle";
          break;
      }
      return bad_addition("add_arc(" + show(centre) + ", " + show(radius) + ", " + show(start) + ", " + show(end) + ")", {name},
                          [=](Container& c) { return c.add_arc(centre, radius, start, end); });
    }
    case 2: {
      Vector centre = point(rng, 5);
      double radius = uniform(rng, 0.5, 3);
      std::string name;
      if (coin(rng)) {
        centre = bad_point(rng);
        name = "add_obstacle: centre";
      } else {
        radius = bad_length(rng);
        name = "add_obstacle: radius";
      }
      return bad_addition("add_obstacle(" + show(centre) + ", " + show(radius) + ")", {name}, [=](Container& c) {
        c.add_obstacle(centre, radius);
        return -1;
      });
    }
    default: {  // a shape that is no outline, or has free walls
      std::optional<Container> shape;
      std::string text, name = "add_obstacle: shape has walls besides its outline";
      switch (integer(rng, 0, 3)) {
        case 0: shape = billiard::circular_table(uniform(rng, 1, 5)); text = "circular_table"; name = "add_obstacle: shape must be an outline"; break;
        case 1: shape = billiard::periodic_box(uniform(rng, 1, 5), 3); text = "periodic_box"; name = "add_obstacle: shape must be an outline"; break;
        case 2:
          shape = billiard::box(Vector(-1, -1), Vector(1, 1));
          shape->add_segment(Vector(-0.5, 0), Vector(0.5, 0));
          text = "box with a segment";
          break;
        default:
          shape = billiard::stadium(Vector(0, 0), 1, 2);
          shape->add_arc(Vector(0, 0), 0.5, 0, 1);
          text = "stadium with an arc";
          break;
      }
      return bad_addition("add_obstacle(" + text + ")", {name}, [shape = *shape](Container& c) {
        c.add_obstacle(shape);
        return -1;
      });
    }
  }
}

// An add_ call with valid arguments, sometimes extreme: accepted, or refused naming the function
// (any wall in a periodic box).
Addition plausible_addition_call(Rng& rng) {
  auto any = [](std::string text, std::function<int(Container&)> run) { return Addition{std::move(text), Expect::Either, {}, std::move(run)}; };
  switch (integer(rng, 0, 3)) {
    case 0: {
      const Vector a(extreme(rng, 20), extreme(rng, 20)), b(extreme(rng, 20), extreme(rng, 20));
      return any("add_segment(" + show(a) + ", " + show(b) + ")", [=](Container& c) { return c.add_segment(a, b); });
    }
    case 1: {
      const Vector centre(extreme(rng, 10), extreme(rng, 10));
      const double radius = length(rng, 4), start = coin(rng) ? uniform(rng, -7, 7) : pick(rng, std::vector<double>{0.0, -0.0, 1e6, -1e6});
      const double end = start + (coin(rng) ? uniform(rng, 0.01, 2 * M_PI) : pick(rng, std::vector<double>{2 * M_PI, 1e-9, M_PI}));
      return any("add_arc(" + show(centre) + ", " + show(radius) + ", " + show(start) + ", " + show(end) + ")",
                 [=](Container& c) { return c.add_arc(centre, radius, start, end); });
    }
    case 2: {
      const Vector centre(extreme(rng, 10), extreme(rng, 10));
      const double radius = length(rng, 2);
      return any("add_obstacle(" + show(centre) + ", " + show(radius) + ")", [=](Container& c) {
        c.add_obstacle(centre, radius);
        return -1;
      });
    }
    default: {
      const auto [text, shape] = obstacle_shape(rng);
      return any("add_obstacle(" + text + ")", [shape = shape](Container& c) {
        c.add_obstacle(shape);
        return -1;
      });
    }
  }
}

// ---- Settings ----

struct SettingsCase {
  std::string text;
  std::vector<std::string> names;  // empty: valid; else one field is bad and must be named
  Settings settings;
  Settings valid;  // the same with the bad field valid
};

// Random settings, every field valid (sometimes extreme), or one field bad.
SettingsCase random_settings(Rng& rng) {
  SettingsCase c;
  Settings& s = c.valid;
  std::ostringstream text;
  if (coin(rng)) {
    auto g = [&] { return coin(rng) ? uniform(rng, -5, 5) : pick(rng, std::vector<double>{0.0, -0.0, 1e-50, -1e-50, 1e50, -1e50, 1.0}); };
    s.gravity = Vector(g(), g());
    text << " gravity " << show(s.gravity);
  }
  if (coin(rng)) {
    s.restitution.normal = normal_restitution(rng);
    s.restitution.tangential = pick(rng, std::vector<double>{-1.0, 1.0, 0.0, -0.0, -kDenormal});
    text << " restitution " << show(s.restitution.normal) << ", " << show(s.restitution.tangential);
  }
  if (coin(rng)) {
    s.exchange_velocities = coin(rng);
    text << " exchange_velocities " << s.exchange_velocities;
  }
  auto granular = [&](const char* name, std::optional<double>& value) {
    if (coin(rng)) return;
    value = coin(rng) ? std::nullopt : std::optional<double>(pick(rng, std::vector<double>{0.0, 1e-3, 1.0, 1e308}));
    text << " " << name << " " << (value ? show(*value) : "automatic");
  };
  granular("contact_duration", s.contact_duration);
  granular("elastic_impact_speed", s.elastic_impact_speed);
  granular("sleep_speed", s.sleep_speed);
  if (coin(rng)) {
    s.cell_size = pick(rng, std::vector<double>{0.0, -0.0, kDenormal, 1e-300, 0.5, 3.0, 1e50, 1e308, kMax});
    text << " cell_size " << show(s.cell_size);
  }
  if (coin(rng)) {
    s.prefetch = pick(rng, std::vector<billiard::Prefetch>{billiard::Prefetch::Automatic, billiard::Prefetch::On, billiard::Prefetch::Off});
    text << " prefetch " << static_cast<int>(s.prefetch);
  }
  c.settings = s;
  if (integer(rng, 0, 2) == 0) {  // one bad field
    Settings& bad = c.settings;
    switch (integer(rng, 0, 7)) {
      case 0:
        bad.gravity = coin(rng) ? bad_point(rng) : Vector(0, pick(rng, std::vector<double>{kDenormal, -1e-308, 1e-51, -1e-300}));
        text << " bad gravity " << show(bad.gravity);
        c.names = {"settings.gravity"};
        break;
      case 1:
        bad.restitution.normal = pick(rng, std::vector<double>{kNan, kInf, -kInf, -0.1, 1.5, 1.0000000000000002, -kDenormal, 1e308, -1e308});
        text << " bad restitution.normal " << show(bad.restitution.normal);
        c.names = {"settings.restitution.normal"};
        break;
      case 2:
        bad.restitution.tangential = pick(rng, std::vector<double>{kNan, kInf, -kInf, -1.0000000000000002, 1.5, -2.0, 1e308, -1e308});
        text << " bad restitution.tangential " << show(bad.restitution.tangential);
        c.names = {"settings.restitution.tangential"};
        break;
      case 3:
        bad.contact_duration = bad_nonnegative(rng);
        text << " bad contact_duration " << show(*bad.contact_duration);
        c.names = {"settings.contact_duration"};
        break;
      case 4:
        bad.elastic_impact_speed = bad_nonnegative(rng);
        text << " bad elastic_impact_speed " << show(*bad.elastic_impact_speed);
        c.names = {"settings.elastic_impact_speed"};
        break;
      case 5:
        bad.sleep_speed = bad_nonnegative(rng);
        text << " bad sleep_speed " << show(*bad.sleep_speed);
        c.names = {"settings.sleep_speed"};
        break;
      case 6:
        bad.cell_size = bad_nonnegative(rng);
        text << " bad cell_size " << show(bad.cell_size);
        c.names = {"settings.cell_size"};
        break;
      default: {
        const int mode = pick(rng, std::vector<int>{-1, 3, 7, INT_MAX, INT_MIN});
        bad.prefetch = static_cast<billiard::Prefetch>(mode);
        text << " bad prefetch " << mode;
        c.names = {"settings.prefetch"};
        break;
      }
    }
  }
  c.text = "settings {" + text.str() + " }";
  return c;
}

// ---- Calls on a simulation ----

struct Call {
  std::string text;                 // what was called, for the failure messages
  Expect expect = Expect::Refused;
  bool setup = true;                // a setup call (adds discs): std::logic_error once started
  std::vector<std::string> names;   // the message must contain one of these
  std::function<void(Simulation&)> run;
};

Call refused(std::string text, std::vector<std::string> names, std::function<void(Simulation&)> run, bool setup = true) {
  return Call{std::move(text), Expect::Refused, setup, std::move(names), std::move(run)};
}

// A disc with exactly one bad field; the others fine (what add_disc checks first is named).
Call bad_disc(Rng& rng, int size) {
  Disc d = make_disc(point(rng, 3), point(rng, 2), uniform(rng, 0.1, 1), uniform(rng, 0.5, 2));
  std::string field;
  switch (integer(rng, 0, 5)) {
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
  const int rows = integer(rng, 0, 4);
  Coordinates positions(rows, 2), velocities(rows, 2);
  for (int k = 0; k < rows; ++k) {
    positions.row(k) = point(rng, 4);
    velocities.row(k) = point(rng, 1);
  }
  double radius = uniform(rng, 0.05, 0.2), mass = 1.0;
  std::vector<std::string> names;
  switch (integer(rng, 0, 3)) {
    case 0: {  // mismatched rows
      velocities.conservativeResize(rows + integer(rng, 1, 3), 2);
      velocities.setZero();
      names = {"velocities has"};
      break;
    }
    case 1: radius = bad_scale(rng); names = {"radius"}; break;
    case 2: mass = bad_scale(rng); names = {"mass"}; break;
    default: {  // one bad row: named, unless an earlier row conflicts with the container or the discs first
      const int k = integer(rng, 0, rows);
      positions.conservativeResize(std::max(rows, k + 1), 2);
      velocities.conservativeResize(std::max(rows, k + 1), 2);
      if (coin(rng)) {
        positions.row(k) = bad_point(rng);
        velocities.row(k).setZero();
      } else {
        positions.row(k) << 0.5, 0.5;
        velocities.row(k) = bad_point(rng);
      }
      names = {"position", "velocity", "overlaps", "outside", "too small", "too large"};
      break;
    }
  }
  std::ostringstream text;
  text << "add_discs(" << positions.rows() << " positions, " << velocities.rows() << " velocities, radius " << show(radius)
       << ", mass " << show(mass) << ")";
  return refused(text.str(), names, [=](Simulation& s) { s.add_discs(positions, velocities, radius, mass); });
}

Call bad_random_discs(Rng& rng) {
  int n = integer(rng, 1, 50);
  double radius = uniform(rng, 0.05, 0.3), mass = 1.0, kT = 1.0;
  std::vector<std::string> names;
  switch (integer(rng, 0, 4)) {
    case 0: n = pick(rng, std::vector<int>{-1, INT_MIN, -integer(rng, 1, INT_MAX)}); names = {"n must"}; break;
    case 1: radius = bad_scale(rng); names = {"radius"}; break;
    case 2: mass = bad_scale(rng); names = {"mass"}; break;
    case 3: kT = bad_nonnegative(rng); names = {"kT"}; break;
    default:  // impossible packings: must be refused at once, however large n is
      n = pick(rng, std::vector<int>{INT_MAX, 1 << 30, 1000000, 100000});
      radius = uniform(rng, 0.5, 2);
      // (A container whose coordinates are too large for the radius is refused first.)
      names = {"fit", "too small"};
      break;
  }
  const std::string text = "add_random_discs(" + std::to_string(n) + ", " + show(radius) + ", " + show(mass) + ", " + show(kT) + ")";
  const std::uint64_t seed = rng();
  return refused(text, names, [=](Simulation& s) { s.add_random_discs(n, radius, mass, kT, seed); });
}

// A random bad call of any kind, for the simulation `sim`.
Call bad_call(Rng& rng, const Simulation& sim) {
  switch (integer(rng, 0, 9)) {
    case 0:
    case 1: return bad_disc(rng, sim.size());
    case 2: return bad_discs(rng);
    case 3: return bad_random_discs(rng);
    case 4: {
      const bool normal = coin(rng);
      const double bad = pick(rng, std::vector<double>{kNan, kInf, -kInf, -0.1, 1.5, 1.0000000000000002, -kDenormal, 1e308, -1e308});
      const double tangential_bad = pick(rng, std::vector<double>{kNan, kInf, -kInf, -1.0000000000000002, 1.5, -2.0, 1e308, -1e308});
      const double n = normal ? bad : uniform(rng, 0, 1), t = normal ? uniform(rng, -1, 1) : tangential_bad;
      return refused("set_restitution({" + show(n) + ", " + show(t) + "})", {normal ? "set_restitution: restitution.normal" : "set_restitution: restitution.tangential"},
                     [=](Simulation& s) { s.set_restitution({n, t}); }, false);
    }
    case 5: {
      if (coin(rng)) {
        const std::int64_t events = pick(rng, std::vector<std::int64_t>{-1, INT64_MIN, INT_MIN, -(std::int64_t{1} << 40)});
        return refused("advance(" + std::to_string(events) + ")", {"max_events"}, [events](Simulation& s) { s.advance(events); }, false);
      }
      const double duration = pick(rng, std::vector<double>{kNan, -kNan, -kInf, -1.0, -kDenormal, -1e308});
      return refused("advance(10, " + show(duration) + ")", {"max_duration"}, [duration](Simulation& s) { s.advance(10, duration); }, false);
    }
    case 6: {
      const std::size_t size = sim.event_log().size();
      const std::size_t k = pick(rng, std::vector<std::size_t>{size, size + 1, SIZE_MAX, std::size_t{1} << 40, static_cast<std::size_t>(-1) / 2});
      return refused("Replay::after_event(" + std::to_string(k) + ")", {"k must"}, [k](const Simulation& s) { billiard::Replay(s).after_event(k); }, false);
    }
    case 7: {
      const double t = pick(rng, std::vector<double>{kNan, kInf, -kInf, -1.0, -kDenormal, -1e308});
      return refused("Replay::at(" + show(t) + ")", {"t must"}, [t](const Simulation& s) { billiard::Replay(s).at(t); }, false);
    }
    case 8: {
      const double value = bad_nonnegative(rng);
      if (coin(rng)) {
        return refused("set_contact_duration(" + show(value) + ")", {"set_contact_duration: duration"},
                       [value](Simulation& s) { s.set_contact_duration(value); }, false);
      }
      if (coin(rng)) {
        return refused("set_sleep_speed(" + show(value) + ")", {"set_sleep_speed: speed"}, [value](Simulation& s) { s.set_sleep_speed(value); }, false);
      }
      return refused("set_elastic_impact_speed(" + show(value) + ")", {"set_elastic_impact_speed: speed"},
                     [value](Simulation& s) { s.set_elastic_impact_speed(value); }, false);
    }
    default: {
      const double tolerance = bad_nonnegative(rng);
      return refused("validate(" + show(tolerance) + ")", {"tolerance"}, [tolerance](Simulation& s) { s.validate(tolerance); }, false);
    }
  }
}

// A valid call with random, sometimes extreme values: it may be accepted or refused (a disc
// outside the container, overlapping another or a wall, too small for the container).
Call plausible_call(Rng& rng) {
  auto any = [](std::string text, bool setup, std::function<void(Simulation&)> run) {
    return Call{std::move(text), Expect::Either, setup, {}, std::move(run)};
  };
  switch (integer(rng, 0, 7)) {
    case 7: {
      const std::optional<double> value = coin(rng) ? std::nullopt : std::optional<double>(pick(rng, std::vector<double>{0.0, 1e-3, 1.0, 1e308}));
      const std::string text = value ? show(*value) : "automatic";
      if (coin(rng)) return any("set_contact_duration(" + text + ")", false, [value](Simulation& s) { s.set_contact_duration(value); });
      if (coin(rng)) return any("set_sleep_speed(" + text + ")", false, [value](Simulation& s) { s.set_sleep_speed(value); });
      return any("set_elastic_impact_speed(" + text + ")", false, [value](Simulation& s) { s.set_elastic_impact_speed(value); });
    }
    case 0:
    case 1:
    case 2: {
      Disc d = make_disc(Vector(extreme(rng, 10), extreme(rng, 10)), Vector(extreme(rng, 3), extreme(rng, 3)), extreme_scale(rng, 0.5),
                         extreme_scale(rng, 1));
      if (coin(rng)) d.inertia = extreme_scale(rng, 0.5);
      if (coin(rng)) d.spin = coin(rng) ? uniform(rng, -2, 2) : pick(rng, std::vector<double>{0.0, -0.0, kDenormal, -1e-308, 1e-50, 2.0, 1e30, -1e50, 1e50});
      return any("add_disc(position " + show(d.position) + ", velocity " + show(d.velocity) + ", radius " + show(d.radius) + ", mass " +
                     show(d.mass) + ", inertia " + (d.inertia ? show(*d.inertia) : "none") + ", spin " + show(d.spin) + ")",
                 true, [d](Simulation& s) { s.add_disc(d); });
    }
    case 3: {
      const int n = integer(rng, 0, 30);
      const double radius = pick(rng, std::vector<double>{1e-50, 1e-10, 0.1, 0.3}), kT = pick(rng, std::vector<double>{0.0, 1e-300, 1.0, 1e50});
      const std::uint64_t seed = rng();
      return any("add_random_discs(" + std::to_string(n) + ", " + show(radius) + ", 1, " + show(kT) + ")", true,
                 [=](Simulation& s) { s.add_random_discs(n, radius, 1.0, kT, seed); });
    }
    case 4: {
      const double n = normal_restitution(rng), t = pick(rng, std::vector<double>{-1.0, 1.0, 0.0, -0.0, -kDenormal});
      return any("set_restitution({" + show(n) + ", " + show(t) + "})", false, [=](Simulation& s) { s.set_restitution({n, t}); });
    }
    case 5: {
      const bool on = coin(rng);
      return any(std::string("set_exchange_velocities(") + (on ? "true" : "false") + ")", false, [on](Simulation& s) { s.set_exchange_velocities(on); });
    }
    default: {
      const std::int64_t events = pick(rng, std::vector<std::int64_t>{0, 1, 50});
      const double duration = pick(rng, std::vector<double>{0.0, -0.0, kDenormal, 1e-300, 0.5, kInf});
      return any("advance(" + std::to_string(events) + ", " + show(duration) + ")", false, [=](Simulation& s) { s.advance(events, duration); });
    }
  }
}

// ---- The checks ----

struct Counts {
  int shapes = 0;            // shape functions called
  int shapes_refused = 0;
  int additions = 0;         // add_ calls on containers
  int additions_refused = 0;
  int additions_accepted = 0;
  int settings_refused = 0;  // simulations refused for a bad settings field
  int calls = 0;             // calls on simulations
  int refused = 0;           // std::invalid_argument
  int wrong_phase = 0;       // std::logic_error: adding discs after the first advance
  int accepted = 0;
  double slowest = 0;        // seconds
  // The systems made: how many ran before their call, their events, and settings drawn.
  int runs = 0;
  std::int64_t events = 0;
  int periodic_gravity = 0;  // periodic boxes under gravity
  int zero_restitution = 0;  // normal restitution 0
  int huge_spins = 0;        // a disc spinning at 1e30 or more
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Runs `run`, timed (each call well within kSecondsPerCall): what its std::invalid_argument said,
// if it threw one. A bad call (`expect` Refused) must be refused naming one of `names`; a valid
// call may be refused only naming its function (the start of `text`). Fails on any other
// exception.
template <class Run>
std::optional<std::string> judged_call(const std::string& text, Expect expect, const std::vector<std::string>& names,
                                       Counts& counts, Run run) {
  std::optional<std::string> message;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    run();
  } catch (const std::invalid_argument& e) {
    message = e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected exception: " << e.what();
  }
  counts.slowest = std::max(counts.slowest, seconds_since(t0));
  EXPECT_LT(seconds_since(t0), kSecondsPerCall);
  if (expect == Expect::Refused) {
    EXPECT_TRUE(message.has_value()) << "must throw std::invalid_argument";
    if (message) {
      EXPECT_TRUE(names_one_of(*message, names)) << "the message names none of the expected arguments: " << *message;
    }
  } else if (message) {
    EXPECT_EQ(message->rfind(function_of(text) + ":", 0), 0u) << *message;
  }
  return message;
}

// Runs a shape function. A bad one must be refused naming its bad argument; a valid one may be
// refused only naming the function. The container, if made, goes to `made`.
void check_shape(const ShapeCall& call, Counts& counts, std::optional<Container>& made) {
  SCOPED_TRACE(call.text);
  ++counts.shapes;
  if (judged_call(call.text, call.expect, call.names, counts, [&] { made = call.make(); })) ++counts.shapes_refused;
}

// Runs an add_ call on `container`. A refused call (a bad one must be, naming its bad argument; a
// valid one names the function) leaves the container unchanged, bit for bit; an accepted one
// returns the index of its wall.
void check_addition(Container& container, const Addition& call, Counts& counts) {
  SCOPED_TRACE(call.text);
  const Snapshot before = snapshot(container);
  const std::size_t walls = container.walls().size();
  int index = -1;
  ++counts.additions;
  const std::optional<std::string> message =
      judged_call(call.text, call.expect, call.names, counts, [&] { index = call.run(container); });
  if (!message) {
    if (call.expect == Expect::Refused) return;
    ++counts.additions_accepted;
    EXPECT_GT(container.walls().size(), walls);
    if (index >= 0) {  // add_segment and add_arc return the index of the new wall
      EXPECT_EQ(index, static_cast<int>(walls));
      EXPECT_TRUE(container.walls()[static_cast<std::size_t>(index)].kind == billiard::WallKind::Segment ||
                  container.walls()[static_cast<std::size_t>(index)].kind == billiard::WallKind::Arc);
    }
    return;
  }
  ++counts.additions_refused;
  EXPECT_EQ(difference(before, snapshot(container)), "") << *message;
}

// Makes the simulation of `container` under random settings: with a bad field, it must be refused
// naming the field, and is made with the field valid. The simulation holds what it was given and
// is valid.
void check_settings(const Container& container, const SettingsCase& c, Counts& counts, std::optional<Simulation>& made) {
  SCOPED_TRACE(c.text);
  std::optional<std::string> message;
  try {
    made.emplace(container, c.settings);
  } catch (const std::invalid_argument& e) {
    message = e.what();
  } catch (const std::exception& e) {
    FAIL() << "unexpected exception: " << e.what();
  }
  if (c.names.empty()) {
    ASSERT_FALSE(message.has_value()) << "valid settings refused: " << *message;
  } else {
    ASSERT_TRUE(message.has_value()) << "a bad settings field must be refused";
    EXPECT_TRUE(names_one_of(*message, c.names)) << "the message names none of the expected fields: " << *message;
    ++counts.settings_refused;
    made.emplace(container, c.valid);
  }
  const Simulation& sim = *made;
  EXPECT_EQ(difference(snapshot(container), snapshot(sim.container())), "");
  EXPECT_EQ(sim.gravity(), c.valid.gravity);
  EXPECT_EQ(sim.restitution().normal, c.valid.restitution.normal);
  EXPECT_EQ(sim.restitution().tangential, c.valid.restitution.tangential);
  EXPECT_EQ(sim.exchange_velocities(), c.valid.exchange_velocities);
  EXPECT_EQ(sim.size(), 0);
  ASSERT_EQ(made->validate(), std::nullopt);
}

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

// One call on a simulation in the state of `start` (a copy; start itself stays untouched, for the
// comparison below).
void check(const std::string& history, const Simulation& start, const Call& call, Counts& counts) {
  SCOPED_TRACE(history + ": " + call.text);
  Simulation sim = start;
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
  const double seconds = seconds_since(t0);
  counts.slowest = std::max(counts.slowest, seconds);
  EXPECT_LT(seconds, kSecondsPerCall);
  ++counts.calls;

  if (wrong_phase) {
    ASSERT_EQ(outcome, LogicError) << "adding discs after the first advance must throw std::logic_error; message: " << message;
    EXPECT_NE(message.find("started"), std::string::npos) << message;
    ++counts.wrong_phase;
  } else if (call.expect == Expect::Refused) {
    ASSERT_EQ(outcome, InvalidArgument) << "must throw std::invalid_argument; message: " << message;
    EXPECT_TRUE(names_one_of(message, call.names)) << "the message names none of the expected arguments: " << message;
    ++counts.refused;
  } else if (outcome == Accepted) {
    ++counts.accepted;
    EXPECT_EQ(sim.validate(), std::nullopt);
    ASSERT_TRUE(finite_state(sim));
    Snapshot ignored;
    const auto t1 = std::chrono::steady_clock::now();
    const std::string thrown = advanced(sim, ignored);
    EXPECT_LT(seconds_since(t1), kSecondsPerCall);
    EXPECT_EQ(thrown, "");
    EXPECT_EQ(sim.validate(), std::nullopt);
    EXPECT_TRUE(finite_state(sim)) << "an accepted call led to non-finite discs";
    return;
  } else {
    // Refused valid-looking call: the message starts with the call's name, or "disc k:".
    ASSERT_EQ(outcome, InvalidArgument) << message;
    EXPECT_TRUE(message.rfind(function_of(call.text) + ":", 0) == 0 || message.rfind("disc ", 0) == 0) << message;
    ++counts.refused;
  }
  // Refused: nothing changed, the simulation is valid and runs on exactly like an untouched copy.
  EXPECT_EQ(difference(before, snapshot(sim)), "") << message;
  EXPECT_EQ(sim.validate(), std::nullopt);
  Simulation copy = start;
  copy.validate();  // (validate() records what it finds, as on `sim` above)
  Snapshot after_sim, after_copy;
  const std::string thrown_sim = advanced(sim, after_sim);
  const std::string thrown_copy = advanced(copy, after_copy);
  EXPECT_EQ(thrown_sim, thrown_copy);
  EXPECT_EQ(difference(after_copy, after_sim), "") << "the refused call changed what happens next";
}

// A random system, described step by step, each step checked: a shape (sometimes a bad one
// first), add_ calls, settings. `history` says how it was made.
void make_system(Rng& rng, Counts& counts, std::string& history, std::optional<Simulation>& made) {
  std::optional<Container> container;
  if (integer(rng, 0, 2) == 0) {
    check_shape(bad_shape_call(rng), counts, container);
    if (::testing::Test::HasFatalFailure()) return;
  }
  const ShapeCall shape = plausible_shape_call(rng);
  check_shape(shape, counts, container);
  if (::testing::Test::HasFatalFailure()) return;
  if (container) {
    history = shape.text;
  } else {
    auto [text, ordinary] = ordinary_container(rng);
    history = text;
    container = std::move(ordinary);
  }
  for (int k = integer(rng, 0, 3); k > 0; --k) {
    const Addition addition = coin(rng) ? bad_addition_call(rng, *container) : plausible_addition_call(rng);
    const std::size_t walls = container->walls().size();
    check_addition(*container, addition, counts);
    if (::testing::Test::HasFatalFailure()) return;
    if (container->walls().size() != walls) history += ", " + addition.text;
  }
  const SettingsCase settings = random_settings(rng);
  check_settings(*container, settings, counts, made);
  if (::testing::Test::HasFatalFailure()) return;
  history += ", " + (settings.names.empty() ? settings.text : "valid " + settings.text);
}

// Discs for a new simulation: random ones sized to the container, a few plausible calls, and
// sometimes a start (kept where accepted).
void add_discs(Rng& rng, Simulation& sim, std::string& history) {
  if (integer(rng, 0, 3) > 0) {
    Vector lower, upper;
    bounds(sim.container(), lower, upper);
    const double side = (upper - lower).minCoeff();
    const int n = integer(rng, 0, 30);
    double radius = side * uniform(rng, 0.005, 0.03);
    if (!(radius >= 1e-50 && radius <= 1e50)) radius = 0.5;
    const std::uint64_t seed = rng();
    try {
      sim.add_random_discs(n, radius, uniform(rng, 0.5, 2), 1.0, seed);
      history += ", add_random_discs(" + std::to_string(n) + ", " + show(radius) + ")";
    } catch (const std::invalid_argument&) {
    }
  }
  for (int step = integer(rng, -2, 2); step > 0; --step) {
    const Call call = plausible_call(rng);
    try {
      call.run(sim);
      history += ", " + call.text;
    } catch (const std::exception&) {
    }
  }
  if (integer(rng, 0, 3) == 0) {
    const bool log = coin(rng);
    const std::int64_t events = integer(rng, 0, 200);
    sim.set_log_events(log);
    sim.advance(events);
    history += std::string(log ? ", event log on" : "") + ", advance(" + std::to_string(events) + ")";
  }
}

}  // namespace

TEST(FuzzApi, BadCallsAreRefusedNamingTheArgumentAndChangeNothing) {
  // BILLIARD_FUZZ_SEED=k explores another corpus (or reproduces one printed before).
  const char* chosen = std::getenv("BILLIARD_FUZZ_SEED");
  const std::uint64_t seed = chosen ? std::stoull(chosen) : kSeed;
  std::cout << "api fuzz seed " << seed << "\n";
  Rng rng(seed);
  Counts counts;
  const int calls = 6000;
  for (int k = 0; k < calls; ++k) {
    std::string history;
    std::optional<Simulation> made;
    make_system(rng, counts, history, made);
    if (::testing::Test::HasFatalFailure()) return;
    add_discs(rng, *made, history);
    ASSERT_EQ(made->validate(), std::nullopt) << history;
    const billiard::Totals totals = made->totals();
    const std::int64_t events = totals.disc_collisions + totals.wall_collisions + totals.cell_crossings;
    counts.runs += events > 0;
    counts.events += events;
    counts.periodic_gravity += made->container().periodic() && made->gravity() != Vector::Zero();
    counts.zero_restitution += made->restitution().normal == 0;
    counts.huge_spins += made->size() > 0 && made->current_state().spins.cwiseAbs().maxCoeff() >= 1e30;
    const Call call = k % 5 == 4 ? plausible_call(rng) : bad_call(rng, *made);
    check(history, *made, call, counts);
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::cout << "api fuzz: " << counts.shapes << " shape functions (" << counts.shapes_refused << " refused), " << counts.additions
            << " add_ calls on containers (" << counts.additions_refused << " refused, " << counts.additions_accepted << " accepted), "
            << counts.settings_refused << " simulations refused for bad settings; " << counts.calls << " calls on simulations, "
            << counts.refused << " refused (std::invalid_argument), " << counts.wrong_phase
            << " refused for the state (std::logic_error: discs added after the start), " << counts.accepted
            << " accepted (valid, some extreme); every refusal left the container or simulation unchanged; slowest call "
            << counts.slowest << " s; " << counts.runs << " systems run before their call (" << counts.events
            << " events), drawn: " << counts.periodic_gravity << " periodic boxes under gravity, " << counts.zero_restitution
            << " with restitution 0, " << counts.huge_spins << " with a spin of 1e30 or more\n";
  EXPECT_EQ(counts.calls, calls);
  EXPECT_GT(counts.shapes_refused, calls / 5);
  EXPECT_GT(counts.additions_refused, calls / 2);
  EXPECT_GT(counts.additions_accepted, calls / 5);
  EXPECT_GT(counts.settings_refused, calls / 5);
  EXPECT_GT(counts.refused, calls / 2);
  EXPECT_GT(counts.wrong_phase, 100);
  EXPECT_GT(counts.accepted, 100);
  EXPECT_GT(counts.periodic_gravity, 50);
  EXPECT_GT(counts.zero_restitution, 50);
  EXPECT_GT(counts.huge_spins, 5);
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
    Simulation sim(billiard::circular_table(10));
    const Snapshot before = snapshot(sim);
    EXPECT_LT(seconds([&] { EXPECT_THROW(sim.add_random_discs(n, 1.0), std::invalid_argument); }), 1.0) << n;
    EXPECT_EQ(difference(before, snapshot(sim)), "");
  }
  // A small disc then one 4 x 10^5 times larger: the overlap test must not scan 10^11 cells of
  // the small disc's size.
  {
    Simulation sim(billiard::circular_table(1e6));
    sim.add_disc(make_disc(Vector(0, 0), Vector(1, 0), 1.0));
    EXPECT_LT(seconds([&] { sim.add_disc(make_disc(Vector(5e5, 0), Vector(0, 1), 4e5)); }), 1.0);
    EXPECT_LT(seconds([&] { EXPECT_THROW(sim.add_disc(make_disc(Vector(-4e5, 0), Vector(0, 0), 4e5)), std::invalid_argument); }), 1.0);
    EXPECT_EQ(sim.size(), 2);
    EXPECT_EQ(sim.validate(), std::nullopt);
  }
  // The smallest radii allowed: two at the same place overlap (below them, squares underflow and
  // the overlap would go unseen).
  {
    Simulation sim(billiard::circular_table(1e-45));
    sim.add_disc(make_disc(Vector(1e-46, 0), Vector(0, 0), 1e-50));
    EXPECT_THROW(sim.add_disc(make_disc(Vector(1e-46, 0), Vector(0, 0), 1e-50)), std::invalid_argument);
    EXPECT_THROW(sim.add_disc(make_disc(Vector(0, 0), Vector(0, 0), 1e-300)), std::invalid_argument);
  }
  // A gigantic table, the lightest discs and the largest temperature allowed.
  {
    Simulation sim(billiard::circular_table(1e50));
    EXPECT_LT(seconds([&] { sim.add_random_discs(100, 1e46, 1e-50, 1e50, 3); }), 5.0);
    EXPECT_EQ(sim.size(), 100);
    EXPECT_LT(seconds([&] { sim.advance(200); }), 5.0);
    EXPECT_EQ(sim.validate(), std::nullopt);
    EXPECT_TRUE(finite_state(sim));
  }
  // A thin polygon in a huge bounding box: the lattice over the box would not fit in memory.
  {
    Coordinates sliver(3, 2);
    sliver << 0, 0, 1e6, 1e6, 1e6, 1e6 + 1;
    Simulation sim(billiard::polygon(sliver));
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
    Simulation sim(billiard::periodic_box(1e-50, 1e-50));
    EXPECT_LT(seconds([&] { EXPECT_EQ(sim.advance(billiard::kAllEvents).collisions, 0); }), 1.0);
    EXPECT_EQ(sim.validate(), std::nullopt);
  }
}

TEST(FuzzApi, ACopyRunsOnLikeTheOriginal) {
  // The fuzzing compares refused calls with untouched copies, so copies of running simulations
  // must be independent of their originals: advancing or destroying the original changes nothing.
  auto running = [] {
    Simulation sim(billiard::box(Vector(0, 0), Vector(20, 20)));
    sim.add_random_discs(40, 0.5, 1.0, 1.0, 8);
    sim.advance(300);
    return sim;
  };
  Simulation reference = running();
  reference.advance(500);
  auto original = std::make_unique<Simulation>(running());
  Simulation copied(*original);
  Simulation assigned(billiard::circular_table(1));  // (replaced whole by the assignment)
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
    Settings settings;
    settings.restitution = {c.normal, c.tangential};
    settings.contact_duration = c.contact_duration;
    Simulation sim(billiard::circular_table(10), settings);
    sim.add_random_discs(20, 0.5, 1.0, 1.0, 1);
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
    Simulation sim(billiard::circular_table(5));
    sim.add_disc(make_disc(Vector(0, 0.1), Vector(speed, 0), 0.3));
    sim.advance(1, 1.0);
    EXPECT_EQ(sim.validate(), std::nullopt) << "speed " << speed;
  }
}

// Containers smaller than any disc (a length below 1e-50, whose square underflows) are refused
// by their shape functions; the smallest and the most elongated ones allowed make simulations
// that advance with a bounded grid. (Before such lengths were refused, advance() threw
// std::bad_alloc on them.)
TEST(FuzzApi, TinyContainersAreRefusedAndTheSmallestAllowedRun) {
  const std::vector<std::pair<std::string, std::function<Container()>>> refused = {
      {"width", [] { return billiard::periodic_box(kDenormal, 20); }},
      {"height", [] { return billiard::periodic_box(1, 1e-200); }},
      {"radius", [] { return billiard::circular_table(1e-200); }},
      {"upper", [] { return billiard::box(Vector(0, 0), Vector(1e-300, 1)); }},
      {"obstacle_radius", [] { return billiard::sinai_billiard(Vector(0, 0), Vector(1, 1), 1e-60); }},
      {"radius", [] { return billiard::stadium(Vector(0, 0), 1e-60, 1); }}};
  for (const auto& [name, make] : refused) {
    try {
      make();
      ADD_FAILURE() << name << ": accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  const std::vector<std::function<Container()>> smallest = {
      [] { return billiard::periodic_box(1e-50, 20); }, [] { return billiard::periodic_box(1e-50, 1e-50); },
      [] { return billiard::circular_table(1e-50); }, [] { return billiard::box(Vector(0, 0), Vector(1e-50, 1e50)); }};
  for (std::size_t k = 0; k < smallest.size(); ++k) {
    Simulation sim(smallest[k]());
    EXPECT_NO_THROW(sim.advance(1)) << "shape " << k;
    EXPECT_LE(sim.cell_count(), 1 << 20) << "shape " << k;
  }
}


// ---- The long fuzz (label stress) ----

namespace {

// Kinetic plus potential energy, the potential from unwrapped positions in a periodic box (a
// wrap moves a disc by a period, not its energy), and the scale of its rounding: the sum of the
// terms' magnitudes.
struct Energy {
  double value = 0;
  double scale = 0;
};
Energy total_energy(const Simulation& sim) {
  const billiard::State s = sim.current_state();
  const billiard::Images images = sim.images();
  const Eigen::VectorXd masses = sim.masses();
  const Vector g = sim.gravity();
  const Vector period = sim.container().periodic() ? sim.container().period() : Vector::Zero();
  Energy e;
  if (period != Vector::Zero() && g != Vector::Zero()) {
    // A periodic box under gravity: the gas falls for ever, and after a fall of 2^63 periods its
    // image counts no longer fit (they saturate), so the energy about the centre of mass, which
    // gravity does not change, is checked (the fall itself: LostDiscs.LongPeriodicRuns...). The
    // reported velocities carry the fall g t, so their rounding scales with it.
    const Eigen::VectorXd inertias = sim.inertias();
    const Vector centre_velocity = masses.transpose() * s.velocities / masses.sum();
    for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
      const Vector v = s.velocities.row(i) - centre_velocity;
      const double spin = 0.5 * inertias[i] * s.spins[i] * s.spins[i];
      e.value += 0.5 * masses[i] * v.squaredNorm() + spin;
      e.scale += 0.5 * masses[i] * s.velocities.row(i).squaredNorm() + spin;
    }
    return e;
  }
  e.value = sim.kinetic_energy();
  e.scale = e.value;
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
    const Vector unwrapped(s.positions(i, 0) + static_cast<double>(images(i, 0)) * period.x(),
                         s.positions(i, 1) + static_cast<double>(images(i, 1)) * period.y());
    e.value -= masses[i] * g.dot(unwrapped);
    e.scale += masses[i] * g.norm() * unwrapped.norm();
  }
  return e;
}

struct StressCounts {
  int runs = 0, periodic_runs = 0, gravity = 0, inelastic = 0, rough = 0, huge_spins = 0, extreme_scales = 0, stuck = 0;
  std::int64_t collisions = 0, crossings = 0, discs = 0;
};

// A random system for the long fuzz: any accepted shape (a refused one replaced by an ordinary
// container), walls and obstacles added, valid settings over their whole ranges, random discs
// (and sometimes one with a huge spin).
Simulation stress_system(Rng& rng, StressCounts& counts, std::string& history) {
  std::optional<Container> container;
  const ShapeCall shape = plausible_shape_call(rng);
  try {
    container = shape.make();
    history = shape.text;
  } catch (const std::invalid_argument&) {
    auto [text, ordinary] = ordinary_container(rng);
    history = text;
    container = std::move(ordinary);
  }
  for (int k = integer(rng, 0, 3); k > 0; --k) {
    const Addition addition = plausible_addition_call(rng);
    try {
      addition.run(*container);
      history += ", " + addition.text;
    } catch (const std::invalid_argument&) {
    }
  }
  const Settings settings = random_settings(rng).valid;
  Simulation sim(*container, settings);
  history += ", gravity " + show(settings.gravity) + ", restitution " + show(settings.restitution.normal) + ", " +
             show(settings.restitution.tangential);
  Vector lower, upper;
  bounds(sim.container(), lower, upper);
  const double side = (upper - lower).minCoeff();
  if (!(side > 1e-30 && side < 1e30)) ++counts.extreme_scales;
  int n = static_cast<int>(std::exp(uniform(rng, 0, std::log(300.0))));
  double radius = side * uniform(rng, 0.003, 0.04);
  radius = std::clamp(radius, 1e-50, 1e50);
  const double mass = pick(rng, std::vector<double>{1.0, 1e-20, 1e20, uniform(rng, 0.5, 2)});
  const double kT = pick(rng, std::vector<double>{1.0, 1.0, 1e-20, 1e20});
  const std::uint64_t seed = rng();
  for (; n > 0; n /= 2) {
    try {
      sim.add_random_discs(n, radius, mass, kT, seed);
      history += ", add_random_discs(" + std::to_string(n) + ", " + show(radius) + ", " + show(mass) + ", " + show(kT) + ", " +
                 std::to_string(seed) + ")";
      break;
    } catch (const std::invalid_argument&) {
    }
  }
  if (settings.restitution.tangential > -1 && coin(rng)) {  // a disc spinning as fast as allowed
    Disc d = make_disc(wrap(sim.container(), 0.5 * (lower + upper) + Vector(uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3)).cwiseProduct(upper - lower)),
                       Vector::Zero(), radius, mass);
    d.spin = pick(rng, std::vector<double>{1e30, -1e50, 1e50});
    try {
      sim.add_disc(d);
      history += ", a disc of spin " + show(d.spin);
      ++counts.huge_spins;
    } catch (const std::invalid_argument&) {
    }
  }
  ++counts.runs;
  if (sim.container().periodic()) ++counts.periodic_runs;
  if (settings.gravity != Vector::Zero()) ++counts.gravity;
  if (settings.restitution.normal < 1) ++counts.inelastic;
  if (settings.restitution.tangential > -1) ++counts.rough;
  counts.discs += sim.size();
  return sim;
}

// Runs `sim` for up to `events` events in blocks, each event's discs checked; fails unless it ends
// valid with the energy not above its start (beyond rounding). Returns false at a failure.
bool run_checked(Simulation& sim, std::int64_t events, double duration, StressCounts& counts, const std::string& history) {
  SCOPED_TRACE(history);
  sim.set_check_event_discs(true);
  const Energy start = total_energy(sim);
  std::int64_t done = 0;
  while (done < events) {
    // (advance counts collisions; a dilute gas may cross cells many times between two, and these
    // events count here too.)
    const std::int64_t chunk = std::min<std::int64_t>(200000, events - done);
    const billiard::AdvanceResult r = sim.advance(chunk, duration, [chunk](const billiard::AdvanceResult& so_far) {
      return so_far.collisions + so_far.cell_crossings >= chunk;
    });
    counts.collisions += r.collisions;
    counts.crossings += r.cell_crossings;
    done += r.collisions + r.cell_crossings;
    EXPECT_EQ(sim.last_problem(), std::nullopt) << "after " << done << " events";
    if (sim.last_problem()) return false;
    if (r.stuck) ++counts.stuck;
    if (r.stuck || r.collisions + r.cell_crossings == 0) break;
  }
  EXPECT_EQ(sim.validate(), std::nullopt) << "after " << done << " events";
  const Energy end = total_energy(sim);
  if (std::isfinite(start.value) && std::isfinite(end.value) && std::isfinite(start.scale + end.scale)) {
    EXPECT_LE(end.value, start.value + 1e-9 * std::max(start.scale, end.scale)) << "the energy rose, after " << done << " events";
  }
  return !::testing::Test::HasFailure();
}

}  // namespace

// Random containers (every shape, with and without walls, arcs and obstacles) and settings over
// their whole accepted ranges (restitution 0 to 1, gravity on and off, rough discs, extreme but
// accepted sizes, masses, temperatures and spins), random N, each run for up to 10^6 events with
// the discs of every event checked: 10^8 events in all. Then discs crossing periodic boxes, with
// and without gravity, for 10^8 cell crossings. Every run ends valid, and the energy (kinetic and
// potential; in a periodic box under gravity, about the centre of mass) never rises.
// BILLIARD_FUZZ_SEED=k explores another corpus.
TEST(FuzzApi, StressRandomSystemsStayValidOverAHundredMillionEvents) {
  const char* chosen = std::getenv("BILLIARD_FUZZ_SEED");
  const std::uint64_t seed = chosen ? std::stoull(chosen) : kSeed;
  Rng rng(seed);
  StressCounts counts;
  while (counts.collisions + counts.crossings < 100000000) {
    std::string history;
    Simulation sim = stress_system(rng, counts, history);
    if (!run_checked(sim, 1000000, billiard::kNever, counts, "run " + std::to_string(counts.runs) + ": " + history)) return;
  }
  const std::int64_t events = counts.collisions + counts.crossings;
  // Periodic boxes: a few discs each, crossing cells for a long time (a duration, so that runs
  // without a collision are not taken for stuck ones).
  StressCounts periodic;
  while (periodic.crossings < 100000000) {
    const Vector size(uniform(rng, 1, 30), uniform(rng, 1, 30));  // (extreme sizes: above)
    Settings settings;
    if (coin(rng)) settings.gravity = Vector(uniform(rng, -1, 1), uniform(rng, -1, 1)) * pick(rng, std::vector<double>{1.0, 1e-3, 1e3});
    Simulation sim(billiard::periodic_box(size.x(), size.y()), settings);
    const int n = integer(rng, 1, 4);
    sim.add_random_discs(n, 0.02 * size.minCoeff(), 1.0, 1.0, rng());
    ++periodic.runs;
    if (settings.gravity != Vector::Zero()) ++periodic.gravity;
    const std::string history = "periodic_box(" + show(size.x()) + ", " + show(size.y()) + "), gravity " + show(settings.gravity) +
                                ", " + std::to_string(n) + " discs";
    // About 2 x 10^7 crossings per run: time for a disc at speed 1 to cross 10^7 cells (under
    // gravity too: the discs cross the cells of the freely falling frame, lib/DESIGN.md).
    const double cell = size.maxCoeff() / 3;
    const double duration = 1e7 * cell / n;
    if (!run_checked(sim, 20000000, duration, periodic, "periodic run " + std::to_string(periodic.runs) + ": " + history)) return;
  }
  std::cout << "stress fuzz seed " << seed << ": " << counts.runs << " random systems (" << counts.periodic_runs << " periodic, "
            << counts.gravity << " under gravity, " << counts.inelastic << " inelastic, " << counts.rough << " rough, "
            << counts.huge_spins << " with a spin of 1e30 to 1e50, " << counts.extreme_scales << " of extreme size; "
            << counts.discs << " discs), " << events << " events (" << counts.collisions << " collisions, " << counts.crossings
            << " cell crossings), " << counts.stuck << " ended stuck (valid); " << periodic.runs << " periodic runs ("
            << periodic.gravity << " under gravity), " << periodic.crossings << " cell crossings; every run ended valid, "
            << "its energy never above the start\n";
  EXPECT_GE(events, 100000000);
  EXPECT_GE(periodic.crossings, 100000000);
}
