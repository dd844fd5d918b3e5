// Another correct propagate, written apart from solutions/propagate.cpp the way a student might:
// plain doubles instead of Eigen rows, one loop per kind of event. The class tests hand it in
// beside the reference to check that two honest solutions are not flagged as copies.
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace billiard {

static const double INF = std::numeric_limits<double>::infinity();

static double wall_hit(double x, double y, double vx, double vy, double rmax) {
  double speed2 = vx * vx + vy * vy;
  if (speed2 == 0.0) {
    return INF;
  }
  double outward = x * vx + y * vy;
  double inside = x * x + y * y - rmax * rmax;
  if (inside >= 0.0 && outward >= 0.0) {
    if (outward > 0.0) return 0.0;
    return INF;
  }
  double d = outward * outward - speed2 * inside;
  if (d < 0.0) d = 0.0;
  double t;
  if (outward > 0.0) {
    t = -inside / (outward + std::sqrt(d));
  } else {
    t = (std::sqrt(d) - outward) / speed2;
  }
  return t < 0.0 ? 0.0 : t;
}

static double pair_hit(double dx, double dy, double dvx, double dvy, double contact) {
  double approach = dx * dvx + dy * dvy;
  if (approach >= 0.0) {
    return INF;
  }
  double gap = dx * dx + dy * dy - contact * contact;
  double rel2 = dvx * dvx + dvy * dvy;
  double d = approach * approach - rel2 * gap;
  if (d < 0.0) {
    return INF;
  }
  double t = gap / (std::sqrt(d) - approach);
  return t < 0.0 ? 0.0 : t;
}

Collision propagate(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                    Velocities& velocities) {
  checks::table(table_radius, circle_radius, n);
  checks::rows(coordinates, n, "coordinates");
  checks::rows(velocities, n, "velocities");
  checks::placement(table_radius, circle_radius, coordinates);

  double best = INF;
  int first = -1;
  int second = kWall;
  for (int a = 0; a < n; a++) {
    double t = wall_hit(coordinates(a, 0), coordinates(a, 1), velocities(a, 0), velocities(a, 1),
                        table_radius - circle_radius);
    if (t < best) {
      best = t;
      first = a;
      second = kWall;
    }
  }
  for (int a = 0; a < n; a++) {
    for (int b = a + 1; b < n; b++) {
      double t = pair_hit(coordinates(a, 0) - coordinates(b, 0), coordinates(a, 1) - coordinates(b, 1),
                          velocities(a, 0) - velocities(b, 0), velocities(a, 1) - velocities(b, 1),
                          2.0 * circle_radius);
      if (t < best) {
        best = t;
        first = a;
        second = b;
      }
    }
  }
  if (best == INF) {
    if (n == 0) throw std::invalid_argument("n = 0: there are no circles to move");
    throw std::invalid_argument("velocities: every circle is at rest, nothing will ever collide");
  }

  for (int a = 0; a < n; a++) {
    coordinates(a, 0) += best * velocities(a, 0);
    coordinates(a, 1) += best * velocities(a, 1);
  }

  if (second == kWall) {
    double x = coordinates(first, 0), y = coordinates(first, 1);
    double len = std::sqrt(x * x + y * y);
    double nx = x / len, ny = y / len;
    double vn = velocities(first, 0) * nx + velocities(first, 1) * ny;
    velocities(first, 0) -= 2.0 * vn * nx;
    velocities(first, 1) -= 2.0 * vn * ny;
  } else {
    double nx = coordinates(second, 0) - coordinates(first, 0);
    double ny = coordinates(second, 1) - coordinates(first, 1);
    double len = std::sqrt(nx * nx + ny * ny);
    nx /= len;
    ny /= len;
    double along = (velocities(first, 0) - velocities(second, 0)) * nx +
                   (velocities(first, 1) - velocities(second, 1)) * ny;
    velocities(first, 0) -= along * nx;
    velocities(first, 1) -= along * ny;
    velocities(second, 0) += along * nx;
    velocities(second, 1) += along * ny;
  }
  return Collision{best, first, second};
}

}  // namespace billiard
