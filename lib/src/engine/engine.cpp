// The event loop (Lubachevsky 1991; Rapaport, The Art of Molecular Dynamics Simulation, ch. 14;
// the layout follows Smallenburg's compact EDMD codes).
//
// Each disc has exactly one entry in the queue: the earlier of its predicted contact and its
// cell crossing. Popping disc i:
//   - crossing: move i to its new cell and look only at the newly adjacent row of cells (and the
//     walls of the new cell); the contact found before stays valid unless its partner collided.
//   - contact with disc j whose counter changed since the prediction: stale, re-predict i only.
//   - otherwise: advance i (and j) to now, apply the impulse, bump the counters, re-predict.
// Every real collision is then the earliest event of at least one of its discs: whichever of the
// two was predicted last saw the other. Positions are lazy: a disc is stored at the time of its
// last update and moved only when an event touches it.
#include "engine.hpp"

#include "time_of_impact.hpp"
#include "wall_geometry.hpp"
#include "billiard/describe.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace billiard {

static_assert(sizeof(HotDisc) == 64, "HotDisc should fill exactly one cache line");
// Events less than this fraction of the time apart count as one instant (see advance).
constexpr double kInstant = 1e-10;
// Automatic cell side: kCellsPerDisc / sqrt(number density), but never below one diameter.
constexpr double kCellsPerDisc = 0.8;

static_assert(sizeof(Scheduled) == 32, "Scheduled should stay 32 bytes");
// The clock (see rebase): how far its rounding may misplace a disc, as a fraction of the smallest
// radius (validate() allows 1e-9), and that rounding, relative to the time.
constexpr double kClockBudget = 1e-11;
constexpr double kClockRounding = 0x1p-53;
// Speed times the smallest radius below which the squares in the times of impact would underflow
// (doubles reach down to 2e-308; their squares and products with lengths need room).
constexpr double kSlowestReach = 1e-140;

void Engine::advance_disc(HotDisc& d, double t) const {
  const double dt = t - d.time;
  if (has_gravity && !asleep(d)) {  // (a sleeping disc stays put)
    d.position += dt * (d.velocity + (0.5 * dt) * gravity);
    d.velocity += dt * gravity;
  } else {
    d.position += dt * d.velocity;
  }
  d.time = t;
}

void Engine::link(int i, int cx, int cy) {
  hot[i].cx = static_cast<std::uint16_t>(cx);
  hot[i].cy = static_cast<std::uint16_t>(cy);
  insert_disc(grid, cx + grid.nx * cy, i);
}

void Engine::unlink(int i) { remove_disc(grid, cell_of_disc(hot[i]), i); }

void Engine::prepare() {
  const int n = static_cast<int>(hot.size());
  // Region covered by the cells: every place a centre can reach.
  Vector lower, upper;
  bounds(container, lower, upper);
  const Vector extent = upper - lower;
  // Cell size. At least one largest diameter, so that contacts are between neighbouring cells.
  // Automatic choice: about one disc per cell on average (side 1/sqrt(number density)), which
  // at low density makes cells larger than a diameter and crossings rarer; measured with
  // billiard_bench (see lib/DESIGN.md). Never fewer than 3 cells per periodic side
  // (a neighbour must not be seen twice); add_disc checks that the period allows it.
  const double diameter = std::max(2 * max_radius, 1e-300);
  double side = diameter;
  if (cell_size > 0) {
    side = std::max(cell_size, diameter);
  } else if (n > 0) {
    const double density = n / (extent.x() * extent.y());
    side = std::max(diameter, kCellsPerDisc / std::sqrt(density));
  }
  // Memory stays linear in N: at most about 4 cells per disc (plus a few for tiny systems).
  side = std::max(side, std::sqrt(extent.x() * extent.y() / (4.0 * n + 64)));
  if (container.periodic()) side = std::min(side, std::min(extent.x(), extent.y()) / 3);
  grid = make_grid(lower, extent, side, container.periodic());
  if (n > 0) set_capacity(grid, capacity_for(grid, min_radius));

  assign_walls(grid, container.walls(), max_radius * (1 + 1e-6) + 1e-12 * extent.norm());

  now = 0.0;
  image_counts.assign(static_cast<std::size_t>(n), {0, 0});
  for (int i = 0; i < n; ++i) {
    HotDisc& d = hot[i];
    d.position = wrap(container, d.position);  // (a no-op: discs are added inside the box)
    const int cell = cell_of(grid, d.position);
    link(i, cell % grid.nx, cell / grid.nx);
  }
  // Requesting the next event's lines a whole event ahead is pure work where everything is in the
  // caches and pays once the arrays outgrow them (lib/DESIGN.md): on from 8 MB of states and
  // schedules, about 87,000 discs, where the whole engine (~390 bytes per disc) outgrows a
  // typical last-level cache of a few tens of MB.
  constexpr double kCachedBytes = 8.0 * (1 << 20);
  prefetch_ahead = prefetch_mode == Prefetch::On ||
                   (prefetch_mode == Prefetch::Automatic &&
                    static_cast<double>(n) * (sizeof(HotDisc) + sizeof(Scheduled)) > kCachedBytes);
  initial = state_now();
  speed_bound = 0.0;
  slowest_squared = has_gravity || hot.empty() ? 0.0 : std::max(kSlowestReach * kSlowestReach / (min_radius * min_radius), 1e-280);
  for (const HotDisc& d : hot) bound_speed(d);
  plan_rebase();
  choose_granular_model();
  for (int i = 0; i < n; ++i) predict_full(i);  // (not scheduled yet: prepared is false)
  std::vector<int> tags(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) tags[i] = event_tag(i);
  queue.set_keys(ScheduledKeys{this, scheduled.data()});  // (no disc can be added from now on)
  queue.assign(n, tags);
  prepared = true;
  setup_hash.cells.clear();  // no more discs can be added: free the setup hash
}

