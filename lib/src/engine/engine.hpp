// Internals of Simulation: the disc arrays, the cells, the queue and the event loop. This header
// includes the public ones for the values they share (Settings, AdvanceResult, Totals); they name
// nothing of it.
// Not part of the public API (tests may include it on purpose).
#pragma once

#include "collide.hpp"
#include "billiard/engine/disc.hpp"
#include "billiard/engine/settings.hpp"
#include "billiard/engine/simulation.hpp"
#include "billiard/engine/wall.hpp"
#include "billiard/engine/container.hpp"
#include "container_geometry.hpp"
#include "event_queue.hpp"
#include "sectors.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace billiard {

// The face of its cell a disc leaves through. The cell steps come by arithmetic: a face is random
// in a gas, and a branch or switch on it would be mispredicted most of the time.
enum class Face : int { PlusX, MinusX, PlusY, MinusY };
inline int face_code(Face f) { return static_cast<int>(f); }
inline int axis_of(Face f) { return face_code(f) >> 1; }             // 0: x, 1: y
inline int direction_of(Face f) { return 1 - 2 * (face_code(f) & 1); }  // +1 or -1
inline int step_x(Face f) { return (f == Face::PlusX) - (f == Face::MinusX); }
inline int step_y(Face f) { return (f == Face::PlusY) - (f == Face::MinusY); }

// What a queued event will read, kept as its queue entry's tag so that the loop can prefetch it a
// few events ahead: for a crossing, the cell it enters and the face; for a contact, the disc's own
// cell. Packed as 8 cell + code (code 0..3 a face, 4 a contact); kNoHint when the grid has too many
// cells for that code.
struct EventHint {
  static constexpr int kNoHint = -1;
  static constexpr int kContact = 4;
  static int contact(int cell) { return 8 * cell + kContact; }
  static int crossing(int entered, Face face) { return 8 * entered + face_code(face); }
  static int cell(int tag) { return tag >> 3; }
  static bool is_contact(int tag) { return (tag & 7) == kContact; }
  static Face face(int tag) { return static_cast<Face>(tag & 7); }
};

// The hot state of one disc: everything the event loop reads for a pair test, a crossing or a
// smooth elastic collision. 64 bytes, one cache line (checked by a static_assert in engine.cpp).
// The radius lives here because every pair test needs it, the inverse mass because every
// collision does (then a collision of smooth discs reads no cold state, two cache misses fewer
// at large N); inertia and spin are only needed by rough discs.
struct HotDisc {
  Vector position;        // 16: centre at `time` (lazy: not advanced until an event touches the disc)
  Vector velocity;        // 16: velocity at `time`
  double time;            //  8: time of the last update
  double radius;          //  8
  double inverse_mass;    //  8: 0 while the disc sleeps (an immovable body, see sleep.cpp)
  int counter;            //  4: collisions so far; events remember it to detect staleness
  std::uint16_t cx;       //  2: column and row of the cell holding the centre (its index is
  std::uint16_t cy;       //  2: cx + nx cy; grids have at most 65535 cells per side)
};

// Cold state: 64 bytes, touched only at wall, rough and inelastic collisions, by sleeping and by
// the state accessors.
struct ColdDisc {
  double mass;
  double inertia;
  double inverse_inertia;
  double spin;
  // Times of the disc's previous collision, and of its previous collision with another moving
  // disc (-infinity: none), for the TC model (see restitution_of).
  double last_collision;
  double last_disc_collision;
  double slow_since;      // slower than the sleep speed ever since (kNever: not now)
  double next_sleep_try;  // no attempt to put it to sleep before then (see try_to_sleep)
};

// What a disc expects next: its earliest contact (disc or wall) as found when predicted, and the
// time it leaves its cell. The queue's key for the disc is the smaller of the two. Keeping the
// contact separate lets a cell crossing re-check only the newly adjacent cells. 32 bytes.
struct Scheduled {
  double contact_time;   // absolute time, kNever if none
  double crossing_time;  // absolute time
  int partner;           // the disc of the contact, or kNoDisc (a wall, or no contact)
  int partner_counter;   // the partner's collision counter at prediction
  int wall;              // the wall of the contact when partner is kNoDisc (else not read)
  Face crossing;         // the face of the crossing
};

struct Engine;

// The queue's view of the keys: a disc's key is the earlier of its contact and its crossing.
// prefetch(): the queue is about to hand out this disc's event (a few events from now).
struct ScheduledKeys {
  const Engine* engine = nullptr;
  const Scheduled* scheduled = nullptr;
  double key(int i) const { return std::min(scheduled[i].contact_time, scheduled[i].crossing_time); }
  inline void prefetch(int i, int tag) const;
};

// Spatial hash used while discs are being added (before the grid exists) to refuse overlaps in
// O(1) per disc.
struct SetupHash {
  double cell = 0.0;
  std::unordered_map<std::int64_t, std::vector<int>> cells;
};

