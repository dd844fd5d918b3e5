// The physics and the engine's choices for a simulation, as one value with defaults:
//
//   billiard::Settings settings;
//   settings.gravity = {0, -1};
//   settings.restitution = {0.9, -1};
//   billiard::Simulation sim(billiard::box({0, 0}, {10, 10}), settings);
//
// The simulation checks them when it is made (std::invalid_argument naming the field, e.g.
// "settings.gravity"). Gravity, the cell size and prefetching are fixed from then on; the
// restitution, the exchange rule and the granular model may be changed during a run with the
// simulation's setters of the same names.
#pragma once

#include "billiard/engine/plane.hpp"

#include <optional>

namespace billiard {

// Coefficients of restitution (the collision rule: lib/PHYSICS.md, "Collision rules"). normal
// in [0, 1] (1: elastic); tangential in [-1, 1] (-1: smooth, the contact points slide freely and
// spins never change; +1: perfectly rough, the tangential contact velocity is reversed). Kinetic
// energy (with spin) is conserved iff normal = 1 and tangential = +-1.
struct Restitution {
  double normal = 1.0;
  double tangential = -1.0;
};

// Whether each event starts loading the data of the event expected after it (the discs' states
// around it) into the caches: faster for large systems, slower where everything fits in the
// caches anyway. Automatic turns it on from about 87,000 discs; On and Off force it (benchmarks,
// tests). The events and results are the same either way.
enum class Prefetch { Automatic, On, Off };

// The granular model's fixed numbers. A disc resting on a floor under gravity bounces at most
// this many mean radii high before its collisions turn elastic (the automatic elastic impact and
// sleep speeds).
inline constexpr double kRestingBounce = 0.05;
// Under gravity a disc meets fixed things (walls, sleeping discs) this fraction of its radius
// closer than touching: a disc at rest on a floor, or sliding along it, would otherwise meet it
// again at once after each bounce (approach speed 0), for ever at one instant. With the slack it
// drops that far and bounces (the drop gives it the speed: no energy is gained). Ten times below
// Simulation::validate()'s tolerance.
inline constexpr double kFixedContactSlack = 1e-10;

struct Settings {
  // Uniform, any direction. In a periodic box it accelerates every disc alike and changes nothing
  // between them: the discs are moved in the freely falling frame (their relative motion as
  // precise as without gravity, however long they fall) and the fall, g t^2 / 2 and g t, is
  // added to what the simulation reports; the granular model's automatic values are those
  // without gravity there (nothing rests in a periodic box).
  Vector gravity = Vector::Zero();
  // The default is smooth elastic discs.
  Restitution restitution;
  // The exchange rule: two discs that meet reverse their whole relative velocity, so discs of
  // equal mass exchange their velocities (exactly); walls reflect like mirrors (the normal
  // component reverses). For equal masses this is perfectly rough discs (tangential restitution
  // +1) whose spins never change (an infinite moment of inertia), but with smooth walls: the
  // rule of the classic "Collisions" exercise (the `particles` program). Momentum and energy
  // are conserved. While it is on, the restitution and the granular rules do not apply to discs
  // meeting discs (a disc meeting a sleeping one, which happens only with a sleep speed set,
  // still follows the restitution).
  bool exchange_velocities = false;
  // Granular gases (normal restitution < 1). Inelastic collisions can come infinitely often in a
  // finite time (inelastic collapse), and a disc settling on a floor under gravity bounces ever
  // lower and faster: event-driven dynamics would stop there. Three rules deal with it; they
  // only ever take energy away or switch dissipation off, never add energy:
  //  - the TC model (Luding & McNamara 1998): a collision less than `contact_duration` after the
  //    previous collision of either disc is elastic, as if the two were one longer contact (for
  //    two moving discs, their previous collisions with moving discs count; for a disc meeting a
  //    wall or a sleeping disc, its previous collision of any kind);
  //  - slow impacts (Poschel & Schwager, Computational Granular Dynamics, ch. 3): a collision
  //    whose contact points approach at less than `elastic_impact_speed` along the normal is
  //    elastic, so that a disc resting on a floor under gravity g bounces at most speed^2 / (2 g)
  //    high;
  //  - sleeping: discs at rest under gravity sleep, so that a settled bed costs no events
  //    (sleep.cpp): discs slower than `sleep_speed` for 3 speed / |g|, connected by contacts and
  //    touching a wall or a sleeping disc, stop together; a sleeping disc is immovable and has no
  //    events. A disc hitting one at a normal speed of at least `sleep_speed` wakes it (and the
  //    sleeping discs resting on it); slower hits bounce off it.
  // std::nullopt (the default) chooses each automatically at the first advance (see
  // Simulation::contact_duration()); 0 switches the rule off. The automatic sleep speed is
  // sqrt(2 |g| h) with h = kRestingBounce mean radii when gravity acts and the
  // normal restitution is below 1, else 0; while discs can sleep, the automatic elastic impact
  // speed is 0.
  std::optional<double> contact_duration;
  std::optional<double> elastic_impact_speed;
  std::optional<double> sleep_speed;
  // Cell side (at least the largest diameter); 0 = automatic.
  double cell_size = 0.0;
  Prefetch prefetch = Prefetch::Automatic;
};

}  // namespace billiard