double Engine::wall_time(const WallShape& wall, const Vector& r, const Vector& v, double radius) const {
  switch (wall.kind) {
    case WallKind::Segment:
      return disc_segment_time(r, v, gravity, wall.a, wall.b, fixed_reach(radius));
    case WallKind::Point:
      return disc_point_time(r, v, gravity, wall.a, fixed_reach(radius));
    case WallKind::Circle:
      return disc_in_circle_time(r - wall.a, v, gravity, wall.radius - fixed_reach(radius));
    case WallKind::Arc:
      return disc_arc_time(r - wall.a, v, gravity, wall.radius, wall.start_angle, wall.sweep, fixed_reach(radius));
  }
  return kNever;
}

namespace {

// One pair test: disc i (at r, v, radius, time t0) against disc j, whose position is shifted by
// `shift` (a periodic image); keeps the contact in `s` if it is the earliest so far. Gravity is a
// template parameter so that the common case pays nothing for it. (A branch-free variant,
// computing the root for every pair and masking it, was measured no faster with billiard_bench
// at N = 10^4: the early rejections below save the square root and the division for most pairs.)
// kSleepers: some discs may be asleep: fixed while disc i falls, so that i meets one as a point
// at the contact distance (less the fixed contact slack, see fixed_reach).
template <bool kGravity, bool kSleepers>
inline void test_pair(const BigVector<HotDisc>& hot, const Vector& gravity, int i, int j, const Vector& shift,
                      const Vector& r, const Vector& v, double radius, double t0, Scheduled& s) {
  const HotDisc& o = hot[j];
  if (kSleepers && Engine::asleep(o)) {
    const double reach = radius * (1 - kFixedContactSlack) + o.radius;
    const double t = t0 + disc_point_time(r, v, gravity, o.position + shift, reach);
    if (t < s.contact_time) {
      s.contact_time = t;
      s.partner = j;
      s.partner_counter = o.counter;
    }
    return;
  }
  const double dt = t0 - o.time;
  Vector rj = o.position + dt * o.velocity + shift;
  Vector vj = o.velocity;
  if (kGravity) {
    rj += (0.5 * dt * dt) * gravity;
    vj += dt * gravity;
  }
  const Vector dr = r - rj;
  const Vector dv = v - vj;
  const double b = dr.dot(dv);
  if (b >= 0 || j == i) return;  // flying apart (or grazing), or i itself
  const double contact = radius + o.radius;
  const double c2 = dr.squaredNorm() - contact * contact;
  // Cheap rejection before the square root: the root c / (-b + sqrt(..)) is at least
  // c / (-2b), so a pair that cannot beat the best event so far is skipped (written as a
  // product, c >= (best - t0) (-2b), to avoid a division).
  if (c2 > 0 && c2 >= (s.contact_time - t0) * (-2 * b)) return;
  if (moving_along(b, dr.squaredNorm(), dv.squaredNorm())) return;  // grazing, up to rounding
  const double discriminant = b * b - dv.squaredNorm() * c2;
  if (discriminant < 0) return;  // they miss
  // Earlier root of dv.dv t^2 + 2 b t + c = 0, stable form; c < 0 (rounding overlap while
  // approaching) gives a negative root: collide now.
  const double t = t0 + std::max(c2 / (std::sqrt(discriminant) - b), 0.0);
  if (t < s.contact_time) {
    s.contact_time = t;
    s.partner = j;
    s.partner_counter = o.counter;
  }
}

// Pair tests of disc i against the discs of cell c, seen through the image shift `shift`.
template <bool kGravity, bool kSleepers>
inline void scan_discs(const BigVector<HotDisc>& hot, const Grid& grid, const Vector& gravity, int i, int c,
                       const Vector& shift, const Vector& r, const Vector& v, double radius, double t0, Scheduled& s) {
  const int* items = cell_discs(grid, c);
  const int count = cell_disc_count(grid, c);
  for (int k = 0; k < count; ++k) test_pair<kGravity, kSleepers>(hot, gravity, i, items[k], shift, r, v, radius, t0, s);
}

// The same pair tests against a list of discs (no periodic shift).
template <bool kGravity, bool kSleepers>
inline void scan_list(const BigVector<HotDisc>& hot, const Vector& gravity, int i, const int* list, int count,
                      const Vector& r, const Vector& v, double radius, double t0, Scheduled& s) {
  const Vector none = Vector::Zero();
  for (int k = 0; k < count; ++k) test_pair<kGravity, kSleepers>(hot, gravity, i, list[k], none, r, v, radius, t0, s);
}

}  // namespace

// Pair tests of disc i (at r, v, time now) against the discs of cell (cx, cy), which may lie
// outside the grid: skipped, or wrapped with the image shift when periodic.
void Engine::scan_cell(int i, int cx, int cy, const Vector& r, const Vector& v, Scheduled& s) const {
  Vector shift = Vector::Zero();
  if (cx < 0 || cx >= grid.nx) {
    if (!grid.periodic) return;
    shift.x() = cx < 0 ? -container.period().x() : container.period().x();
    cx = cx < 0 ? cx + grid.nx : cx - grid.nx;
  }
  if (cy < 0 || cy >= grid.ny) {
    if (!grid.periodic) return;
    shift.y() = cy < 0 ? -container.period().y() : container.period().y();
    cy = cy < 0 ? cy + grid.ny : cy - grid.ny;
  }
  const int c = cx + grid.nx * cy;
  if (sleeping > 0) {
    scan_discs<true, true>(hot, grid, gravity, i, c, shift, r, v, hot[i].radius, now, s);
  } else if (has_gravity) {
    scan_discs<true, false>(hot, grid, gravity, i, c, shift, r, v, hot[i].radius, now, s);
  } else {
    scan_discs<false, false>(hot, grid, gravity, i, c, shift, r, v, hot[i].radius, now, s);
  }
}

