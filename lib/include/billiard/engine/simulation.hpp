// The simulation: discs and walls, advanced from collision to collision.
//
//   billiard::Simulation sim;
//   sim.add_box({0, 0}, {10, 10});                       // or set_circular_table / set_periodic_box
//   billiard::Disc d;  d.position = {1, 1};  d.velocity = {1, 0.5};
//   int id = sim.add_disc(d);
//   sim.advance(1000);                                   // 1000 collisions, or
//   sim.advance(kAllEvents, 2.5);                        // 2.5 time units
//   billiard::State now = sim.current_state();
//
// Setup (discs, walls, container, gravity, cell size) must be complete before the first
// advance(); afterwards only the restitution, the event log and validation can change. Every
// setup call checks its input and throws std::invalid_argument naming the argument (and the disc
// index) and its value; a refused call leaves the simulation unchanged. A setup call after the
// first advance() throws std::logic_error (the call is the mistake, whatever its arguments), as
// does advance() without a container. Numbers must be finite and at most 1e50 in magnitude, and
// radii, masses and moments of inertia at least 1e-50: the engine squares and multiplies them,
// and beyond that the products overflow or underflow. Radii must also be at least 1e-6 of the
// coordinates of the container and the discs: positions are computed to about 1e-16 of them.
//
// Units: the user's. Time starts at 0. Energy is conserved to rounding for smooth elastic discs
// (about 1e-16 relative per collision, a random walk).
#pragma once

