// Sleeping discs: a granular bed at rest under gravity costs no events.
//
// Hard discs cannot rest on one another: a disc "at rest" on a floor bounces ever lower and
// faster, and the granular model's rules (simulation.hpp) keep the last bounces elastic, so a
// settled bed still costs tens of collisions per disc per unit of time, and far more where the
// rules leave energy with no way out (a row of discs that exactly fills the floor of a box passes
// its sideways rattling on elastically for ever). Event-driven granular codes therefore let discs
// at rest sleep (DynamO's "sleeping particles" are one example). The rules here:
//  - A disc falls asleep at a collision with something fixed (a wall or a sleeping disc) when it
//    leaves that collision slower than the sleep speed and is supported: gravity points into the
//    cone of its contacts with fixed things (those within kSupportGap of its radius), so that
//    frictionless contact forces could hold it. A disc on a slope, or leaning on one disc, slides
//    on instead.
//  - A sleeping disc has no velocity, does not fall and has no events: to the discs that hit it,
//    it is an immovable body (inverse mass 0, as a wall).
//  - A disc hitting a sleeping one at a normal speed of at least the sleep speed wakes it, and in
//    turn every sleeping disc resting on a disc woken; then the collision is an ordinary one.
//    Slower hits bounce off it as off a wall.
// Falling asleep takes kinetic energy away and waking gives none, so energy never increases.
#include "engine.hpp"

#include "billiard/time_of_impact.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace billiard {

namespace {

// Contacts no farther than this many of the disc's radii count as supports: a disc may fall
// asleep at most this far above the things it rests on.
constexpr double kSupportGap = 1e-3;
// A single contact supports a disc if gravity points at it within this angle (radians): a disc
// balanced that nearly on top of another stays (sliding off, it would gain too little speed to
// be followed in double precision); two contacts support it if they are less than half a turn
// minus kSupportMargin apart.
constexpr double kBalanceAngle = 0.05;
constexpr double kSupportMargin = 1e-6;
// Slow discs that can only hold one another up fall asleep together in groups of at most this
// many (try_to_sleep).
constexpr std::size_t kLargestSleepingGroup = 8;
// Leaving a fixed contact (lift_off): the least normal part of the velocity, as a fraction of the
// speed; and the slide of a disc at rest, in radii (10 times below validate()'s tolerance, as it
// may bring the disc that much closer to a neighbour).
constexpr double kLift = 0.1;
constexpr double kSlideStep = 1e-10;
constexpr double kPi = 3.14159265358979323846;

}  // namespace

// Disc i (awake) has reached sleeping disc j.
void Simulation::Engine::hit_sleeper(int i, int j) {
  HotDisc& d = hot[i];
  advance_disc(d, now);
  const HotDisc& fixed = hot[j];
  const Vec2 dr = minimum_image(fixed.position - d.position);  // from i to j
  const double distance = dr.norm();
  const Vec2 sigma = dr / distance;
  const double approach = d.velocity.dot(sigma);
  if (approach >= sleep_speed) {
    wake(j);
    collide_and_predict(i, j);
    if (logging) record(EventKind::DiscDisc, i, j, kNoWall);
    return;
  }
  // A disc found a rounding error inside the sleeper is put back on it (see collide_wall).
  const double contact = d.radius + fixed.radius;
  if (distance < contact) d.position -= (contact - distance) * sigma;
  ColdDisc& c = cold[i];
  ContactBody body{d.velocity, c.spin, d.inverse_mass, c.inverse_inertia, d.radius};
  ContactBody immovable{Vec2::Zero(), 0.0, 0.0, 0.0, fixed.radius};
  collide(sigma, body, immovable, restitution_against_fixed(approach, c.last_collision));
  d.velocity = body.velocity;
  c.spin = body.spin;
  c.last_collision = now;
  ++d.counter;
  if (logging) record(EventKind::DiscDisc, i, j, kNoWall);
  leave_fixed_contact(i, sigma);
}

// Disc i has bounced off something fixed (a wall, or a sleeping disc), touching it along `normal`
// (from i's centre towards it, any length): it falls asleep, or is predicted again.
void Simulation::Engine::leave_fixed_contact(int i, const Vec2& normal) {
  if (try_to_sleep(i)) return;
  if (sleep_speed > 0) lift_off(i, normal.normalized());
  predict_full(i);
}