// Pair tests of disc i (at r, v, time now) against a gathered list of discs (no image shifts).
void Engine::scan_listed(int i, const int* list, int m, const Vector& r, const Vector& v, Scheduled& s) const {
  if (sleeping > 0) {
    scan_list<true, true>(hot, gravity, i, list, m, r, v, hot[i].radius, now, s);
  } else if (has_gravity) {
    scan_list<true, false>(hot, gravity, i, list, m, r, v, hot[i].radius, now, s);
  } else {
    scan_list<false, false>(hot, gravity, i, list, m, r, v, hot[i].radius, now, s);
  }
}

void Engine::scan_walls(int cell, const Vector& r, const Vector& v, double radius, Scheduled& s) const {
  if (!cell_has_walls(grid, cell)) return;  // (most cells: no read of wall_ranges)
  for (int k = cell_walls_begin(grid, cell), end = cell_walls_end(grid, cell); k < end; ++k) {
    const int w = grid.wall_items[k];
    const double t = now + wall_time(container.walls()[w], r, v, radius);
    if (t < s.contact_time) {
      s.contact_time = t;
      s.partner = kNoDisc;
      s.wall = w;
    }
  }
}

void Engine::set_crossing(int i) {
  const HotDisc& d = hot[i];
  // Cell faces (the outer faces of a non-periodic grid at infinity, see cell_bounds).
  Vector lo(grid.lower.x() + d.cx * grid.cell.x(), grid.lower.y() + d.cy * grid.cell.y());
  Vector hi = lo + grid.cell;
  if (d.cx == grid.nx - 1) hi.x() = grid.periodic ? grid.lower.x() + grid.extent.x() : kNever;
  if (d.cy == grid.ny - 1) hi.y() = grid.periodic ? grid.lower.y() + grid.extent.y() : kNever;
  if (!grid.periodic) {
    if (d.cx == 0) lo.x() = -kNever;
    if (d.cy == 0) lo.y() = -kNever;
  }
  Scheduled& s = scheduled[i];
  if (!has_gravity) {
    // Straight line, the face ahead on each axis (direction code by arithmetic, no branches on
    // the random signs of the velocity).
    const double vx = d.velocity.x(), vy = d.velocity.y();
    const double tx = straight_face_time(d.position.x(), vx, lo.x(), hi.x());
    const double ty = straight_face_time(d.position.y(), vy, lo.y(), hi.y());
    const int back_x = !(vx > 0), back_y = !(vy > 0), y_first = !(tx <= ty);
    s.crossing_time = d.time + std::min(tx, ty);
    s.crossing = static_cast<Face>(back_x + y_first * (2 + back_y - back_x));  // (the order of Face)
    return;
  }
  const CellExit exit = cell_exit_time(d.position, d.velocity, gravity, lo, hi);
  s.crossing_time = d.time + exit.time;
  s.crossing = static_cast<Face>(2 * exit.axis + (exit.direction > 0 ? 0 : 1));
}

// The hint for disc i's next event (see EventHint).
int Engine::event_tag(int i) const {
  const HotDisc& d = hot[i];
  const Scheduled& s = scheduled[i];
  if (grid.nx * static_cast<std::int64_t>(grid.ny) > (std::int64_t{1} << 27)) return EventHint::kNoHint;
  if (s.crossing_time > s.contact_time) return EventHint::contact(cell_of_disc(d));
  const int cx = std::clamp(d.cx + step_x(s.crossing), 0, grid.nx - 1);
  const int cy = std::clamp(d.cy + step_y(s.crossing), 0, grid.ny - 1);
  return EventHint::crossing(cx + grid.nx * cy, s.crossing);
}

void Engine::schedule(int i) {
  const Scheduled& s = scheduled[i];
  queue.update(i, std::min(s.contact_time, s.crossing_time), event_tag(i));
}

// Prefetches the records of the 3 x 3 block of cells around cell c (clipped to the grid): three
// rows of three consecutive 16-byte records, one or two cache lines each. A hint only.
void Engine::prefetch_block(int c) const {
  const int last = grid.nx * grid.ny - 1;
  const int* base = grid.records.data();
  for (int dy = -1; dy <= 1; ++dy) {
    const int first = std::clamp(c + dy * grid.nx - 1, 0, last);
    const int end = std::clamp(c + dy * grid.nx + 1, 0, last);
    prefetch_line(base + 4 * static_cast<std::size_t>(first));
    prefetch_line(base + 4 * static_cast<std::size_t>(end) + 3);
  }
}

namespace {

// The cells a crossing into cell c through `face` touches: the cell left, the cell entered and the
// row of three cells that becomes adjacent (clamped to the grid: hints only).
struct CrossingCells {
  int left, entered, row[3];
};
CrossingCells crossing_cells(const Grid& grid, int c, Face face) {
  const int step = step_x(face) + step_y(face) * grid.nx;  // to the next cell through the face
  const int across = step_x(face) != 0 ? grid.nx : 1;      // along the row that becomes adjacent
  const int last = grid.nx * grid.ny - 1;
  const int centre = c + step;
  return {std::clamp(c - step, 0, last), c,
          {std::clamp(centre - across, 0, last), std::clamp(centre, 0, last), std::clamp(centre + across, 0, last)}};
}

}  // namespace

// Disc i's event will come up a few events from now (its bucket entered the queue's heap): start
// loading its schedule, its state and the cell records its event will use (`tag`, see event_tag):
// the 3 x 3 block for a contact, five records for a crossing.
void Engine::prefetch_event(int i, int tag) const {
  prefetch_line(&scheduled[i]);
  prefetch_line(&hot[i]);
  if (tag == EventHint::kNoHint) return;
  const int c = EventHint::cell(tag);
  if (EventHint::is_contact(tag)) {
    prefetch_block(c);
    return;
  }
  const CrossingCells cells = crossing_cells(grid, c, EventHint::face(tag));
  for (int cell : {cells.left, cells.entered, cells.row[0], cells.row[1], cells.row[2]}) {
    prefetch_line(&grid.records[static_cast<std::size_t>(cell) * 4]);
  }
}

