// Time-of-impact solvers. Every function is pure and returns kNever for "no future contact".
#include "time_of_impact.hpp"

#include <algorithm>
#include <cmath>

namespace billiard {

QuadraticRoots solve_quadratic(double a, double b, double c) {
  if (a == 0) {
    if (b == 0) return {};
    const double t = -c / b;
    return {1, t, t};
  }
  const double discriminant = b * b - 4 * a * c;
  if (discriminant < 0) return {};
  // Stable form (Numerical Recipes 5.6): q has the sign of -b, so b + sign(b) sqrt(...) never
  // cancels; the textbook (-b +- sqrt) / 2a loses all digits of the small root when 4ac << b^2,
  // which is exactly the case of two objects that have just touched.
  const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
  if (q == 0) return {2, 0.0, 0.0};  // b = 0 and c = 0: double root at 0
  double r1 = q / a;
  double r2 = c / q;
  if (r1 > r2) std::swap(r1, r2);
  return {2, r1, r2};
}

double first_upward_root(double a, double b, double c) {
  // h(t) = a t^2 + b t + c. h'(t) = 2 a t + b.
  if (a == 0) {
    if (b <= 0) return kNever;  // not rising: never starts to overlap (b = 0: grazing)
    return std::max(-c / b, 0.0);  // c > 0: rounding overlap while moving in: now
  }
  const QuadraticRoots roots = solve_quadratic(a, b, c);
  if (roots.count == 0) {
    // h never vanishes: always positive when a > 0 (inside for good, which only rounding can
    // cause: collide now), always negative when a < 0 (never touches).
    return a > 0 ? 0.0 : kNever;
  }
  // A convex h (a > 0) rises through its larger root, a concave one through its smaller root.
  const double up = a > 0 ? roots.hi : roots.lo;
  const double down = a > 0 ? roots.lo : roots.hi;
  if (a < 0 && roots.lo == roots.hi) return kNever;  // touches at the apex only: grazing
  if (up >= 0) return up;
  if (a > 0) return 0.0;  // both roots behind us: h > 0 and rising now
  // Concave, rose through zero in the past: overlapping now if the other root is ahead. Collide
  // now only if still moving in (b > 0); moving out, a concave h never comes back.
  return (down > 0 && b > 0) ? 0.0 : kNever;
}

namespace {

double horner(const double* p, int degree, double t) {
  double s = p[degree];
  for (int k = degree - 1; k >= 0; --k) s = s * t + p[k];
  return s;
}

// Bisection of a sign change of p on [lo, hi] (p(lo) = f_lo and p(hi) of the other sign) down to
// adjacent doubles. Returns the end on the far side of the root (where p has the sign of p(hi)),
// so that the caller's event happens at contact or a rounding error after it.
double bisect(const double* p, int degree, double lo, double hi, double f_lo) {
  // Halving reaches adjacent doubles within log2(hi / root) + 53 steps, up to ~2150 for a bracket
  // from a denormal to 1e308 (weak gravity bounds the time of impact by ~|v| / |g|, far beyond
  // it): a smaller cap stopped short and let discs through walls.
  for (int iteration = 0; iteration < 2200; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const double f_mid = horner(p, degree, mid);
    if ((f_mid < 0) == (f_lo < 0) && f_mid != 0) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return hi;
}

// Sorted real roots of p inside the open interval (lo, hi), degree <= 4. Quadratics directly;
// higher degrees through the roots of p', which split (lo, hi) into monotone pieces.
int roots_in(const double* p, int degree, double lo, double hi, double* out) {
  while (degree > 0 && p[degree] == 0) --degree;
  if (degree <= 0) return 0;
  int count = 0;
  if (degree <= 2) {
    const QuadraticRoots r = solve_quadratic(degree == 2 ? p[2] : 0.0, p[1], p[0]);
    if (r.count >= 1 && r.lo > lo && r.lo < hi) out[count++] = r.lo;
    if (r.count == 2 && r.hi != r.lo && r.hi > lo && r.hi < hi) out[count++] = r.hi;
    return count;
  }
  double derivative[4];
  for (int k = 1; k <= degree; ++k) derivative[k - 1] = k * p[k];
  double critical[4];
  const int n_critical = roots_in(derivative, degree - 1, lo, hi, critical);
  double x0 = lo;
  double f0 = horner(p, degree, lo);
  for (int k = 0; k <= n_critical; ++k) {
    const double x1 = k < n_critical ? critical[k] : hi;
    const double f1 = horner(p, degree, x1);
    if ((f0 < 0 && f1 > 0) || (f0 > 0 && f1 < 0)) {
      out[count++] = bisect(p, degree, x0, x1, f0);
    } else if (f1 == 0 && k < n_critical) {
      out[count++] = x1;  // double root at a critical point
    }
    x0 = x1;
    f0 = f1;
  }
  return count;
}

}  // namespace

int polynomial_crossings(const double* p, int degree, double t_max, bool rising, double* out, int max_count) {
  while (degree > 0 && p[degree] == 0) --degree;
  if (degree <= 0 || !(t_max > 0) || max_count <= 0) return 0;
  // Monotone pieces of p on [0, t_max]: between consecutive roots of p'.
  double derivative[4];
  for (int k = 1; k <= degree; ++k) derivative[k - 1] = k * p[k];
  double critical[4];
  const int n_critical = roots_in(derivative, degree - 1, 0.0, t_max, critical);
  int count = 0;
  double x0 = 0.0;
  double f0 = horner(p, degree, 0.0);
  for (int k = 0; k <= n_critical; ++k) {
    const double x1 = k < n_critical ? critical[k] : t_max;
    const double f1 = horner(p, degree, x1);
    const double s0 = rising ? f0 : -f0;  // flip so that we always look for an upward crossing
    const double s1 = rising ? f1 : -f1;
    double found = kNever;
    if (s0 < 0 && s1 >= 0) {
      found = s1 == 0 ? x1 : bisect(p, degree, x0, x1, f0);
    } else if (s0 == 0 && s1 > 0 && k > 0 && (count == 0 || out[count - 1] != x0)) {
      found = x0;
    }
    if (found < kNever) {
      out[count++] = found;
      if (count == max_count) return count;
    }
    x0 = x1;
    f0 = f1;
  }
  return count;
}

double first_polynomial_crossing(const double* p, int degree, double t_max, bool rising) {
  double t = kNever;
  polynomial_crossings(p, degree, t_max, rising, &t, 1);
  return t;
}

double disc_disc_time(const Vector& dr, const Vector& dv, double contact) {
  const double b = dr.dot(dv);
  // Flying apart, or side by side (grazing): no collision.
  if (b >= 0 || moving_along(b, dr.squaredNorm(), dv.squaredNorm())) return kNever;
  const double c = dr.squaredNorm() - contact * contact;
  const double discriminant = b * b - dv.squaredNorm() * c;
  if (discriminant < 0) return kNever;  // they miss each other
  // Earlier root of dv.dv t^2 + 2 b t + c = 0 without cancellation; c < 0 (rounding overlap
  // while approaching) gives a negative time: collide now.
  return std::max(c / (-b + std::sqrt(discriminant)), 0.0);
}

double disc_point_time(const Vector& r, const Vector& v, const Vector& g, const Vector& p, double radius) {
  const Vector d = r - p;
  if (g.x() == 0 && g.y() == 0) return disc_disc_time(d, v, radius);
  // f(t) = |d + v t + g t^2/2|^2 - radius^2
  //      = (g.g/4) t^4 + (v.g) t^3 + (v.v + d.g) t^2 + 2 (d.v) t + d.d - radius^2.
  // Contact is a downward crossing of f. Rounding overlap (f(0) <= 0) while approaching: now.
  const double f0 = d.squaredNorm() - radius * radius;
  const double b = d.dot(v);
  const double df0 = moving_along(b, d.squaredNorm(), v.squaredNorm()) ? 0.0 : 2 * b;
  if (f0 <= 0) {
    if (df0 < 0 || (df0 == 0 && v.squaredNorm() + d.dot(g) < 0)) return 0.0;
  }
  // Beyond t_max, |d(t)| >= |g| t^2/2 - |v| t - |d| > radius: no contact can happen later.
  const QuadraticRoots bound = solve_quadratic(0.5 * g.norm(), -v.norm(), -(d.norm() + radius));
  const double t_max = bound.hi;
  const double poly[5] = {f0, df0, v.squaredNorm() + d.dot(g), v.dot(g), 0.25 * g.squaredNorm()};
  const double t = first_polynomial_crossing(poly, 4, t_max, false);
  if (t < kNever || f0 > 0) return t;
  // Found a hair inside and moving out: if too slowly to get clear before gravity brings it back
  // (f never rises above zero, so there is no downward crossing to find), it is in contact, as in
  // disc_in_circle_time: collide now. f is highest at the first root of f' (or at t_max).
  const double slope[4] = {df0, 2 * poly[2], 3 * poly[3], 4 * poly[4]};
  double turning[3];
  const double highest = roots_in(slope, 3, 0.0, t_max, turning) > 0 ? turning[0] : t_max;
  return horner(poly, 4, highest) <= 0 ? 0.0 : kNever;
}

double disc_in_circle_time(const Vector& r, const Vector& v, const Vector& g, double reach) {
  const double C = r.squaredNorm() - reach * reach;  // <= 0 inside
  const double B = r.dot(v);
  if (g.x() == 0 && g.y() == 0) {
    // |r + v t| = reach: A t^2 + 2 B t + C = 0, A = v.v. C <= 0, so the roots have opposite
    // signs; the positive one is (-B + sqrt(B^2 - A C)) / A, written as -C / (B + sqrt(...)) when
    // B > 0 to avoid cancellation (the course's task 4).
    const double A = v.squaredNorm();
    if (A == 0) return kNever;
    // On or a hair outside and not moving in: bounce now. Moving along the wall (B = 0) is no
    // graze here: inside a circle a tangent leads straight out.
    if (C >= 0 && B >= 0) return 0.0;
    const double root = std::sqrt(std::max(B * B - A * C, 0.0));
    const double t = B > 0 ? -C / (B + root) : (-B + root) / A;
    return std::max(t, 0.0);
  }
  // f(t) = |r + v t + g t^2/2|^2 - reach^2, upward crossing; quartic as in disc_point_time.
  // Moving along the rim (moving_along, as in disc_point_time and disc_arc_time, which must agree
  // with this function) is neither moving in nor out.
  const double slope0 = moving_along(B, r.squaredNorm(), v.squaredNorm()) ? 0.0 : 2 * B;
  const double second = v.squaredNorm() + r.dot(g);
  if (C >= 0 && (slope0 > 0 || (slope0 == 0 && second > 0))) return 0.0;
  // Under gravity every disc reaches the wall: by t_max, |r(t)| >= |g| t^2/2 - |v| t - |r| >=
  // reach, so f(t_max) >= 0 and the crossing lies in [0, t_max]. The bound is exact for a disc
  // dropped from rest at the centre, where rounding can leave f(t_max) a hair below zero: a
  // margin of 1e-9 keeps the crossing inside.
  const QuadraticRoots bound = solve_quadratic(0.5 * g.norm(), -v.norm(), -(r.norm() + reach));
  const double t_max = bound.hi * (1 + 1e-9);
  const double poly[5] = {C, slope0, second, v.dot(g), 0.25 * g.squaredNorm()};
  if (C >= 0) {
    // A hair outside and moving in, so slowly that f turns up again before it gets below zero
    // (a disc sliding along the rim after an inelastic hit: its normal speed is rounding, and
    // gravity presses it outwards): it never gets inside, so it is in contact now. Without this
    // the first upward crossing found would be a later one, after the disc has flown on outside
    // the wall and come back in.
    const double slope[4] = {slope0, 2 * second, 3 * poly[3], 4 * poly[4]};
    double turning[3];
    const double lowest = roots_in(slope, 3, 0.0, t_max, turning) > 0 ? turning[0] : t_max;
    if (horner(poly, 4, lowest) >= 0) return 0.0;
  }
  const double t = first_polynomial_crossing(poly, 4, t_max, true);
  // (A hair outside whose dip below zero rounding hides from the bisection: in contact too.)
  return t == kNever && C >= 0 ? 0.0 : t;
}

double disc_segment_time(const Vector& r, const Vector& v, const Vector& g, const Vector& a, const Vector& b,
                         double radius) {
  const Vector along = b - a;
  const double length = along.norm();
  if (length == 0) return kNever;
  const Vector u = along / length;  // unit tangent
  const Vector n = perp(u);         // unit normal
  const Vector d = r - a;
  const double d0 = d.dot(n);   // signed distance of the centre from the line
  const double vn = v.dot(n);
  const double gn = g.dot(n);
  const double side = d0 >= 0 ? 1.0 : -1.0;  // the side the disc is on
  // Own side: penetration h(t) = radius - side d(t) = -side (gn/2 t^2 + vn t) + radius - side d0.
  double best = kNever;
  const double t_own = first_upward_root(-side * 0.5 * gn, -side * vn, radius - side * d0);
  auto on_segment = [&](double t) {
    const double s = d.dot(u) + v.dot(u) * t + 0.5 * g.dot(u) * t * t;  // foot of the normal
    return s >= 0 && s <= length;
  };
  if (t_own < kNever && on_segment(t_own)) best = t_own;
  // Other side: under gravity a disc can pass the end of the segment and come back to hit its
  // other face. Penetration from that side, h(t) = radius + side d(t), starts positive, so it
  // must first dip below zero and rise again: a convex h with both roots ahead, contact at the
  // larger root.
  const double ca = side * 0.5 * gn;
  if (ca > 0) {
    const QuadraticRoots roots = solve_quadratic(ca, side * vn, radius + side * d0);
    if (roots.count == 2 && roots.lo > 0 && roots.hi < best && on_segment(roots.hi)) best = roots.hi;
  }
  return best;
}

bool arc_contains(double start, double sweep, const Vector& d) {
  constexpr double kTurn = 2 * M_PI;
  if (sweep >= kTurn) return true;
  double angle = std::atan2(d.y(), d.x()) - start;
  angle -= kTurn * std::floor(angle / kTurn);  // in [0, 2 pi)
  return angle <= sweep;
}

double disc_arc_time(const Vector& r, const Vector& v, const Vector& g, double rho, double start, double sweep,
                     double radius) {
  // Contact with the circle of the arc: |r(t)| = outer (disc outside the circle, convex side) or
  // |r(t)| = inner (disc inside, concave side), where r(t) = r + v t + g t^2 / 2. Squared:
  // f(t) = |r(t)|^2 - reach^2 = (g.g/4) t^4 + (v.g) t^3 + (v.v + r.g) t^2 + 2 (r.v) t + r.r - reach^2.
  // The contact counts only if the direction r(t) lies on the arc; otherwise the disc passes
  // through the gap (or meets an end point, a separate wall) and may meet the other face later.
  const double outer = rho + radius;
  const double inner = rho - radius;  // <= 0: the disc is too large to touch the concave face
  const bool outside = r.squaredNorm() >= rho * rho;
  auto on_arc = [&](double t) { return arc_contains(start, sweep, Vector(r + v * t + (0.5 * t * t) * g)); };
  const double A = v.squaredNorm();
  const double B = r.dot(v);
  const double C = r.squaredNorm();
  if (g.x() == 0 && g.y() == 0) {
    if (A == 0) return kNever;
    if (outside) {
      // Convex face: |r(t)| falls to outer at the earlier root (the centre as a disc of radius
      // rho; rounding overlap while approaching: now).
      const double t = disc_disc_time(r, v, outer);
      if (t < kNever && on_arc(t)) return t;
      // Missed the arc (or the circle): through the gap, the line dips below inner and meets
      // the concave face on its way out, at the later root of A t^2 + 2 B t + C - inner^2.
      if (inner > 0) {
        const QuadraticRoots roots = solve_quadratic(A, 2 * B, C - inner * inner);
        if (roots.count == 2 && roots.lo > 0 && on_arc(roots.hi)) return roots.hi;
      }
      return kNever;
    }
    // Inside: a straight line leaving the circle never comes back, so only the concave face
    // (penetration |r(t)|^2 - inner^2 rising through zero; rounding overlap moving out: now).
    if (!(inner > 0)) return kNever;
    const double t = first_upward_root(A, 2 * B, C - inner * inner);
    return t < kNever && on_arc(t) ? t : kNever;
  }
  // Gravity. Contact now (rounding overlap, moving in) is decided as for the full circle.
  if (outside) {
    if (disc_point_time(r, v, g, Vector::Zero(), outer) == 0 && on_arc(0)) return 0.0;
  } else if (inner > 0 && disc_in_circle_time(r, v, g, inner) == 0 && on_arc(0)) {
    return 0.0;
  }
  // Later contacts: every crossing before t_max (beyond it |r(t)| >= |g| t^2/2 - |v| t - |r| >
  // outer for good), the earliest on the arc. Moving along the circle (moving_along) counts as
  // neither approaching nor receding, as in disc_point_time.
  const QuadraticRoots bound = solve_quadratic(0.5 * g.norm(), -v.norm(), -(r.norm() + outer));
  const double t_max = bound.hi;
  const double slope = moving_along(B, C, A) ? 0.0 : 2 * B;
  const double second = A + r.dot(g);
  double best = kNever;
  double crossings[4];
  const double convex[5] = {C - outer * outer, slope, second, v.dot(g), 0.25 * g.squaredNorm()};
  for (int k = 0, n = polynomial_crossings(convex, 4, t_max, false, crossings, 4); k < n; ++k) {
    if (on_arc(crossings[k])) {
      best = crossings[k];
      break;
    }
  }
  if (inner > 0) {
    const double concave[5] = {C - inner * inner, slope, second, v.dot(g), 0.25 * g.squaredNorm()};
    for (int k = 0, n = polynomial_crossings(concave, 4, t_max, true, crossings, 4); k < n && crossings[k] < best; ++k) {
      if (on_arc(crossings[k])) {
        best = crossings[k];
        break;
      }
    }
  }
  return best;
}

CellExit cell_exit_time(const Vector& r, const Vector& v, const Vector& g, const Vector& lo, const Vector& hi) {
  CellExit exit;
  for (int axis = 0; axis < 2; ++axis) {
    if (g[axis] == 0) {  // no acceleration along this axis (gravity along the other one): a line
      const double t = straight_face_time(r[axis], v[axis], lo[axis], hi[axis]);
      if (t < exit.time) exit = {t, axis, v[axis] > 0 ? +1 : -1};
      continue;
    }
    // Leaving through the upper face: h = x(t) - hi rises through zero; lower face: lo - x(t).
    if (hi[axis] < kNever) {
      const double t = first_upward_root(0.5 * g[axis], v[axis], r[axis] - hi[axis]);
      if (t < exit.time) exit = {t, axis, +1};
    }
    if (lo[axis] > -kNever) {
      const double t = first_upward_root(-0.5 * g[axis], -v[axis], lo[axis] - r[axis]);
      if (t < exit.time) exit = {t, axis, -1};
    }
  }
  return exit;
}

}  // namespace billiard