// Under gravity a disc that leaves a fixed contact almost along it (sliding on a floor after a
// sideways hit, or at rest against a slope after the disc below it woke) meets it again at once,
// and again, all at one instant. So its velocity is turned away from the contact until the normal
// part is kLift of the speed (same speed: same energy), and a disc too slow for that first slides
// kSlideStep radii down along the contact and leaves it the same way, at the speed that drop
// gives it (no energy gained). (Beyond kBalanceAngle from the top of a contact, each such hop
// gains more from the slope than a collision takes, so a disc at rest slides off.)
// `towards`: unit, from i's centre towards the contact.
void Simulation::Engine::lift_off(int i, const Vec2& towards) {
  HotDisc& d = hot[i];
  const double pressing = gravity.dot(towards);
  if (!(pressing > 0)) return;  // gravity takes it away from the contact
  const Vec2 downhill = gravity - pressing * towards;
  const double step = kSlideStep * d.radius;
  const double slide_speed = std::sqrt(2 * step * downhill.norm());
  double speed = d.velocity.norm();
  Vec2 along;
  if (speed < slide_speed) {
    along = downhill.normalized();
    d.position += step * along;
    speed = slide_speed;
  } else {
    const double away = -d.velocity.dot(towards);
    if (!(away < kLift * speed)) return;
    along = d.velocity + away * towards;  // (the part along the contact)
    if (along.squaredNorm() == 0) along = Vec2(-towards.y(), towards.x());
    along.normalize();
  }
  d.velocity = speed * (std::sqrt(1 - kLift * kLift) * along - kLift * towards);
}

// Whether disc i (at the current time) is slow enough to sleep.
bool Simulation::Engine::slow(int i) const {
  const HotDisc& d = hot[i];
  const double spin_speed = cold[i].spin * d.radius;
  const double limit = sleep_speed * sleep_speed;
  return d.velocity.squaredNorm() < limit && spin_speed * spin_speed < limit;
}

// After disc i's collision with something fixed (i is at the current time): puts it to sleep if
// it is slow and supported. Slow discs leaning on one another (an arch over a gap, say) may only
// be supported together: then the slow awake discs touching an unsupported member join the
// group, up to kLargestSleepingGroup discs, and the whole group falls asleep if every member is
// supported by fixed things and the other members. Returns whether i fell asleep.
bool Simulation::Engine::try_to_sleep(int i) {
  if (!(sleep_speed > 0) || !slow(i)) return false;
  std::vector<int>& group = sleeping_group;
  group.assign(1, i);
  const auto member = [&](int j) { return std::find(group.begin(), group.end(), j) != group.end(); };
  for (;;) {
    const auto unsupported = std::find_if(group.begin(), group.end(), [&](int m) { return !supported(m, group); });
    if (unsupported == group.end()) break;
    const int m = *unsupported;
    const std::size_t before = group.size();
    for_each_near(m, [&](int j, const Vec2& shift) {
      if (asleep(hot[j]) || member(j) || group.size() >= kLargestSleepingGroup) return;
      HotDisc moved = hot[j];
      advance_disc(moved, now);
      const double reach = hot[m].radius + moved.radius + kSupportGap * hot[m].radius;
      if ((moved.position + shift - hot[m].position).squaredNorm() > reach * reach) return;
      hot[j] = moved;
      if (slow(j)) group.push_back(j);
    });
    if (group.size() == before) return false;
  }
  fall_asleep(group);
  return true;
}