// The states of the discs the event `tag` will test (their cell records prefetched by
// prefetch_event a few events ago): the 3 x 3 block around the cell of a contact, the new row of
// a crossing.
void Engine::prefetch_neighbours(int tag) const {
  if (tag == EventHint::kNoHint) return;
  const int c = EventHint::cell(tag);
  auto fetch = [&](int cell) {
    const int* items = cell_discs(grid, cell);
    for (int m = 0, count = cell_disc_count(grid, cell); m < count; ++m) prefetch_line(&hot[items[m]]);
  };
  if (!EventHint::is_contact(tag)) {
    const CrossingCells cells = crossing_cells(grid, c, EventHint::face(tag));
    for (int cell : cells.row) fetch(cell);
    return;
  }
  const int last = grid.nx * grid.ny - 1;
  for (int dy = -1; dy <= 1; ++dy) {
    const int row = c + dy * grid.nx;
    for (int cell = row - 1; cell <= row + 1; ++cell) fetch(std::clamp(cell, 0, last));
  }
}

// Discs of the 3 x 3 block around disc i's cell, written to `list`, when that cell is an
// interior cell (almost all: no wrapping or bounds checks needed); -1 otherwise. Their states
// are prefetched, so that the cache misses (the bottleneck from N ~ 10^5 on, when the discs no
// longer fit in the caches) overlap instead of waiting for one another.
int Engine::gather(int i, int* list) const {
  const HotDisc& d = hot[i];
  if (!(d.cx > 0 && d.cx < grid.nx - 1 && d.cy > 0 && d.cy < grid.ny - 1)) return -1;
  int m = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    const int row = cell_of_disc(d) + dy * grid.nx;
    for (int c = row - 1; c <= row + 1; ++c) m = append_cell_discs(grid, c, list, m);
  }
  for (int k = 0; k < m; ++k) prefetch_line(&hot[list[k]]);
  return m;
}

int* Engine::scratch(int which) {
  const std::size_t most = 9 * static_cast<std::size_t>(grid.capacity) + kInline;  // (see append_cell_discs)
  if (neighbours.size() < 2 * most) neighbours.resize(2 * most);  // the slots may have grown
  return neighbours.data() + which * most;
}

void Engine::predict_full(int i) {
  prefetch_block(cell_of_disc(hot[i]));
  int* list = scratch(0);
  predict_gathered(i, list, gather(i, list));
}

// A collision of discs i and j and their new predictions, ordered so that cache misses overlap
// with work: the records of j's cells are requested, i's neighbours gathered (and their states
// requested), then the impulse is computed while those loads are under way, then j's
// neighbours are gathered, and only then are the pairs tested. (Cell membership does not
// change at a collision, so gathering before the impulse is the same.)
void Engine::collide_and_predict(int i, int j) {
  prefetch_block(cell_of_disc(hot[j]));
  int* list_j = scratch(1);  // (both calls ask for the same size: the second never reallocates)
  int* list_i = scratch(0);
  const int m_i = gather(i, list_i);
  collide_pair(i, j);
  const int m_j = gather(j, list_j);
  predict_gathered(i, list_i, m_i);
  predict_gathered(j, list_j, m_j);
}

// Predicts disc i's next contact and crossing from scratch and reschedules it; `list` holds
// the m discs gathered around it, or m < 0 for a border cell (scanned cell by cell).
void Engine::predict_gathered(int i, const int* list, int m) {
  HotDisc& d = hot[i];
  advance_disc(d, now);
  Scheduled& s = scheduled[i];
  s.contact_time = kNever;
  s.partner = kNoDisc;
  s.wall = kNoWall;
  if (asleep(d)) {  // (no events until woken)
    s.crossing_time = kNever;
    if (prepared) schedule(i);
    return;
  }
  const Vector r = d.position;
  const Vector v = d.velocity;
  if (m >= 0) {
    scan_listed(i, list, m, r, v, s);
  } else {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) scan_cell(i, d.cx + dx, d.cy + dy, r, v, s);
    }
  }
  scan_walls(cell_of_disc(d), r, v, d.radius, s);
  set_crossing(i);
  if (prepared) schedule(i);
}

void Engine::cross(int i) {
  HotDisc& d = hot[i];
  Scheduled& s = scheduled[i];
  advance_disc(d, now);
  const Face face = s.crossing;
  const int axis = axis_of(face);
  int cx = d.cx + step_x(face);
  int cy = d.cy + step_y(face);
  if (cx < 0 || cx >= grid.nx || cy < 0 || cy >= grid.ny) {
    // Only a periodic grid has finite outer faces: wrap the disc to the other side.
    int& moved = axis == 0 ? cx : cy;
    const int count = axis == 0 ? grid.nx : grid.ny;
    moved = moved < 0 ? count - 1 : 0;
    d.position[axis] -= direction_of(face) * container.period()[axis];
    image_counts[static_cast<std::size_t>(i)][static_cast<std::size_t>(axis)] += direction_of(face);
  }
  assert(cx >= 0 && cx < grid.nx && cy >= 0 && cy < grid.ny);
  unlink(i);
  link(i, cx, cy);
  // The contact predicted before is still the best among the old neighbours unless its partner
  // has collided since; then predict from scratch.
  if (s.partner >= 0 && hot[s.partner].counter != s.partner_counter) {
    predict_full(i);
    return;
  }
  // Only the row of cells that just became adjacent is new.
  const Vector r = d.position;
  const Vector v = d.velocity;
  // Its centre cell and the step along it; inside the grid (almost always), its three records
  // are read directly, else cell by cell with the bounds checks and periodic images.
  const int rx = cx + step_x(face), ry = cy + step_y(face);
  const int along = axis == 0 ? grid.nx : 1;
  if (rx - axis >= 0 && rx + axis < grid.nx && ry - (1 - axis) >= 0 && ry + (1 - axis) < grid.ny) {
    int* list = scratch(0);
    const int c = rx + grid.nx * ry;
    int m = append_cell_discs(grid, c - along, list, 0);
    m = append_cell_discs(grid, c, list, m);
    m = append_cell_discs(grid, c + along, list, m);
    scan_listed(i, list, m, r, v, s);
  } else {
    for (int e = -1; e <= 1; ++e) scan_cell(i, rx + e * axis, ry + e * (1 - axis), r, v, s);
  }
  scan_walls(cell_of_disc(d), r, v, d.radius, s);
  set_crossing(i);
  schedule(i);
}