// Simulation::request_stop's flag, set by any thread or a signal handler and read by the event
// loop between events. Lock-free, so setting it is safe in a signal handler. A copy of the
// engine starts without a request: that was meant for the original's run.
struct StopRequest {
  static_assert(std::atomic<bool>::is_always_lock_free);
  std::atomic<bool> requested{false};
  StopRequest() = default;
  StopRequest(const StopRequest&) {}
  StopRequest& operator=(const StopRequest&) { return *this; }
};

// The data and the event loop of a Simulation, which holds it behind an opaque pointer.
struct Engine {
  Engine(Container container, const Settings& settings);

  // ---- setup ----
  Container container;
  // The gravity the discs move under: Settings::gravity, except in a periodic box. There it
  // accelerates every disc alike and changes nothing between them, so the engine moves the discs
  // in the freely falling frame, without gravity (`fall` holds Settings::gravity), and adds the
  // fall, g t^2 / 2 and g t, to what it reports (lab_frame): a gas that falls for ever keeps the
  // precision of its relative motion (lib/DESIGN.md, "Discs are never lost").
  Vector gravity = Vector::Zero();
  bool has_gravity = false;
  double gravity_norm = 0.0;
  Vector fall = Vector::Zero();
  Restitution restitution;
  // Disc-disc collisions take the fast smooth elastic path (restitution 1, -1, no exchange).
  bool smooth_elastic = true;
  // Settings::exchange_velocities; walls reflect like mirrors when either is set.
  bool exchange_velocities = false;
  bool mirror_walls = true;
  // The granular model (see Settings::contact_duration): as set (nullopt: automatic), and
  // the values in use, chosen at the first advance.
  std::optional<double> contact_duration_setting;
  std::optional<double> elastic_impact_speed_setting;
  std::optional<double> sleep_speed_setting;
  double contact_duration = 0.0;
  double elastic_impact_speed = 0.0;
  double resting_speed = 0.0;  // sqrt(2 |g| kRestingBounce mean radii): the automatic speeds
  double sleep_speed = 0.0;    // 0: discs never sleep
  double cell_size = 0.0;  // 0: automatic

  // ---- discs ----
  BigVector<HotDisc> hot;         // huge pages when large: see memory.hpp
  BigVector<ColdDisc> cold;
  BigVector<Scheduled> scheduled;
  // Periodic image counts, from the first advance on (empty before): how often each disc was
  // wrapped across the box along x and y, +1 at the upper face, -1 at the lower. Kept out of
  // HotDisc: written only at a wrap, rare next to collisions, and read only by images_now().
  std::vector<std::array<std::int64_t, 2>> image_counts;
  double max_radius = 0.0;
  double min_radius = kNever;
  SetupHash setup_hash;

  // ---- the clock (see rebase) ----
  // Engine times count from `epoch`, the simulation's time at engine time 0: Simulation::time()
  // is epoch + now.
  double epoch = 0.0;
  // Every moving disc's speed at engine time t >= 0 is at most speed_bound + |g| t (raised at
  // collisions, measured again at each rebase).
  double speed_bound = 0.0;
  // The engine time from which the clock's rounding could misplace a disc by more than
  // kClockBudget of the smallest radius: rebase() then moves the zero to now.
  double rebase_at = kNever;
  // Without gravity, a moving disc slower than this (squared) makes the squares in the times of
  // impact underflow; set at the first advance from the smallest radius (see bound_speed).
  double slowest_squared = 0.0;
  bool too_slow = false;  // a disc moves slower than that: advance() stops, stuck
  // The running advance()'s start and end, in engine time (a rebase moves them).
  double run_start = 0.0;
  double run_end = kNever;

  // ---- run ----
  bool prepared = false;
  // Before each event, request the lines of the event expected after it (see prepare).
  Prefetch prefetch_mode = Prefetch::Automatic;
  bool prefetch_ahead = false;
  double now = 0.0;
  // The time of the first event of the latest instant and how many events came in it (see
  // advance), counted across advance() calls (so that a loop of short calls stops stuck where one
  // long call would).
  double instant = 0.0;
  std::int64_t events_at_instant = 0;
  Grid grid;
  CalendarQueue<ScheduledKeys> queue;
  std::vector<int> neighbours;  // scratch: the discs of two 3 x 3 blocks of cells
  Totals totals;
  State initial;
  bool logging = false;
  std::vector<EventRecord> log;
  int sleeping = 0;                // discs asleep now
  std::vector<int> island, woken;          // scratch of try_to_sleep and wake
  std::vector<unsigned char> in_island;    // scratch of try_to_sleep: 1 for its members
  bool validate_every_event = false;
  bool check_event_discs = false;
  std::string problem;
  StopRequest stop;

