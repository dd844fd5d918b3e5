// Task 7, reference solution: one event step of circles falling under a uniform gravity g.
//
// Between events every centre flies on a parabola, r(t) = r + v t + g t^2 / 2, with velocity
// v(t) = v + g t. The step is the one of propagate (task 4):
//   1. the time until each circle hits the wall and until each pair touches;
//   2. the smallest of these is the next event;
//   3. move every circle on its parabola for that time, velocities included;
//   4. change the velocities of the colliding circle(s), using their velocities at contact.
// Two things differ. Pair times do not change at all: both circles of a pair fall alike, so
// their relative motion r_i - r_j is a straight line. The wall time does: |r(t)| = R - a is a
// quartic in t, solved here by splitting time into pieces on which |r(t)|^2 is monotone and
// bisecting the piece where the circle crosses the wall.
#include "billiard/argument_checks.hpp"
#include "billiard/extensions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace billiard {
namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();

// p(t) = p[0] + p[1] t + ... + p[degree] t^degree, by Horner's rule.
double evaluate(const double* p, int degree, double t) {
  double sum = p[degree];
  for (int k = degree - 1; k >= 0; --k) sum = sum * t + p[k];
  return sum;
}

// Bisection of [lo, hi] where p changes sign, down to adjacent doubles (about 60 halvings,
// more when the root is tiny). Returns the end on the same side as hi, so that a wall hit is
// found at contact or a rounding error after it, never before.
double bisect(const double* p, int degree, double lo, double hi) {
  const bool lo_negative = evaluate(p, degree, lo) < 0;
  for (;;) {
    const double mid = lo + (hi - lo) / 2;
    if (mid <= lo || mid >= hi) return hi;
    if ((evaluate(p, degree, mid) < 0) == lo_negative) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
}

// The points lo = x_0 < x_1 < ... < x_m = hi between which p is monotone: lo, the roots of p'
// inside (lo, hi), and hi. The roots of p' are found the same way one degree lower: p' is
// monotone between the roots of p'', so each of its pieces holds at most one root, found by
// bisection when p' changes sign there. Returns m + 1 (at most degree + 1 points).
int monotone_pieces(const double* p, int degree, double lo, double hi, double* points) {
  int count = 0;
  points[count++] = lo;
  if (degree >= 2) {  // else p' is constant: p is monotone on all of [lo, hi]
    double derivative[4];
    for (int k = 1; k <= degree; ++k) derivative[k - 1] = k * p[k];
    double pieces[5];
    const int m = monotone_pieces(derivative, degree - 1, lo, hi, pieces);
    for (int k = 0; k + 1 < m; ++k) {
      const double left = evaluate(derivative, degree - 1, pieces[k]);
      const double right = evaluate(derivative, degree - 1, pieces[k + 1]);
      if ((left < 0 && right > 0) || (left > 0 && right < 0)) {
        points[count++] = bisect(derivative, degree - 1, pieces[k], pieces[k + 1]);
      } else if (right == 0 && k + 2 < m) {
        points[count++] = pieces[k + 1];  // p' vanishes exactly at a piece's end
      }
    }
  }
  points[count++] = hi;
  return count;
}

// Time until a circle at r with velocity v reaches the wall, |r(t)| = reach = R - a, moving
// outward. Without gravity the stable quadratic of propagate.
double time_to_wall_straight(const Vector& r, const Vector& v, double reach) {
  const double A = v.squaredNorm();
  if (A == 0) return kNever;  // at rest and no gravity: never
  const double B = r.dot(v);
  const double C = r.squaredNorm() - reach * reach;
  if (C >= 0 && B >= 0) return B > 0 ? 0.0 : kNever;  // on the wall: moving out bounces now
  const double root = std::sqrt(std::max(B * B - A * C, 0.0));
  return std::max(B > 0 ? -C / (B + root) : (-B + root) / A, 0.0);
}

// Under gravity: f(t) = |r + v t + g t^2/2|^2 - reach^2
//                     = (g.g/4) t^4 + (v.g) t^3 + (v.v + r.g) t^2 + 2 (r.v) t + r.r - reach^2,
// negative inside the table. The wall is hit where f crosses zero upward (the circle moving
// out); a downward crossing, or a root at t ~ 0 right after a bounce, is no hit.
double time_to_wall(const Vector& r, const Vector& v, const Vector& g, double reach) {
  if (g.isZero(0)) return time_to_wall_straight(r, v, reach);
  const double f[5] = {r.squaredNorm() - reach * reach, 2 * r.dot(v), v.squaredNorm() + r.dot(g), v.dot(g),
                       g.squaredNorm() / 4};
  // On or a hair outside the wall (rounding) and moving out: bounce now. f'(0) = 0 with
  // f''(0) > 0 is a circle sliding along the wall that gravity pushes out.
  if (f[0] >= 0 && (f[1] > 0 || (f[1] == 0 && f[2] > 0))) return 0.0;
  // |r(t)| >= |g| t^2/2 - |v| t - |r|, which reaches `reach` at the larger root T of
  // |g|/2 t^2 - |v| t - (|r| + reach) (a sum in its numerator: no cancellation). From T on the
  // circle is outside, so the crossing lies in [0, T]. The bound is tight (a circle dropped from
  // rest at the centre arrives exactly at T), so search up to 2 T, lest rounding put it beyond.
  const double speed = v.norm();
  const double t_max = 2 * (speed + std::sqrt(speed * speed + 2 * g.norm() * (r.norm() + reach))) / g.norm();
  // A g so weak that |g|^2 underflows (|g| < 1e-154) has norm 0 and no finite bound; its pull is
  // far below rounding then: fly straight (this also keeps the bisections below finite).
  if (!(t_max < kNever)) return time_to_wall_straight(r, v, reach);
  // Each monotone piece of f crosses zero at most once: look for the first piece that starts
  // inside (f < 0) and ends on or outside the wall (f >= 0). Sampling f at fixed steps instead
  // would step over a near-grazing arc that leaves the table for only a moment.
  double points[5];
  const int m = monotone_pieces(f, 4, 0.0, t_max, points);
  for (int k = 0; k + 1 < m; ++k) {
    const double left = evaluate(f, 4, points[k]);
    const double right = evaluate(f, 4, points[k + 1]);
    if (left < 0 && right >= 0) return right == 0 ? points[k + 1] : bisect(f, 4, points[k], points[k + 1]);
  }
  // No upward crossing: only possible for a circle a hair outside (rounding) that moves in too
  // slowly to get inside before gravity takes it out again. It is in contact: bounce now.
  return f[0] >= 0 ? 0.0 : kNever;
}

// Time until circles touch: |dr + dv t| = 2a, exactly as in propagate, because gravity cancels
// in the relative position (r_i - r_j)(t) = dr + dv t.
double time_to_collision(const Vector& dr, const Vector& dv, double diameter) {
  const double b = dr.dot(dv);
  if (b >= 0) return kNever;  // flying apart, or sliding past each other: no collision
  const double c = dr.squaredNorm() - diameter * diameter;
  const double discriminant = b * b - dv.squaredNorm() * c;
  if (discriminant < 0) return kNever;
  return std::max(c / (-b + std::sqrt(discriminant)), 0.0);
}

}  // namespace