void Engine::collide_pair(int i, int j) {
  assert(i != j && i >= 0 && j >= 0);
  HotDisc& a = hot[i];
  HotDisc& b = hot[j];
  advance_disc(a, now);
  advance_disc(b, now);
  const Vector dr = minimum_image(container, b.position - a.position);  // from i to j
  const double speed_i = a.velocity.norm(), speed_j = b.velocity.norm();
  Vector q;
  if (smooth_elastic) {
    q = collide_smooth_elastic(dr, a.velocity, a.inverse_mass, b.velocity, b.inverse_mass);
  } else if (exchange_velocities && !asleep(b) && (a.velocity - b.velocity).dot(dr) > 0) {
    // The whole relative velocity is reversed (Settings::exchange_velocities); equal
    // masses swap their velocities exactly, so that no rounding enters.
    const Vector g = a.velocity - b.velocity;
    if (a.inverse_mass == b.inverse_mass) {
      std::swap(a.velocity, b.velocity);
    } else {
      const double sum = a.inverse_mass + b.inverse_mass;
      a.velocity -= (2 * a.inverse_mass / sum) * g;
      b.velocity += (2 * b.inverse_mass / sum) * g;
    }
    q = -(2 / (a.inverse_mass + b.inverse_mass)) * g;
  } else {
    ColdDisc& ca = cold[i];
    ColdDisc& cb = cold[j];
    const Vector sigma = dr.normalized();
    ContactBody bi{a.velocity, ca.spin, a.inverse_mass, ca.inverse_inertia, a.radius};
    ContactBody bj{b.velocity, cb.spin, b.inverse_mass, asleep(b) ? 0.0 : cb.inverse_inertia, b.radius};
    const double approach = (a.velocity - b.velocity).dot(sigma);
    // A sleeping disc is met like a wall (see restitution_of).
    const bool fixed = asleep(b);
    q = collide(sigma, bi, bj,
                fixed ? restitution_of(approach, ca.last_collision, -kNever)
                      : restitution_of(approach, ca.last_disc_collision, cb.last_disc_collision));
    a.velocity = bi.velocity;
    b.velocity = bj.velocity;
    ca.spin = bi.spin;
    cb.spin = bj.spin;
    ca.last_collision = now;
    if (!fixed) ca.last_disc_collision = cb.last_collision = cb.last_disc_collision = now;
  }
  totals.virial += -dr.dot(q);  // r_ij . dp_i with r_ij = r_i - r_j = -dr
  ++a.counter;
  ++b.counter;
  bound_speed(a);
  bound_speed(b);
  if (sleep_speed > 0) {
    note_speed(i, speed_i);
    if (!asleep(b)) note_speed(j, speed_j);
  }
}

void Engine::collide_wall(int i, int w) {
  HotDisc& d = hot[i];
  advance_disc(d, now);
  const WallShape& wall = container.walls()[w];
  // Contact normal from the disc centre towards the wall.
  const Vector normal = wall.kind == WallKind::Circle ? Vector(d.position - wall.a) : Vector(closest_point(wall, d.position) - d.position);
  // A disc found a rounding error into the wall is put back on it. Under gravity a disc resting
  // there could otherwise never get clear: each collision would find it inside again, moving in.
  if (has_gravity) {
    const double distance = normal.norm();
    const double reach = wall.kind == WallKind::Circle ? wall.radius - fixed_reach(d.radius) : fixed_reach(d.radius);
    if (wall.kind == WallKind::Circle && distance > reach) {
      d.position += ((reach - distance) / distance) * normal;  // (normal points outwards here)
    } else if (wall.kind != WallKind::Circle && distance < reach && distance > 0) {
      d.position += ((distance - reach) / distance) * normal;  // (normal points at the wall)
    }
  }
  ColdDisc& c = cold[i];
  const double speed_before = d.velocity.norm();
  Vector q;
  if (mirror_walls) {
    // Mirror reflection v' = v - 2 (v.n) n / (n.n), unnormalised n as in collide_smooth_elastic.
    const double vn = d.velocity.dot(normal);
    q = vn > 0 ? Vector((-2 * vn * c.mass / normal.squaredNorm()) * normal) : Vector::Zero();
    d.velocity += d.inverse_mass * q;
  } else {
    const Vector sigma = normal.normalized();
    ContactBody body{d.velocity, c.spin, d.inverse_mass, c.inverse_inertia, d.radius};
    ContactBody fixed{Vector::Zero(), 0.0, 0.0, 0.0, 0.0};
    q = collide(sigma, body, fixed, restitution_of(d.velocity.dot(sigma), c.last_collision, -kNever));
    d.velocity = body.velocity;
    c.spin = body.spin;
    c.last_collision = now;
  }
  totals.wall_momentum += q.norm();
  ++d.counter;
  bound_speed(d);
  if (sleep_speed > 0) note_speed(i, speed_before);
}

// The restitution of one collision, whose contact points approach at `approach_speed` along the
// normal: the one set, unless the granular model makes the collision elastic
// (Settings::contact_duration and elastic_impact_speed). Elastic means no dissipation
// at all, tangential included, so the model can only take dissipation away, never add energy.
// last_i, last_j: for two moving discs, the times of their previous collisions with moving discs;
// for a disc meeting something fixed (a wall, a sleeping disc), the time of its previous
// collision of any kind, and -infinity. So a disc resting on a floor, whose hops there are always
// recent, keeps that contact elastic without making elastic the hits of a disc bouncing on it.
Restitution Engine::restitution_of(double approach_speed, double last_i, double last_j) const {
  const bool recent = now - std::max(last_i, last_j) < contact_duration;
  if (!recent && !(approach_speed < elastic_impact_speed)) return restitution;
  const bool conserving = restitution.tangential == 1 || restitution.tangential == -1;
  return Restitution{1.0, conserving ? restitution.tangential : -1.0};
}

