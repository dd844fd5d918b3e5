// The simulation: discs in a container, advanced from collision to collision. A system is
// described first (a Container and its Settings, container.hpp and settings.hpp), then made into
// a simulation, given discs and run:
//
//   billiard::Settings settings;                         // defaults: no gravity, elastic
//   billiard::Simulation sim(billiard::box({0, 0}, {10, 10}), settings);
//   billiard::Disc d;  d.position = {1, 1};  d.velocity = {1, 0.5};
//   int id = sim.add_disc(d);
//   sim.advance(1000);                                   // 1000 collisions, or
//   sim.advance(kAllEvents, 2.5);                        // 2.5 time units
//   billiard::State now = sim.current_state();
//
// The container and the settings are checked when the simulation is made; discs are checked
// against the container as they are added, before the first advance(). Afterwards only the
// restitution, the exchange rule, the granular model, the event log and validation can change.
// Every call checks its input and throws std::invalid_argument naming the argument (and the
// disc index) and its value; a refused call leaves the simulation unchanged. Adding discs after
// the first advance() throws std::logic_error (the call is the mistake, whatever its
// arguments). Numbers must be finite and at most 1e50 in magnitude, and radii, masses and
// moments of inertia at least 1e-50: the engine squares and multiplies them, and beyond that the
// products overflow or underflow. Radii must also be at least 1e-6 of the coordinates of the
// container and the discs: positions are computed to about 1e-16 of them.
//
// Units: the user's. Time starts at 0. Energy is conserved to rounding for smooth elastic discs
// (about 1e-16 relative per collision, a random walk).
//
// Stopping a long run: advance() stops between two events when another thread (or a signal
// handler) calls request_stop(), or when the function given to advance() as `should_stop`
// returns true (it is asked every so many events). The result then says `stopped`; the state is
// the one after the last event handled, as valid as after any event, and advancing further
// gives exactly the future an unstopped run would have had. Python's binding uses the second
// way to let Ctrl-C (KeyboardInterrupt) stop a run, since the engine holds Python's lock.
//
// Saving and restarting: to_bytes() (or save(stream)) keeps everything that decides the future,
// and from_bytes() (or load(stream)) makes a simulation that continues exactly as the original
// would have, bit for bit; a damaged file, or one of another format version, is refused with a
// message saying so, never half-loaded. Containers have to_bytes() and from_bytes() too.
#pragma once

#include "billiard/engine/container.hpp"
#include "billiard/engine/disc.hpp"
#include "billiard/engine/settings.hpp"
#include "billiard/engine/plane.hpp"
#include "billiard/engine/wall.hpp"

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace billiard {

inline constexpr std::int64_t kAllEvents = std::numeric_limits<std::int64_t>::max();

// Periodic image counts, N by 2 (row i = disc i, columns x and y): how many times each disc has
// been wrapped across the periodic box, +1 for each crossing of its upper face (x = width or
// y = height) and -1 for each crossing of the lower. Position + images * period is the unwrapped
// position, continuous in time: displacements and mean squared displacements come from it. Under
// gravity the fall's whole periods count too (see Settings::gravity); counts saturate at
// +-9.2e18, a fall through that many periods.
using Images = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 2, Eigen::RowMajor>;

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
  // True if the run stopped early because request_stop() or advance()'s `should_stop` asked it
  // to (not because of the event or duration limit); the state is valid and advance may go on.
  bool stopped = false;
};

