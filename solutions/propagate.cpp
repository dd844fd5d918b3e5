// Task 4, reference solution: one event step of the event-driven simulation.
//
// Between collisions every circle moves in a straight line, so instead of taking small time
// steps we jump straight to the next collision (the "event"):
//   1. for every circle, the time until it hits the wall, and for every pair, the time until
//      the two circles touch;
//   2. the smallest of these times is the next event;
//   3. move all circles in a straight line for that time;
//   4. change the velocities of the circle(s) that collide; return what happened.
// Checking all pairs costs O(n^2) per event: simple and right for the course. The library in
// lib/ does the same in O(log n) with an event queue and cells.
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace billiard {
namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();

// Time until circle i, at r moving with v, touches the wall: |r + v t| = R - a.
// Squaring gives A t^2 + 2 B t + C = 0 with A = v.v, B = r.v, C = r.r - (R - a)^2 <= 0.
// Since C <= 0 (the circle is inside) the two roots have opposite signs and we want the
// positive one, t = (-B + sqrt(B^2 - A C)) / A. When B > 0 that formula subtracts two nearly
// equal numbers (cancellation), so we use the equivalent t = -C / (B + sqrt(B^2 - A C)).
double time_to_wall(const Vector& r, const Vector& v, double reach) {
  const double A = v.squaredNorm();
  if (A == 0) return kNever;  // a circle at rest never reaches the wall
  const double B = r.dot(v);
  const double C = r.squaredNorm() - reach * reach;
  // Rounding may leave a circle on or a hair outside the wall after a collision (C >= 0). If
  // it is moving outward (B > 0) it must bounce now, not escape: time 0. Sliding exactly
  // along the wall (B = 0) is a grazing touch, which changes nothing: no collision.
  if (C >= 0 && B >= 0) return B > 0 ? 0.0 : kNever;
  const double root = std::sqrt(std::max(B * B - A * C, 0.0));
  const double t = B > 0 ? -C / (B + root) : (-B + root) / A;
  return std::max(t, 0.0);
}

// Time until circles i and j touch: |dr + dv t| = 2a with dr = r_i - r_j, dv = v_i - v_j.
// Squaring gives dv.dv t^2 + 2 b t + c = 0 with b = dr.dv and c = dr.dr - (2a)^2 >= 0.
// They can only meet if they approach (b < 0) and the discriminant b^2 - dv.dv c >= 0. The
// earlier root, written without cancellation (Numerical Recipes 5.6), is
// t = c / (-b + sqrt(b^2 - dv.dv c)). A pair that has just collided has c ~ 0 and b > 0, so
// it is rejected here without any epsilon.
double time_to_collision(const Vector& dr, const Vector& dv, double diameter) {
  const double b = dr.dot(dv);
  if (b >= 0) return kNever;  // flying apart, or moving side by side (grazing): no collision
  const double c = dr.squaredNorm() - diameter * diameter;
  const double discriminant = b * b - dv.squaredNorm() * c;
  if (discriminant < 0) return kNever;  // they pass each other
  return std::max(c / (-b + std::sqrt(discriminant)), 0.0);  // c < 0 (rounding): collide now
}

}  // namespace

Collision propagate(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                    Velocities& velocities) {
  checks::table(table_radius, circle_radius, n);
  checks::rows(coordinates, n, "coordinates");
  checks::rows(velocities, n, "velocities");
  checks::placement(table_radius, circle_radius, coordinates);

  const double reach = table_radius - circle_radius;  // how far a centre can be from the origin
  const double diameter = 2 * circle_radius;          // centre distance of touching circles

  // 1 and 2: the earliest event over all walls and all pairs.
  Collision next{kNever, -1, kWall};
  for (int i = 0; i < n; ++i) {
    const double t = time_to_wall(coordinates.row(i), velocities.row(i), reach);
    if (t < next.time) next = {t, i, kWall};
    for (int j = i + 1; j < n; ++j) {  // each pair once
      const double tij = time_to_collision(coordinates.row(i) - coordinates.row(j),
                                           velocities.row(i) - velocities.row(j), diameter);
      if (tij < next.time) next = {tij, i, j};
    }
  }
  if (next.time == kNever) {
    throw std::invalid_argument(n == 0 ? "n = 0: with no circles there is no collision to propagate to"
                                       : "velocities: all circles are at rest, so no collision will ever happen");
  }

  // 3: straight-line motion of every circle, colliding or not.
  coordinates += next.time * velocities;

  // 4: new velocities.
  const int i = next.circle;
  if (next.other == kWall) {
    // Ideal reflection: reverse the component along the normal n = r / |r|, keep the tangent.
    const Vector normal = coordinates.row(i).normalized();
    velocities.row(i) -= 2 * velocities.row(i).dot(normal) * normal;
  } else {
    // Equal masses, smooth circles: only the velocity components along the line of centres
    // are exchanged (in 1D this is a swap of velocities; in 2D the tangential parts stay).
    const int j = next.other;
    const Vector normal = (coordinates.row(j) - coordinates.row(i)).normalized();
    const Vector exchange = (velocities.row(i) - velocities.row(j)).dot(normal) * normal;
    velocities.row(i) -= exchange;
    velocities.row(j) += exchange;
  }
  return next;
}

}  // namespace billiard