Collision propagate_gravity(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                            Velocities& velocities, const Vector& g) {
  checks::table(table_radius, circle_radius, n);
  checks::rows(coordinates, n, "coordinates");
  checks::rows(velocities, n, "velocities");
  checks::vector(g, "g");
  checks::placement(table_radius, circle_radius, coordinates);

  const double reach = table_radius - circle_radius;
  const double diameter = 2 * circle_radius;

  Collision next{kNever, -1, kWall};
  for (int i = 0; i < n; ++i) {
    const double t = time_to_wall(coordinates.row(i), velocities.row(i), g, reach);
    if (t < next.time) next = {t, i, kWall};
    for (int j = i + 1; j < n; ++j) {
      const double tij = time_to_collision(coordinates.row(i) - coordinates.row(j),
                                           velocities.row(i) - velocities.row(j), diameter);
      if (tij < next.time) next = {tij, i, j};
    }
  }
  if (next.time == kNever) {
    // Under gravity every circle reaches the wall, so this happens only for n = 0 or g = 0.
    throw std::invalid_argument(n == 0 ? "n = 0: with no circles there is no collision to propagate to"
                                       : "velocities: all circles are at rest and g = 0, so no collision will ever happen");
  }

  // Every circle flies on its parabola; the velocities gain g t.
  const double t = next.time;
  coordinates += t * velocities;
  coordinates.rowwise() += (t * t / 2) * g;
  velocities.rowwise() += t * g;

  // New velocities, from the velocities at contact.
  const int i = next.circle;
  if (next.other == kWall) {
    const Vector normal = coordinates.row(i).normalized();
    velocities.row(i) -= 2 * velocities.row(i).dot(normal) * normal;
  } else {
    const int j = next.other;
    const Vector normal = (coordinates.row(j) - coordinates.row(i)).normalized();
    const Vector exchange = (velocities.row(i) - velocities.row(j)).dot(normal) * normal;
    velocities.row(i) -= exchange;
    velocities.row(j) += exchange;
  }
  return next;
}

// Kinetic energy |v|^2 / 2 plus potential energy -g.r per circle (unit mass): the potential
// grows against gravity (with g = (0, -9.81) it is 9.81 y, the familiar m g h).
double mean_energy(int n, const Coordinates& coordinates, const Velocities& velocities, const Vector& g) {
  checks::rows(coordinates, n, "coordinates");
  checks::rows(velocities, n, "velocities");
  checks::vector(g, "g");
  if (n == 0) return 0.0;
  double sum = 0;
  for (int i = 0; i < n; ++i) sum += velocities.row(i).squaredNorm() / 2 - g.dot(coordinates.row(i));
  return sum / n;
}

}  // namespace billiard
