// Time of impact: pure functions, each returning the smallest time t >= 0 at which two objects
// moving freely (straight lines, or parabolas under a uniform gravity g) start touching, or
// kNever if they never do. Derivations: lib/PHYSICS.md ("Time of impact") and the
// comments in time_of_impact.cpp. Internal: not installed.
//
// Rounding convention, used everywhere: an object found a hair inside an obstacle (overlap of
// the order of rounding) and still moving into it collides at t = 0, so it bounces back instead
// of escaping; one moving out of it, or sliding along it (grazing, b = 0), is no collision.
// Times are never shifted by epsilons.
#pragma once

#include "billiard/engine/plane.hpp"

#include <algorithm>
#include <cmath>

namespace billiard {

// Moving along a contact up to rounding: the cosine between the offset d and the velocity v is
// below 1e-12, so the sign of b = d.v is rounding only (a tangential speed 1e29 times the normal
// one makes b's rounding 1e13 times the normal part). Such motion neither approaches nor
// recedes; taking it for an approach would collide a pair again and again at one instant.
inline bool moving_along(double b, double d_squared, double v_squared) { return b * b <= 1e-24 * d_squared * v_squared; }

// Real roots of a t^2 + b t + c = 0 in increasing order (count 0, 1 or 2; a double root is
// reported twice), computed with the stable form of Numerical Recipes 5.6:
// q = -(b + sign(b) sqrt(b^2 - 4ac)) / 2, roots q / a and c / q. When a = 0 the equation is
// linear (count 1, or 0 if b = 0 too).
struct QuadraticRoots {
  int count = 0;
  double lo = kNever;
  double hi = kNever;
};
QuadraticRoots solve_quadratic(double a, double b, double c);

// h(t) = a t^2 + b t + c is a "penetration" (negative while apart, zero at contact). Returns the
// first t >= 0 at which h crosses zero upwards (the objects start to overlap), 0 if h(0) >= 0
// while h is still rising (rounding overlap, see above), kNever if h never rises through zero.
double first_upward_root(double a, double b, double c);

// Smallest t in [0, t_max] at which the polynomial p(t) = p[0] + p[1] t + ... + p[degree]
// t^degree (degree <= 4) crosses zero upwards (rising = true) or downwards (rising = false), or
// kNever. Robust: the roots of the derivatives split [0, t_max] into monotone pieces (found
// recursively), and each piece with a sign change is bisected to full double precision.
double first_polynomial_crossing(const double* p, int degree, double t_max, bool rising);

// Two discs with relative position dr = r_i - r_j, relative velocity dv = v_i - v_j and contact
// distance `contact` = a_i + a_j. Relative motion is linear even under gravity (both discs fall
// alike). Approaching only if b = dr.dv < 0 (and not moving_along); then t = c / (-b + sqrt(b^2 - dv.dv c)) with
// c = dr.dr - contact^2 (stable form). A pair that has just collided has c ~ 0, b > 0: never.
double disc_disc_time(const Vector& dr, const Vector& dv, double contact);

// A disc of radius `radius` at r with velocity v under gravity g hitting a fixed point p (the
// end of a wall segment, a corner). Without gravity the disc-disc formula with a point of
// radius 0; with gravity |r - p + v t + g t^2 / 2|^2 = radius^2 is a quartic.
double disc_point_time(const Vector& r, const Vector& v, const Vector& g, const Vector& p, double radius);

// A disc inside a circle of radius `reach` = R - a centred at the origin (r is the disc centre
// relative to the circle centre): time when |r(t)| = reach while moving outwards. Without gravity
// the stable quadratic of the course (A t^2 + 2 B t + C = 0); with gravity a quartic, bounded by
// the time after which |g| t^2 / 2 - |v| t - |r| >= reach (the disc must be outside by then).
double disc_in_circle_time(const Vector& r, const Vector& v, const Vector& g, double reach);

// A disc hitting the segment from a to b (either side, only the part between the end points;
// the end points themselves are separate obstacles, see disc_point_time). Signed distance to
// the line d(t) = d0 + (v.n) t + (g.n) t^2 / 2 with n the unit normal; contact when |d| = radius
// while approaching, and only if the foot of the perpendicular lies on the segment then.
double disc_segment_time(const Vector& r, const Vector& v, const Vector& g, const Vector& a, const Vector& b,
                         double radius);

// Every crossing of zero by p (as in first_polynomial_crossing) in [0, t_max], in increasing
// order, at most max_count of them (at most 4 exist); returns how many were written to `out`.
int polynomial_crossings(const double* p, int degree, double t_max, bool rising, double* out, int max_count);

// Is the direction d (from an arc's centre, d != 0) on the arc that starts at the angle `start`
// and runs counter-clockwise through `sweep` radians (0 < sweep <= 2 pi; 2 pi is a full circle)?
bool arc_contains(double start, double sweep, const Vector& d);

// A disc of `radius` at r (relative to the arc's centre) with velocity v under gravity g hitting
// the arc of radius rho (start angle and sweep as in arc_contains) from either side: from inside
// (concave) when |r(t)| rises to rho - radius, from outside (convex) when it falls to
// rho + radius, the contact point's direction r(t) lying on the arc. The end points are separate
// obstacles (disc_point_time). Without gravity |r(t)|^2 is a quadratic in t and the candidates
// are closed-form roots; under gravity a quartic, and a disc may pass through the gap of the arc
// and meet it later from the other side, so every crossing is checked in turn and the earliest
// one on the arc is the contact. A full circle seen from inside is disc_in_circle_time, from
// outside disc_point_time with the point at the centre and radius rho + radius.
double disc_arc_time(const Vector& r, const Vector& v, const Vector& g, double rho, double start, double sweep,
                     double radius);

// A point at x moving at constant speed v between faces lo and hi (either may be +-infinity):
// time to the face ahead, the larger of the times to the two faces (the face behind is reached
// at a negative time, or at -infinity when at rest), so that nothing branches on the sign of v,
// which is random in a gas and would be mispredicted half the time. A point a hair outside by
// rounding gets 0 (leave now); at rest exactly on a face (0/0): never.
inline double straight_face_time(double x, double v, double lo, double hi) {
  const double t = std::max((hi - x) / v, (lo - x) / v);
  return t >= 0 ? t : std::isnan(t) ? kNever : 0.0;
}

// A point (disc centre) leaving the axis-aligned cell [lo, hi] (bounds may be +-infinity).
// Returns the time and which face: axis 0 = x, 1 = y; direction +1 through the upper face,
// -1 through the lower one. Linear, or quadratic per face under gravity (the same penetration
// rule as a wall of radius 0, counted only when leaving).
struct CellExit {
  double time = kNever;
  int axis = 0;
  int direction = 0;
};
CellExit cell_exit_time(const Vector& r, const Vector& v, const Vector& g, const Vector& lo, const Vector& hi);

}  // namespace billiard
