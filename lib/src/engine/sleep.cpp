// Sleeping discs: a granular bed at rest under gravity costs no events.
//
// Hard discs cannot rest on one another: a disc "at rest" bounces ever lower and faster, and
// where a row of discs exactly fills the floor of a box, its sideways rattling passes along the
// row for ever, faster and faster as the bed settles. Event-driven granular codes therefore let
// discs at rest sleep, as rigid-body engines do: a group of bodies that has been slow for a while
// is frozen until something hits it hard. The rules here:
//  - Each disc remembers since when it has been slower than the sleep speed (at every collision
//    its speed before and after is checked; in free flight the speed |v + g t| is largest at the
//    ends, so that is enough).
//  - At a collision, a disc slow for at least sleep_time() tries to fall asleep with its island:
//    the awake discs connected to it by contacts (gaps below island_gap()). If every one of them
//    has been slow that long, and the island touches a wall or a sleeping disc, the whole island
//    falls asleep. An island that touches nothing fixed cannot be slow that long (its centre of
//    mass would fall faster than the sleep speed), so a sleeping island is one that was held up.
//  - A sleeping disc has no velocity, does not fall and has no events: to the discs that hit it
//    it is an immovable body (inverse mass 0, as a wall).
//  - A disc hitting a sleeping one at a normal speed of at least the sleep speed wakes it, and in
//    turn every sleeping disc resting on a woken one (touching it from above); then the collision
//    is an ordinary one. Slower hits bounce off it as off a wall.
// Falling asleep takes kinetic energy away and waking gives none, so energy never increases.
#include "engine.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace billiard {

namespace {

// An island that could not fall asleep is tried again after this fraction of the sleep time.
constexpr double kRetryFraction = 0.25;
// A sleeping disc rests on a woken one (and wakes too) if its centre lies higher than the woken
// one's by more than this fraction of their distance (30 degrees above level and more: a disc of
// the row above, not its neighbour in the same row).
constexpr double kRestingOn = 0.5;

}  // namespace

// How long a disc must have been slow to fall asleep: three times the time gravity takes to
// bring a disc from rest to the sleep speed. A disc, or an island of discs, that nothing holds up
// speeds up beyond the sleep speed in less than twice that time.
double Engine::sleep_time() const { return 3 * sleep_speed / gravity.norm(); }

// The largest gap between discs of one island, or between an island and a wall or sleeping disc
// it rests on: twice the height a disc slower than the sleep speed can hop (v^2 / 2g each), at
// most a tenth of the disc's radius.
double Engine::island_gap(double radius) const {
  return std::min(sleep_speed * sleep_speed / gravity.norm(), 0.1 * radius);
}

// Disc i (at the current time) has just collided; it moved at `speed_before` just before.
void Engine::note_speed(int i, double speed_before) {
  const HotDisc& d = hot[i];
  ColdDisc& c = cold[i];
  const double spin_speed = std::abs(c.spin) * d.radius;
  const bool slow_after = d.velocity.norm() < sleep_speed && spin_speed < sleep_speed;
  if (!(speed_before < sleep_speed) || !slow_after) {
    c.slow_since = slow_after ? now : kNever;
  } else if (c.slow_since == kNever) {
    c.slow_since = now;  // (fast after its previous collision: slow from some time since)
  }
}

