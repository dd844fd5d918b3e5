// Helpers shared by the engine tests: random systems that are valid by construction.
#pragma once

#include "billiard/engine/simulation.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace engine_test {

using billiard::Vector;

struct RandomDiscs {
  std::vector<Vector> positions;
  std::vector<Vector> velocities;
  std::vector<double> radii;
};

// n discs with radii in [radius_lo, radius_hi] placed by random sequential addition where
// `inside(position, radius)` accepts them, without overlaps; Gaussian velocities.
template <class Inside>
RandomDiscs random_discs(std::mt19937_64& rng, int n, double radius_lo, double radius_hi, const Vector& lo,
                         const Vector& hi, Inside inside) {
  RandomDiscs d;
  std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y()), ur(radius_lo, radius_hi);
  std::normal_distribution<double> normal;
  int attempts = 0;
  while (static_cast<int>(d.positions.size()) < n && ++attempts < 1000000) {
    const Vector p(ux(rng), uy(rng));
    const double a = radius_lo == radius_hi ? radius_lo : ur(rng);
    if (!inside(p, a)) continue;
    bool free = true;
    for (std::size_t k = 0; k < d.positions.size() && free; ++k) {
      free = (p - d.positions[k]).norm() >= a + d.radii[k] + 1e-9;
    }
    if (!free) continue;
    d.positions.push_back(p);
    d.radii.push_back(a);
    d.velocities.emplace_back(normal(rng), normal(rng));
  }
  return d;
}

inline void add_all(billiard::Simulation& sim, const RandomDiscs& d, double mass = 1.0) {
  for (std::size_t k = 0; k < d.positions.size(); ++k) {
    billiard::Disc disc;
    disc.position = d.positions[k];
    disc.velocity = d.velocities[k];
    disc.radius = d.radii[k];
    disc.mass = mass;
    sim.add_disc(disc);
  }
}

// Whether two lists of walls are the same, field by field (a refused add_ call must leave a
// container's walls as they were).
inline bool same_walls(const std::vector<billiard::WallShape>& x, const std::vector<billiard::WallShape>& y) {
  if (x.size() != y.size()) return false;
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (x[k].kind != y[k].kind || x[k].a != y[k].a || x[k].b != y[k].b || x[k].radius != y[k].radius ||
        x[k].start_angle != y[k].start_angle || x[k].sweep != y[k].sweep) {
      return false;
    }
  }
  return true;
}

// Settings with this gravity and restitution, everything else at its default.
inline billiard::Settings physics(const Vector& gravity, const billiard::Restitution& restitution = {}) {
  billiard::Settings settings;
  settings.gravity = gravity;
  settings.restitution = restitution;
  return settings;
}

inline billiard::Disc make_disc(const Vector& position, const Vector& velocity, double radius = 1.0, double mass = 1.0) {
  billiard::Disc disc;
  disc.position = position;
  disc.velocity = velocity;
  disc.radius = radius;
  disc.mass = mass;
  return disc;
}

// Angular momentum about the origin, sum m r x v + I w (masses 1 unless given).
inline double angular_momentum(const billiard::State& s, const std::vector<double>& masses = {}) {
  double l = 0;
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
    const double m = masses.empty() ? 1.0 : masses[static_cast<std::size_t>(i)];
    l += m * (s.positions(i, 0) * s.velocities(i, 1) - s.positions(i, 1) * s.velocities(i, 0));
  }
  return l;
}

}  // namespace engine_test