// Asked by advance() between two events (before the first, then every `check_interval`
// events), with the counts so far: true stops the run there. If it throws, the run stops there
// too (the state and the totals are those after the last event handled) and the exception
// propagates out of advance().
using StopCheck = std::function<bool(const AdvanceResult& so_far)>;

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
  // A simulation of discs in `container` under `settings`, with no discs yet.
  explicit Simulation(Container container, const Settings& settings = Settings());
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;
  Simulation(const Simulation&);
  Simulation& operator=(const Simulation&);

  // ---- Settings that may change at any time (see settings.hpp) ----
  void set_restitution(const Restitution& restitution);  // e.g. {0.9} or {0.9, 0.5}; see settings.hpp
  void set_exchange_velocities(bool on);
  void set_contact_duration(std::optional<double> duration);
  void set_elastic_impact_speed(std::optional<double> speed);
  // 0 switches sleeping off and wakes every sleeping disc.
  void set_sleep_speed(std::optional<double> speed);

  // ---- Discs ----
  // Adds one disc (see disc.hpp) and returns its index. Refused if it overlaps another disc or
  // a wall, or lies outside the container.
  int add_disc(const Disc& disc);
  // Adds many discs of one radius and mass (positions and velocities N by 2); returns the index
  // of the first. All or nothing: one bad disc refuses the whole call.
  int add_discs(const Coordinates& positions, const Velocities& velocities, double radius, double mass = 1.0);
  // Adds n discs of one radius and mass at random places in the container, clear of the walls
  // and of every disc: random sequential addition, or, when that cannot place them all within
  // its budget (dense systems, area fraction above ~0.4), random sites of a triangular lattice,
  // which melts within a few collisions per disc (fitted to a periodic box, it takes 10,000 discs
  // up to area fraction 0.9; the densest packing is 0.907). Velocities: Gaussian, with the total momentum of the new discs removed
  // (n >= 2) and rescaled so that their kinetic energy is exactly n kT (2D: kT per disc).
  // Returns the index of the first. All or nothing; refused (std::invalid_argument) if they
  // cannot fit.
  int add_random_discs(int n, double radius, double mass = 1.0, double kT = 1.0, std::uint64_t seed = 0);

  // ---- Running ----
  // Advances until max_events collisions have happened or max_duration time has passed,
  // whichever comes first (the clock then stops exactly at the duration).
  AdvanceResult advance(std::int64_t max_events, double max_duration = kNever);
  // The same, also stopping when `should_stop` (if not empty) returns true. It is asked before
  // the first event and then every `check_interval` (>= 1) events, counting cell crossings and
  // stale queue entries too (a run may cross cells for long between collisions); asking only
  // every so many events keeps the cost per event negligible (an event takes about 0.4
  // microseconds).
  AdvanceResult advance(std::int64_t max_events, double max_duration, const StopCheck& should_stop,
                        std::int64_t check_interval = kEventsBetweenStopPolls);
  // Asks advance() to stop between two events; callable from any thread and from a signal
  // handler (it only sets a lock-free atomic flag; the simulation must outlive the call).
  // advance() looks at the request when it would ask should_stop, or, without one, before the
  // first event and then every kEventsBetweenStopPolls events (well under a millisecond). The
  // request stays until an advance() honours it: the one running, or else the next one, before
  // its first event (`stopped` true, no event). So a request made just as a run starts or ends
  // is never lost, and a loop of advance() calls ends at its next call. A copy of the simulation
  // starts without a request.
  void request_stop();
  static constexpr std::int64_t kEventsBetweenStopPolls = 1000;

  // ---- State ----
  int size() const;
  double time() const;
  State current_state() const;        // all discs advanced to time()
  const State& initial_state() const; // as at the first advance (or now, before it)
  // Image counts at time(), row i for row i of current_state(): its positions + images() times
  // the period are the unwrapped positions. Counted from the first advance (discs are added
  // inside the box, at image 0); zeros without a periodic box. A copy keeps them.
  Images images() const;
  const Container& container() const;
  Totals totals() const;
  double kinetic_energy() const;      // sum m v^2/2 + I w^2/2
  double potential_energy() const;    // - sum m g.r
  double memory_bytes() const;        // memory held by the engine

  // ---- Properties (fixed once set; arrays of N, row i = disc i) ----
  Eigen::VectorXd radii() const;
  Eigen::VectorXd masses() const;
  Eigen::VectorXd inertias() const;   // moments of inertia (mass x length^2)
  Vector gravity() const;
  Restitution restitution() const;
  bool exchange_velocities() const;
  // The granular model's values in use (automatic ones are chosen at the first advance; 0 before
  // it). Automatic duration: 1e-4 mean radius / rms speed (of the discs at the first advance),
  // under gravity at least 0.01 sqrt(mean radius / |g|). Automatic elastic impact speed:
  // sqrt(2 |g| h) with h = kRestingBounce (settings.hpp) mean radii; 0 without gravity or while
  // discs can sleep.
  double contact_duration() const;
  double elastic_impact_speed() const;
  double sleep_speed() const;
  std::vector<int> sleeping_discs() const;  // the discs asleep now, in increasing order
  int cell_count() const;             // cells of the grid (0 before the first advance)

  // ---- Event log (replayed by billiard::Replay, replay.hpp) ----
  void set_log_events(bool on);  // record every event from now on (from the start, to replay)
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
  // The same checks for the discs each event changed only (the discs of a collision, the disc
  // crossing into a cell: inside the container, off the walls, in their cells, no overlap with
  // any disc near them, next event not in the past):
  // O(1) per event, for long runs. advance() stops at the first problem. (With
  // set_validate_every_event on as well, the full check runs.)
  void set_check_event_discs(bool on);
  // The problem that stopped the last advance() (or the last validate()'s), if any.
  std::optional<std::string> last_problem() const;

  // ---- Saving and loading (snapshot.cpp) ----
  // The whole simulation as bytes: the container, the settings and the granular model's chosen
  // values, the discs (spins, sleeping discs), the time, the totals, the image counts, the
  // event log and the engine's cells and event queue as they are, so that a loaded copy
  // continues exactly as the original would (the same events, bit for bit, on a machine of the
  // same kind). (No random state: add_random_discs takes its seed per call.) A stop request is
  // not kept. The layout: "billiard-simulation" and a zero byte, a byte-order mark (uint32
  // 0x01020304), the format version (uint32 kFileFormatVersion), the library version (uint32
  // length and text), the length of the data (uint64), the data, and a 64-bit FNV-1a checksum
  // of everything before it.
  std::string to_bytes() const;
  void save(std::ostream& out) const;  // writes to_bytes()
  // A simulation from to_bytes() (or a saved stream, read to its end). Anything else is refused
  // with a std::invalid_argument that names `source` and says why: not a billiard simulation
  // file, another format version (or byte order), truncated, or damaged (checksum mismatch).
  // Nothing is half-loaded: the result is made whole or not at all.
  static Simulation from_bytes(std::string_view bytes, const std::string& source = "the data");
  static Simulation load(std::istream& in, const std::string& source = "the stream");
  static constexpr std::uint32_t kFileFormatVersion = 3;

 private:
  // The disc arrays, the cells, the queue and the event loop, whose type belongs to lib/src
  // (engine.hpp): held here as an opaque pointer, so that this header names none of it.
  std::unique_ptr<void, void (*)(void*)> engine_;
};

}  // namespace billiard