// The clock. An event at time t is placed only to within the rounding of t, a relative 2^-53, so
// a disc moving at speed v lands up to v t 2^-53 away from its true place: a long run (large t)
// or a huge speed (large v) makes that more than validate() allows (lib/DESIGN.md, "Discs are
// never lost"). So engine times count from an epoch, moved up to now whenever v t 2^-53 could
// reach kClockBudget of the smallest radius. Subtracting now from a stored time is exact when
// the time lies within a factor two of now (Sterbenz's lemma), as every pending event's does: the
// discs' trajectories do not change, only the clock's resolution gets finer. Between events, and
// in a collision before its discs are predicted again (a collision that creates a huge speed).
void Engine::rebase() {
  const double shift = now;
  epoch += shift;
  now = 0.0;
  instant -= shift;
  run_start -= shift;
  run_end -= shift;  // (kNever stays kNever)
  const double g = gravity_norm;
  double bound = 0.0;
  const int n = static_cast<int>(hot.size());
  std::vector<int> tags(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    HotDisc& d = hot[i];
    ColdDisc& c = cold[i];
    Scheduled& s = scheduled[i];
    d.time -= shift;
    c.last_collision -= shift;
    c.last_disc_collision -= shift;
    c.slow_since -= shift;
    c.next_sleep_try -= shift;
    s.contact_time -= shift;
    s.crossing_time -= shift;
    if (!asleep(d)) bound = std::max(bound, d.velocity.norm() - g * d.time);  // (d.time <= 0)
    tags[i] = event_tag(i);
  }
  speed_bound = bound;
  plan_rebase();
  queue.assign(n, tags);  // (its calendar is planned from the keys' times)
}

// The engine time t at which (speed_bound + |g| t) t kClockRounding reaches kClockBudget of the
// smallest radius.
void Engine::plan_rebase() {
  const double g = gravity_norm;
  if (hot.empty() || (speed_bound == 0 && g == 0)) {
    rebase_at = kNever;
    return;
  }
  // The positive root of g t^2 + speed_bound t - c, in the form that does not cancel.
  const double c = kClockBudget * min_radius / kClockRounding;
  rebase_at = 2 * c / (speed_bound + std::hypot(speed_bound, 2 * std::sqrt(g * c)));
}

// Disc d's velocity has just changed: raise the speed bound if d is faster than it, and move the
// clock's zero to now if its new speed needs a finer clock before d is predicted.
//
// Without gravity, a disc also must not move so slowly that the squares of its speed times a
// radius, in the times of impact, underflow (a gas cooling for ever by inelastic collisions gets
// there: speeds of 1e-162 after 1,600 collisions at restitution 0.5, and a disc then passed
// through an obstacle): advance() stops, stuck, before such a disc moves.
void Engine::bound_speed(const HotDisc& d) {
  const double speed_squared = d.velocity.squaredNorm();
  if (speed_squared < slowest_squared && speed_squared > 0) too_slow = true;
  const double reach = speed_bound + gravity_norm * now;
  if (speed_squared <= reach * reach) return;  // (the common case: no square root)
  speed_bound = d.velocity.norm() - gravity_norm * now;  // (so that the bound at now is its speed)
  plan_rebase();
  if (now > rebase_at) rebase();
}

void Engine::record(EventKind kind, int i, int other, int wall) {
  EventRecord e;
  e.time = epoch + now;
  e.kind = kind;
  e.disc = i;
  e.other = other;
  e.wall = wall;
  LabDisc lab = lab_frame(hot[i], now);
  e.position = lab.position;
  e.velocity = lab.velocity;
  e.spin = cold[i].spin;
  if (other >= 0) {
    lab = lab_frame(hot[other], now);
    e.other_position = lab.position;
    e.other_velocity = lab.velocity;
    e.other_spin = cold[other].spin;
  }
  log.push_back(e);
}

// Events at one instant are normal in small numbers (corners, three discs touching); more than
// stuck_limit means the dynamics cannot go on (resting contact under gravity, inelastic collapse).
// "One instant" is a relative 1e-10 of the time: a collapse can also crawl on by a rounding step
// per event. Checked before the event is popped, so that a stop leaves every disc's event queued.
bool Engine::stuck_at_instant(double time, AdvanceResult& result) {
  const std::int64_t stuck_limit = 1000 + 20 * static_cast<std::int64_t>(hot.size());
  if (time > instant + kInstant * std::abs(instant)) {
    events_at_instant = 0;
    instant = time;
    return false;
  }
  if (++events_at_instant <= stuck_limit) return false;
  result.stuck = true;
  result.stuck_reason = describe("stuck at time ", epoch + now, ": more than ", stuck_limit,
                                 " events at that instant (within ", kInstant, " of the time; discs resting on "
                                 "each other or on a wall under gravity, or an inelastic collapse); the state is valid");
  return true;
}

// The event after this one is most likely the heap's next current entry (unless this event
// reschedules a disc earlier): start loading its disc, its cells and its partner now, so that
// those cache misses overlap with the work on this event. (Its schedule was prefetched when its
// bucket moved into the heap.) `changing`: the partner of this event, whose entry for the same
// collision is not the next event. 87% of the guesses are right at N = 10^6, area fraction 0.5.
void Engine::prefetch_upcoming(int changing) {
  const auto* next = queue.upcoming(changing);
  if (next == nullptr) return;
  prefetch_neighbours(next->tag);
  const Scheduled& upcoming = scheduled[next->disc];
  if (upcoming.partner == kNoDisc) return;
  prefetch_line(&hot[upcoming.partner]);  // (a crossing also reads its counter)
  if (!smooth_elastic && upcoming.contact_time < upcoming.crossing_time) {
    prefetch_line(&cold[upcoming.partner]);
    prefetch_line(&cold[next->disc]);
  }
}