// After a collision of disc i: puts its island to sleep if every disc of it has been slow for the
// sleep time and it touches something fixed. A failed try postpones the next tries of the discs
// it looked at, so that a large island is not searched again at each collision.
void Engine::try_to_sleep(int i) {
  ColdDisc& c = cold[i];
  if (asleep(hot[i]) || c.slow_since > now - sleep_time() || c.next_sleep_try > now) return;
  const double since = now - sleep_time();
  std::vector<int>& members = island;
  members.assign(1, i);
  in_island.resize(hot.size(), 0);
  in_island[i] = 1;
  bool held = false, all_slow = true;
  for (std::size_t k = 0; k < members.size() && all_slow; ++k) {
    const int m = members[k];
    HotDisc& d = hot[m];
    advance_disc(d, now);
    const ColdDisc& cm = cold[m];
    if (cm.slow_since > since || !(d.velocity.norm() < sleep_speed) || !(std::abs(cm.spin) * d.radius < sleep_speed)) {
      all_slow = false;
      break;
    }
    const double gap = island_gap(d.radius);
    const int cell = cell_of_disc(d);
    if (!held && cell_has_walls(grid, cell)) {
      for (int w = cell_walls_begin(grid, cell), end = cell_walls_end(grid, cell); w < end && !held; ++w) {
        held = wall_clearance(container.walls()[grid.wall_items[w]], d.position, d.radius) <= gap;
      }
    }
    for_each_near(m, [&](int j, const Vector& shift) {
      if (j == m || !all_slow) return;
      HotDisc& o = hot[j];
      if (in_island[j]) return;
      const double reach = d.radius + o.radius + gap;
      const Vector position = asleep(o) ? o.position : [&] {
        advance_disc(o, now);
        return o.position;
      }();
      if ((position + shift - d.position).squaredNorm() > reach * reach) return;
      if (asleep(o)) {
        held = true;
      } else {
        in_island[j] = 1;
        members.push_back(j);
      }
    });
  }
  for (int m : members) in_island[m] = 0;
  if (!all_slow || !held) {
    for (int m : members) cold[m].next_sleep_try = now + kRetryFraction * sleep_time();
    return;
  }
  for (int m : members) {
    HotDisc& d = hot[m];
    d.velocity = Vector::Zero();
    d.inverse_mass = 0;
    d.time = now;
    cold[m].spin = 0;
    cold[m].next_sleep_try = now;
    ++d.counter;  // (contacts predicted with it while it moved are stale)
    ++sleeping;
    Scheduled& s = scheduled[m];
    s.contact_time = kNever;
    s.crossing_time = kNever;
    s.partner = kNoDisc;
    s.wall = kNoWall;
    schedule(m);
    if (logging) record(EventKind::Sleep, m, kNoDisc, kNoWall);
  }
  predict_around(members);
}

// The awake discs around `discs` predicted their contacts with them while they moved (or stood):
// predicts them again.
void Engine::predict_around(const std::vector<int>& discs) {
  for (int i : discs) {
    for_each_near(i, [&](int j, const Vector&) {
      if (!asleep(hot[j])) predict_full(j);
    });
  }
}

// Whether awake disc i, about to collide with sleeping disc j, hits it hard enough to wake it.
bool Engine::hit_wakes(int i, int j) const {
  HotDisc d = hot[i];
  advance_disc(d, now);
  const Vector sigma = minimum_image(container, hot[j].position - d.position).normalized();
  return d.velocity.dot(sigma) >= sleep_speed;
}

// Wakes sleeping disc j and, in turn, every sleeping disc resting on a disc woken; each then
// falls freely from rest, from now.
void Engine::wake(int j) {
  const Vector up = -gravity.normalized();
  woken.assign(1, j);
  hot[j].inverse_mass = 1.0 / cold[j].mass;
  for (std::size_t k = 0; k < woken.size(); ++k) {
    const HotDisc& lower = hot[woken[k]];
    const double gap = island_gap(lower.radius);
    for_each_near(woken[k], [&](int o, const Vector& shift) {
      HotDisc& upper = hot[o];
      if (!asleep(upper)) return;
      const Vector towards = upper.position + shift - lower.position;
      const double distance = towards.norm();
      if (distance <= upper.radius + lower.radius + gap && towards.dot(up) > kRestingOn * distance) {
        upper.inverse_mass = 1.0 / cold[o].mass;
        woken.push_back(o);
      }
    });
  }
  for (int k : woken) {
    hot[k].time = now;
    ++hot[k].counter;
    cold[k].slow_since = now;
    cold[k].next_sleep_try = now;
    --sleeping;
    if (logging) record(EventKind::Wake, k, kNoDisc, kNoWall);
  }
  for (int k : woken) predict_full(k);
  predict_around(woken);
}

// Every sleeping disc wakes (discs may no longer sleep).
void Engine::wake_all() {
  woken.clear();
  for (int i = 0, n = static_cast<int>(hot.size()); i < n; ++i) {
    HotDisc& d = hot[i];
    if (!asleep(d)) continue;
    d.inverse_mass = 1.0 / cold[i].mass;
    d.time = now;
    ++d.counter;
    cold[i].slow_since = now;
    woken.push_back(i);
    if (logging) record(EventKind::Wake, i, kNoDisc, kNoWall);
  }
  sleeping = 0;
  for (int i : woken) predict_full(i);
}

}  // namespace billiard