// Whether gravity points into the cone spanned by disc i's contacts with fixed things (walls and
// sleeping discs) and with the discs of `group` (about to sleep with it; at the current time):
// one contact straight below it, or two on either side of straight down less than half a turn
// apart.
bool Simulation::Engine::supported(int i, const std::vector<int>& group) const {
  const HotDisc& d = hot[i];
  const Vec2 down = gravity.normalized();
  const double gap = kSupportGap * d.radius;
  // The contacts closest to straight down, counter-clockwise and clockwise from it (angles).
  double counter_clockwise = kNever, clockwise = kNever;
  const auto contact = [&](const Vec2& towards) {  // unit, from i's centre
    const double angle = std::atan2(down.x() * towards.y() - down.y() * towards.x(), down.dot(towards));
    if (angle >= 0) counter_clockwise = std::min(counter_clockwise, angle);
    if (angle <= 0) clockwise = std::min(clockwise, -angle);
  };
  const int cell = cell_of_disc(d);
  if (cell_has_walls(grid, cell)) {
    for (int k = cell_walls_begin(grid, cell), end = cell_walls_end(grid, cell); k < end; ++k) {
      const Wall& wall = walls[grid.wall_items[k]];
      if (wall.kind == WallKind::Circle) {
        const Vec2 out = d.position - wall.a;
        const double r = out.norm();
        if (r > 0 && r >= wall.radius - d.radius - gap) contact(out / r);
      } else {
        const Vec2 to = closest_point(wall, d.position) - d.position;
        const double distance = to.norm();
        if (distance > 0 && distance <= d.radius + gap) contact(to / distance);
      }
    }
  }
  for_each_near(i, [&](int j, const Vec2& shift) {
    const HotDisc& o = hot[j];
    if (j == i || !(asleep(o) || std::find(group.begin(), group.end(), j) != group.end())) return;
    const Vec2 to = o.position + shift - d.position;
    const double distance = to.norm();
    if (distance > 0 && distance <= d.radius + o.radius + gap) contact(to / distance);
  });
  return counter_clockwise <= kBalanceAngle || clockwise <= kBalanceAngle ||
         counter_clockwise + clockwise < kPi - kSupportMargin;
}

// The discs of `group` (at the current time) fall asleep.
void Simulation::Engine::fall_asleep(const std::vector<int>& group) {
  for (int i : group) {
    HotDisc& d = hot[i];
    d.velocity = Vec2::Zero();
    d.inverse_mass = 0;
    d.time = now;
    cold[i].spin = 0;
    ++d.counter;  // (contacts predicted with it while it moved are stale)
    ++sleeping;
    Scheduled& s = scheduled[i];
    s.contact_time = kNever;
    s.crossing_time = kNever;
    s.partner = kNoPartner;
    schedule(i);
    if (logging) record(EventKind::Sleep, i, kNoPartner, kNoWall);
  }
  // The discs around them predicted their contacts with them while they moved: they stay now.
  for (int i : group) {
    for_each_near(i, [&](int j, const Vec2&) {
      if (!asleep(hot[j])) predict_full(j);
    });
  }
}

// Wakes sleeping disc j and, in turn, every sleeping disc resting on a disc woken (touching it
// within the support gap, from above); each then falls freely from rest, from now.
void Simulation::Engine::wake(int j) {
  std::vector<int> woken{j};
  hot[j].inverse_mass = 1.0 / cold[j].mass;
  for (std::size_t k = 0; k < woken.size(); ++k) {
    const HotDisc& lower = hot[woken[k]];
    for_each_near(woken[k], [&](int o, const Vec2& shift) {
      HotDisc& upper = hot[o];
      if (!asleep(upper)) return;
      const Vec2 down = lower.position - (upper.position + shift);  // from the upper disc to the lower
      const double reach = upper.radius + lower.radius + kSupportGap * upper.radius;
      if (down.dot(gravity) > 0 && down.squaredNorm() <= reach * reach) {
        upper.inverse_mass = 1.0 / cold[o].mass;
        woken.push_back(o);
      }
    });
  }
  for (int k : woken) {
    hot[k].time = now;
    ++hot[k].counter;
    --sleeping;
    if (logging) record(EventKind::Wake, k, kNoPartner, kNoWall);
  }
  for (int k : woken) predict_full(k);
}

// Every sleeping disc wakes (the sleep speed became 0).
void Simulation::Engine::wake_all() {
  std::vector<int> woken;
  for (int i = 0, n = static_cast<int>(hot.size()); i < n; ++i) {
    if (!asleep(hot[i])) continue;
    HotDisc& d = hot[i];
    d.inverse_mass = 1.0 / cold[i].mass;
    d.time = now;
    ++d.counter;
    woken.push_back(i);
    if (logging) record(EventKind::Wake, i, kNoPartner, kNoWall);
  }
  sleeping = 0;
  for (int i : woken) predict_full(i);
}

}  // namespace billiard