// A collision of discs i and j, now: wake j if the hit is hard enough, apply the impulse,
// predict both again, and let them fall asleep if they are slow.
void Engine::handle_disc_collision(int i, int j, AdvanceResult& result) {
  if (asleep(hot[j]) && hit_wakes(i, j)) wake(j);
  collide_and_predict(i, j);
  if (logging) record(EventKind::DiscDisc, i, j, kNoWall);
  ++result.disc_collisions;
  if (sleep_speed > 0) {
    try_to_sleep(i);
    try_to_sleep(j);
  }
}

void Engine::handle_wall_collision(int i, int wall, AdvanceResult& result) {
  collide_wall(i, wall);
  if (logging) record(EventKind::DiscWall, i, kNoDisc, wall);
  predict_full(i);
  ++result.wall_collisions;
  if (sleep_speed > 0) try_to_sleep(i);
}

// The checks switched on by set_validate_every_event or set_check_event_discs, after an event of
// disc i (and disc j, or kNoDisc); false when they found a problem (kept in `problem`).
bool Engine::checks_pass(int i, int j) {
  if (validate_every_event) {
    problem = check();
  } else {
    problem = disc_problem(i, 1e-9, nullptr);
    if (problem.empty() && j != kNoDisc) problem = disc_problem(j, 1e-9, nullptr);
  }
  return problem.empty();
}

AdvanceResult Engine::advance(std::int64_t max_events, double max_duration, const StopCheck& should_stop,
                              std::int64_t check_interval) {
  if (!prepared) prepare();
  AdvanceResult result;
  run_start = now;
  run_end = now + max_duration;  // (rebase() moves both)
  // The run's counts go into the totals however it ends, a should_stop that throws included.
  const auto account = [&] {
    result.elapsed = now - run_start;
    totals.disc_collisions += result.disc_collisions;
    totals.wall_collisions += result.wall_collisions;
    totals.cell_crossings += result.cell_crossings;
  };
  // Stop requests and should_stop are looked at before the first event and then every
  // poll_interval queue entries: one countdown per event (looking at the atomic flag after every
  // event measurably slowed the loop, by 0.7%).
  const std::int64_t poll_interval = check_interval;
  std::int64_t until_poll = 1;
  // Without a duration limit, a system where no collision can ever happen (discs moving in
  // parallel in a periodic box) would cross cells forever: stop after this many crossings in a
  // row, far more than any gas needs between two collisions.
  const std::int64_t crossing_limit = 1000000 + 1000 * static_cast<std::int64_t>(hot.size());
  std::int64_t crossings_in_a_row = 0;
  while (result.collisions < max_events && !hot.empty()) {
    if (too_slow) {
      result.stuck = true;
      result.stuck_reason = describe("stuck at time ", epoch + now, ": a disc moves slower than ", std::sqrt(slowest_squared),
                                     ", where the times of impact underflow (an inelastic gas cooled that far); the state "
                                     "is valid, but the run cannot go on");
      break;
    }
    if (now > rebase_at) rebase();
    // Stops happen here, between two events, where the state is as complete as after any run.
    if (--until_poll == 0) {
      until_poll = poll_interval;
      if (stop.requested.load(std::memory_order_relaxed)) {
        stop.requested.store(false, std::memory_order_relaxed);
        result.stopped = true;
        break;
      }
      if (should_stop) {
        bool stop_now = false;
        try {
          stop_now = should_stop(result);
        } catch (...) {
          account();
          throw;
        }
        if (stop_now) {
          result.stopped = true;
          break;
        }
      }
    }
    const auto top = queue.top();
    if (top.time > run_end || top.time == kNever) {
      if (run_end < kNever) now = run_end;
      break;
    }
    if (stuck_at_instant(top.time, result)) break;
    queue.pop();
    const int i = top.disc;
    const Scheduled& s = scheduled[i];
    const bool crossing = s.crossing_time <= s.contact_time;
    // The partner of a collision that is still current: its key changes with this event.
    const int changing = !crossing && s.partner != kNoDisc && hot[s.partner].counter == s.partner_counter ? s.partner : kNoDisc;
    if (prefetch_ahead) prefetch_upcoming(changing);
    now = top.time;
    if (crossing) {
      cross(i);
      ++result.cell_crossings;
      if ((validate_every_event | check_event_discs) && !checks_pass(i, kNoDisc)) break;
      if (++crossings_in_a_row > crossing_limit && run_end == kNever) {
        result.stuck = true;
        result.stuck_reason = describe("stuck at time ", epoch + now, ": ", crossing_limit,
                                       " cell crossings in a row and no collision (no collision may ever happen); "
                                       "give advance a duration");
        break;
      }
      continue;
    }
    crossings_in_a_row = 0;
    const int j = s.partner;  // (s becomes the next prediction once the event is handled)
    if (j != kNoDisc && changing != j) {  // j collided since the prediction: stale
      ++result.stale_events;
      predict_full(i);
      continue;
    }
    if (j != kNoDisc) {
      handle_disc_collision(i, j, result);
    } else {
      handle_wall_collision(i, s.wall, result);
    }
    ++result.collisions;
    if ((validate_every_event | check_event_discs) && !checks_pass(i, j)) break;
  }
  // No discs: no event ever comes, so the duration passes.
  if (hot.empty() && max_events > 0 && run_end < kNever) now = run_end;
  account();
  return result;
}

State Engine::state_now() const {
  const int n = static_cast<int>(hot.size());
  State state;
  state.time = epoch + now;
  state.positions.resize(n, 2);
  state.velocities.resize(n, 2);
  state.spins.resize(n);
  for (int i = 0; i < n; ++i) {
    HotDisc d = hot[i];
    advance_disc(d, now);
    const LabDisc lab = lab_frame(d, now);
    state.positions.row(i) = lab.position;
    state.velocities.row(i) = lab.velocity;
    state.spins[i] = cold[i].spin;
  }
  return state;
}