#include "billiard/engine/collide.hpp"
#include "billiard/engine/disc.hpp"
#include "billiard/engine/vec2.hpp"
#include "billiard/engine/wall.hpp"

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace billiard {

inline constexpr std::int64_t kAllEvents = std::numeric_limits<std::int64_t>::max();

// What advance() did. "Collisions" are disc-disc plus disc-wall events; cell crossings and
// stale queue entries are bookkeeping and are counted separately.
struct AdvanceResult {
  std::int64_t collisions = 0;
  std::int64_t disc_collisions = 0;
  std::int64_t wall_collisions = 0;
  std::int64_t cell_crossings = 0;
  std::int64_t stale_events = 0;
  double elapsed = 0.0;  // simulated time advanced
  // True if the run stopped because events kept happening at the same instant (a disc resting
  // on a floor under gravity, an inelastic collapse: event-driven dynamics cannot continue), or
  // because, with no duration limit, only cell crossings happened for a very long time (no
  // collision can happen, e.g. all discs moving in parallel in a periodic box).
  bool stuck = false;
  std::string stuck_reason;  // what happened, when stuck; the state is valid and advance may go on
};

// Running totals since time 0, for pressure: PA = N kT + virial / (2 t) (lib/PHYSICS.md,
// "Statistical physics") and the
// momentum given to the walls per unit time and length.
struct Totals {
  double wall_momentum = 0.0;  // sum of |impulse| given to walls
  double virial = 0.0;         // sum over disc-disc collisions of r_ij . dp_i
  std::int64_t disc_collisions = 0;
  std::int64_t wall_collisions = 0;
  std::int64_t cell_crossings = 0;
};

class Simulation {
 public:
  Simulation();
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;
  Simulation(const Simulation&);
  Simulation& operator=(const Simulation&);

  // ---- Containers (at least one is needed before advance) ----
  // Circular table of `radius` centred at the origin; discs live inside it.
  void set_circular_table(double radius);
  // Periodic box [0, width) x [0, height): the standard bulk system (no walls inside it).
  void set_periodic_box(double width, double height);
  // A straight wall from a to b (two-sided) and its two end points; returns the segment's wall
  // index. End points shared with earlier segments are not duplicated.
  int add_segment(const Vec2& a, const Vec2& b);
  // The four walls of the axis-aligned box [lower, upper]; discs live inside it.
  void add_box(const Vec2& lower, const Vec2& upper);
  // A closed polygon (vertices N by 2, N >= 3, in order): one segment per side. Discs must be
  // inside an odd number of the closed polygons and boxes (so a polygon inside a box is an
  // obstacle).
  void add_polygon(const Points& vertices);
  // Curved walls. Angles in radians, counter-clockwise from +x.
  // A circular arc (two-sided, like a segment: discs meet it from inside its circle or from
  // outside) of `radius` about `centre`, counter-clockwise from start_angle to end_angle
  // (0 < end_angle - start_angle <= 2 pi; 2 pi is a whole circle), and its two end points;
  // returns the arc's wall index.
  int add_arc(const Vec2& centre, double radius, double start_angle, double end_angle);
  // A disc obstacle: a whole circle that discs stay outside of (a hole in the container, which
  // must be set as well: a table, box, polygon or curved outline around it).
  void add_disc_obstacle(const Vec2& centre, double radius);
  // A stadium: two half circles of `radius` whose centres lie `length` apart on a horizontal
  // line through `centre`, joined by two straight sides of that length; discs live inside it.
  void add_stadium(const Vec2& centre, double radius, double length);
  // The Sinai billiard: the box [lower, upper] with a disc obstacle of obstacle_radius at its
  // middle (2 obstacle_radius below the smaller side).
  void add_sinai_billiard(const Vec2& lower, const Vec2& upper, double obstacle_radius);
  // A mushroom: a half-disc cap of cap_radius above the horizontal line through `centre` (the
  // middle of its flat side), on a rectangular stem stem_width wide (< 2 cap_radius) and
  // stem_height tall below it; discs live inside it.
  void add_mushroom(const Vec2& centre, double cap_radius, double stem_width, double stem_height);
  // The union of circles (centres N by 2, radii N): its boundary is the arcs of each circle
  // outside all the others, and the points where two such arcs meet are point walls. Discs
  // live inside the union.
  // The curved outlines count in the even-odd rule like polygons.
  void add_union_of_circles(const Points& centres, const std::vector<double>& radii);

  // ---- Physics ----
  void set_gravity(const Vec2& g);                      // uniform, any direction; default 0
  void set_restitution(double normal, double tangential = -1.0);  // see collide.hpp
  // The exchange rule (off by default): two discs that meet reverse their whole relative
  // velocity, so discs of equal mass exchange their velocities (exactly); walls reflect like
  // mirrors (the normal component reverses). For equal masses this is perfectly rough discs
  // (tangential restitution +1) whose spins never change (an infinite moment of inertia), but
  // with smooth walls: the rule of the classic "Collisions" exercise (the `particles` program).
  // Momentum and energy are conserved. While it is on, the restitution and the granular rules
  // do not apply to discs meeting discs (a disc meeting a sleeping one, which happens only with
  // a sleep speed set, still follows the restitution). May be changed at any time.
  void set_exchange_velocities(bool on);
  // Granular gases (normal restitution < 1). Inelastic collisions can come infinitely often in a
  // finite time (inelastic collapse), and a disc settling on a floor under gravity bounces ever
  // lower and faster: event-driven dynamics would stop there. Three rules, on by default, deal
  // with it; they only ever take energy away or switch dissipation off, never add energy:
  //  - the TC model (Luding & McNamara 1998): a collision less than `duration` after the previous
  //    collision of either disc is elastic, as if the two were one longer contact (for two moving
  //    discs, their previous collisions with moving discs count; for a disc meeting a wall or a
  //    sleeping disc, its previous collision of any kind);
  //  - slow impacts (Poschel & Schwager, Computational Granular Dynamics, ch. 3): a collision
  //    whose contact points approach at less than `speed` along the normal is elastic, so that a
  //    disc resting on a floor under gravity g bounces at most speed^2 / (2 g) high;
  //  - sleeping (set_sleep_speed), which takes the place of slow impacts under gravity.
  // std::nullopt chooses automatically at the first advance (see contact_duration()); 0 switches
  // the rule off. Either may be changed at any time, like the restitution.
  void set_contact_duration(std::optional<double> duration);
  void set_elastic_impact_speed(std::optional<double> speed);
  // Discs at rest under gravity sleep, so that a settled bed costs no events (sleep.cpp): discs
  // slower than `speed` for 3 speed / |g|, connected by contacts and touching a wall or a sleeping
  // disc, stop together; a sleeping disc is immovable and has no events. A disc hitting one at a
  // normal speed of at least `speed` wakes it (and the sleeping discs resting on it); slower hits
  // bounce off it. std::nullopt: automatic, sqrt(2 |g| h) with h = kRestingBounce mean radii when
  // gravity acts and the normal restitution is below 1, else 0; 0 switches sleeping off and wakes
  // every sleeping disc. May be changed at any time. While discs can sleep, the automatic elastic
  // impact speed is 0.
  void set_sleep_speed(std::optional<double> speed);
  // Cell side (>= the largest diameter); 0 = automatic (the default).
  void set_cell_size(double size);
  // Whether each event starts loading the data of the event expected after it (the discs' states
  // around it) into the caches: faster for large systems, slower where everything fits in the
  // caches anyway. Automatic (the default) turns it on from about 87,000 discs; On and Off force
  // it (benchmarks, tests). The events and results are the same either way.
  enum class Prefetch { Automatic, On, Off };
  void set_prefetch_ahead(Prefetch mode);

  // ---- Discs ----
  // Adds one disc (see disc.hpp) and returns its index. Refused if it overlaps another disc or
  // a wall, or lies outside the container.
  int add_disc(const Disc& disc);
  // Adds many discs of one radius and mass (positions and velocities N by 2); returns the index
  // of the first. All or nothing: one bad disc refuses the whole call.
  int add_discs(const Points& positions, const Points& velocities, double radius, double mass = 1.0);
  // Adds n discs of one radius and mass at random places in the container (a table, boxes or
  // polygons, or a periodic box must be set), clear of the walls and of every disc: random
  // sequential addition, or, when that cannot place them all within its budget (dense systems,
  // area fraction above ~0.4), random sites of a triangular lattice, which melts within a few
  // collisions per disc. Velocities: Gaussian, with the total momentum of the new discs removed
  // (n >= 2) and rescaled so that their kinetic energy is exactly n kT (2D: kT per disc).
  // Returns the index of the first. All or nothing; refused (std::invalid_argument) if they
  // cannot fit.
  int add_random_discs(int n, double radius, double mass = 1.0, double kT = 1.0, std::uint64_t seed = 0);

  // ---- Running ----
  // Advances until max_events collisions have happened or max_duration time has passed,
  // whichever comes first (the clock then stops exactly at the duration).
  AdvanceResult advance(std::int64_t max_events, double max_duration = kNever);

  // ---- State ----
  int size() const;
  double time() const;
  State current_state() const;        // all discs advanced to time()
  const State& initial_state() const; // as at the first advance (or now, before it)
  const std::vector<WallShape>& walls() const;
  Totals totals() const;
  double kinetic_energy() const;      // sum m v^2/2 + I w^2/2
  double potential_energy() const;    // - sum m g.r
  double memory_bytes() const;        // memory held by the engine

  // ---- Properties (fixed once set; arrays of N, row i = disc i) ----
  Eigen::VectorXd radii() const;
  Eigen::VectorXd masses() const;
  Eigen::VectorXd inertias() const;   // moments of inertia (mass x length^2)
  Vec2 gravity() const;
  Restitution restitution() const;
  bool exchange_velocities() const;
  // The granular model's values in use (automatic ones are chosen at the first advance; 0 before
  // it). Automatic duration: 1e-4 mean radius / rms speed (of the discs at the first advance),
  // under gravity at least 0.01 sqrt(mean radius / |g|). Automatic elastic impact speed:
  // sqrt(2 |g| h) with h = kRestingBounce mean radii; 0 without gravity or while discs can sleep.
  double contact_duration() const;
  double elastic_impact_speed() const;
  double sleep_speed() const;
  std::vector<int> sleeping_discs() const;  // the discs asleep now, in increasing order
  static constexpr double kRestingBounce = 0.05;
  // Under gravity a disc meets fixed things (walls, sleeping discs) this fraction of its radius
  // closer than touching: a disc at rest on a floor, or sliding along it, would otherwise meet it
  // again at once after each bounce (approach speed 0), for ever at one instant. With the slack
  // it drops that far and bounces (the drop gives it the speed: no energy is gained). Ten times
  // below validate()'s tolerance.
  static constexpr double kFixedContactSlack = 1e-10;
  bool periodic() const;              // a periodic box (see period())
  Vec2 period() const;                // width and height of the periodic box; (0, 0) if none
  double table_radius() const;        // radius of the circular table; 0 if none
  int cell_count() const;             // cells of the grid (0 before the first advance)

  // ---- Event log (replayed by billiard::Replay, replay.hpp) ----
  void enable_event_log(bool on);
  void clear_event_log();
  const std::vector<EventRecord>& event_log() const;

  // ---- Checks ----
  // No problem (std::nullopt) if every disc is inside its container, no two discs overlap by
  // more than `tolerance` times the smaller radius, every disc lies in its cell and the queue is
  // in order and holds every disc's next event; otherwise a description of the first problem.
  std::optional<std::string> validate(double tolerance = 1e-9);
  // Runs validate() after every event and stops advance() at the first problem (slow, O(N) per
  // event; tests).
  void set_validate_every_event(bool on);
  // The same checks for the discs each collision changed only (inside the container, off the
  // walls, in their cells, no overlap with any disc near them, next event not in the past):
  // O(1) per event, for long runs. advance() stops at the first problem. (With
  // set_validate_every_event on as well, the full check runs.)
  void set_check_event_discs(bool on);
  // The problem that stopped the last advance() (or the last validate()'s), if any.
  std::optional<std::string> last_problem() const;

  struct Engine;  // internals, lib/src/engine/engine.hpp

 private:
  std::unique_ptr<Engine> engine_;
};

}  // namespace billiard