  // Setup helpers (simulation.cpp).
  void check_disc(const Disc& disc, int index) const;
  void add_checked_disc(const Disc& disc);
  void remove_discs_from(int first);  // undoes the adding of discs first, first + 1, ...
  void rebuild_setup_hash(double cell);
  bool overlaps_existing(const Vector& position, double radius, int& other) const;

  // Event loop (engine.cpp).
  void prepare();
  AdvanceResult advance(std::int64_t max_events, double max_duration, const StopCheck& should_stop,
                        std::int64_t check_interval);
  // The steps of advance.
  bool stuck_at_instant(double time, AdvanceResult& result);
  void prefetch_upcoming(int changing);
  void handle_disc_collision(int i, int j, AdvanceResult& result);
  void handle_wall_collision(int i, int wall, AdvanceResult& result);
  void rebase();
  void plan_rebase();
  void bound_speed(const HotDisc& d);
  bool checks_pass(int i, int j);
  void advance_disc(HotDisc& d, double t) const;
  void predict_full(int i);
  void collide_and_predict(int i, int j);
  void predict_gathered(int i, const int* list, int m);
  int gather(int i, int* list) const;
  int* scratch(int which);
  void cross(int i);
  void collide_pair(int i, int j);
  void collide_wall(int i, int wall);
  Restitution restitution_of(double approach_speed, double last_i, double last_j) const;
  // Under gravity, the distance from a disc's centre at which it meets fixed things (see
  // kFixedContactSlack).
  double fixed_reach(double radius) const { return has_gravity ? radius * (1 - kFixedContactSlack) : radius; }
  // Sleeping discs (sleep.cpp).
  static bool asleep(const HotDisc& d) { return d.inverse_mass == 0; }
  double sleep_time() const;
  double island_gap(double radius) const;
  void note_speed(int i, double speed_before);
  void try_to_sleep(int i);
  bool hit_wakes(int i, int j) const;
  void wake(int j);
  void wake_all();
  void predict_around(const std::vector<int>& discs);
  template <typename Visit>
  void for_each_near(int i, Visit visit) const;
  void choose_granular_model();
  void choose_speeds();
  void choose_rules();
  double wall_time(const WallShape& wall, const Vector& r, const Vector& v, double radius) const;
  void scan_cell(int i, int cx, int cy, const Vector& r, const Vector& v, Scheduled& s) const;
  void scan_listed(int i, const int* list, int m, const Vector& r, const Vector& v, Scheduled& s) const;
  void scan_walls(int cell, const Vector& r, const Vector& v, double radius, Scheduled& s) const;
  void set_crossing(int i);
  int event_tag(int i) const;
  void schedule(int i);
  void prefetch_block(int c) const;
  void prefetch_event(int i, int tag) const;
  void prefetch_neighbours(int tag) const;
  void link(int i, int cx, int cy);
  int cell_of_disc(const HotDisc& d) const { return d.cx + grid.nx * d.cy; }
  void unlink(int i);
  State state_now() const;
  Images images_now() const;  // consistent with state_now()'s wrapped positions
  // A disc as the user sees it at engine time `t`: in the lab frame (the fall added in a periodic
  // box under gravity), wrapped into the box; `images`, if given, gets the wraps the fall adds.
  struct LabDisc {
    Vector position, velocity;
  };
  LabDisc lab_frame(const HotDisc& d, double t, std::array<std::int64_t, 2>* images = nullptr) const;
  std::string check(double tolerance = 1e-9) const;
  std::string disc_problem(int i, double tolerance, const Vector* positions) const;
  void record(EventKind kind, int i, int other, int wall);
};

// The message for a disc overlapping a wall, the same at set-up and in validation
// (container.cpp).
std::string wall_overlap_message(const std::string& who, const Vector& p, int wall, double clearance, double radius);

inline void ScheduledKeys::prefetch(int i, int tag) const { engine->prefetch_event(i, tag); }

// Calls visit(j, shift) for every disc j in the 3 x 3 cells around disc i's cell (i included),
// where j's position plus `shift` is its periodic image nearest to those cells.
template <typename Visit>
void Engine::for_each_near(int i, Visit visit) const {
  const HotDisc& d = hot[i];
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      int x = d.cx + dx, y = d.cy + dy;
      Vector shift = Vector::Zero();
      if (x < 0 || x >= grid.nx || y < 0 || y >= grid.ny) {
        if (!grid.periodic) continue;
        if (x < 0) { x += grid.nx; shift.x() = -container.period().x(); }
        if (x >= grid.nx) { x -= grid.nx; shift.x() = container.period().x(); }
        if (y < 0) { y += grid.ny; shift.y() = -container.period().y(); }
        if (y >= grid.ny) { y -= grid.ny; shift.y() = container.period().y(); }
      }
      const int cell = x + grid.nx * y;
      const int* items = cell_discs(grid, cell);
      for (int k = 0, count = cell_disc_count(grid, cell); k < count; ++k) visit(items[k], shift);
    }
  }
}

}  // namespace billiard