Engine::LabDisc Engine::lab_frame(const HotDisc& d, double t, std::array<std::int64_t, 2>* images) const {
  LabDisc lab{d.position, d.velocity};
  if (!container.periodic()) return lab;
  const double time = epoch + t;
  lab.velocity += time * fall;
  const Vector& period = container.period();
  for (int k = 0; k < 2; ++k) {
    // The fall g t^2 / 2 as whole periods and a rest within one: the wrapped position keeps its
    // precision however far the gas has fallen (the rest is the same for every disc).
    const double drop = fall[k] == 0 ? 0.0 : 0.5 * fall[k] * time * time;
    const double periods = std::floor(drop / period[k]);
    const double unwrapped = d.position[k] + (drop - periods * period[k]);
    // (Rounding may have left the disc just outside the box, at its cell's outer face: that wrap
    // counts too, as in wrap_into_period.)
    const double wraps = std::floor(unwrapped / period[k]);
    lab.position[k] = unwrapped - wraps * period[k];
    if (images) (*images)[k] = static_cast<std::int64_t>(std::clamp(periods + wraps, -9.2e18, 9.2e18));
  }
  return lab;
}

Images Engine::images_now() const {
  const int n = static_cast<int>(hot.size());
  Images out = Images::Zero(n, 2);
  if (!container.periodic()) return out;
  for (int i = 0; i < n; ++i) {
    HotDisc d = hot[i];
    advance_disc(d, now);
    std::array<std::int64_t, 2> wraps{};  // the wraps state_now() makes (and the fall's)
    lab_frame(d, now, &wraps);
    out(i, 0) = wraps[0];
    out(i, 1) = wraps[1];
    if (static_cast<std::size_t>(i) < image_counts.size()) {
      out(i, 0) += image_counts[static_cast<std::size_t>(i)][0];
      out(i, 1) += image_counts[static_cast<std::size_t>(i)][1];
    }
  }
  return out;
}

// The checks of validate() for disc i at the current time: inside its container, off every wall,
// in its cell, not overlapping a disc of the 3 x 3 cells around it, its next event not in the
// past (a message is made only when a check fails). `positions`: every disc's position now
// (validate() checks each pair once, from its lower index), or null: the positions needed are
// computed and every neighbour is checked (the check of the discs an event changed, O(1) per
// event).
std::string Engine::disc_problem(int i, double tolerance, const Vector* positions) const {
  const auto at = [&](int j) -> Vector {
    if (positions) return positions[j];
    HotDisc moved = hot[j];
    advance_disc(moved, now);
    return moved.position;
  };
  const Vector ri = at(i);
  const HotDisc& d = hot[i];
  const int cell_i = cell_of_disc(d);
  const double slack = tolerance * d.radius;
  // Inside the container and off every wall (those listed in its cell, when there are many).
  const std::string who = describe("disc ", i);
  const std::string where = outside(container, ri, d.radius, slack);
  if (!where.empty()) return who + " " + where;
  const bool few_walls = container.walls().size() <= 64;
  const int first_wall = cell_walls_begin(grid, cell_i);
  const auto on_wall = few_walls ? overlapped_wall(container, ri, d.radius, slack)
                                 : overlapped_wall(container, ri, d.radius, slack, grid.wall_items.data() + first_wall,
                                                             cell_walls_end(grid, cell_i) - first_wall);
  if (on_wall) return wall_overlap_message(who, ri, on_wall->wall, on_wall->clearance, d.radius);
  // In its cell (up to rounding).
  Vector lo, hi;
  cell_bounds(grid, cell_i, lo, hi);
  const double cell_slack = 1e-9 * grid.cell.maxCoeff();
  if ((ri.array() < lo.array() - cell_slack).any() || (ri.array() > hi.array() + cell_slack).any()) {
    return describe("disc ", i, " at (", ri.x(), ", ", ri.y(), ") is not in its cell ", cell_i);
  }
  // No overlap with the discs of the neighbouring cells.
  std::string overlap;
  for_each_near(i, [&](int j, const Vector& shift) {
    if (!overlap.empty() || (positions ? j <= i : j == i)) return;
    const double distance = (ri - at(j) - shift).norm();
    const double contact = d.radius + hot[j].radius;
    if (distance < contact - tolerance * std::min(d.radius, hot[j].radius)) {
      overlap = describe("discs ", i, " and ", j, " overlap: distance ", distance, " < ", contact, " at time ", epoch + now);
    }
  });
  if (!overlap.empty()) return overlap;
  if (asleep(d) && !(d.velocity == Vector::Zero() && cold[i].spin == 0)) {
    return describe("disc ", i, " is asleep but moves: velocity (", d.velocity.x(), ", ", d.velocity.y(), "), spin ", cold[i].spin);
  }
  // The next event lies in the future.
  const Scheduled& s = scheduled[i];
  const double next = std::min(s.contact_time, s.crossing_time);
  if (next < now) return describe("disc ", i, ": next event at ", next, " is before now (", now, ")");
  return "";
}

std::string Engine::check(double tolerance) const {
  if (!prepared) return "";
  const int n = static_cast<int>(hot.size());
  std::vector<Vector> r(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    HotDisc d = hot[i];
    advance_disc(d, now);
    r[i] = d.position;
  }
  for (int i = 0; i < n; ++i) {
    std::string found = disc_problem(i, tolerance, r.data());
    if (!found.empty()) return found;
  }
  // Heap order, and an entry for every disc's next event.
  if (!queue.valid()) return "event queue out of order, or a disc's next event missing from it";
  const auto asleep_now = std::count_if(hot.begin(), hot.end(), [](const HotDisc& d) { return asleep(d); });
  if (asleep_now != sleeping) return describe(asleep_now, " discs asleep, but ", sleeping, " counted");
  return "";
}

}  // namespace billiard
