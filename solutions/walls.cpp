// Task 8, reference solution: one event step with straight walls inside the table.
//
// The same event loop as propagate (task 4), with more kinds of event. Besides the table and
// the pairs of circles, each wall k offers three obstacles:
//   - its two faces (the segment from a to b, hit on either side), and
//   - its two end points a and b, which a circle passing the end of the wall hits like a circle
//     of radius 0.
// Every one of them reflects the circle's velocity along a normal and is reported as
// wall_id(k). As in propagate, nothing here uses a time epsilon: whether a circle is moving
// towards an obstacle decides whether it can hit it, so a circle that has just bounced off
// (and touches by rounding) never hits the same obstacle again at once.
#include "billiard/argument_checks.hpp"
#include "billiard/extensions.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace billiard {
namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();

// Time until the circle at r, moving with v, touches the table's rim: |r + v t| = R - a.
// Exactly as in propagate: the positive root of A t^2 + 2 B t + C = 0, in the form without
// cancellation, and t = 0 for a circle a rounding hair outside that moves outward.
double time_to_table(const Vector& r, const Vector& v, double reach) {
  const double A = v.squaredNorm();
  if (A == 0) return kNever;
  const double B = r.dot(v);
  const double C = r.squaredNorm() - reach * reach;
  if (C >= 0 && B >= 0) return B > 0 ? 0.0 : kNever;
  const double root = std::sqrt(std::max(B * B - A * C, 0.0));
  const double t = B > 0 ? -C / (B + root) : (-B + root) / A;
  return std::max(t, 0.0);
}

// Time until a circle whose centre is at d from a fixed point (d = r - p), moving with v,
// touches it: |d + v t| = contact. The pair formula of propagate with the point at rest and
// contact = circle_radius in place of the diameter: only if approaching (b = d.v < 0), the
// earlier root c / (-b + sqrt(b^2 - v.v c)), clamped to 0 when rounding leaves c < 0.
double time_to_point(const Vector& d, const Vector& v, double contact) {
  const double b = d.dot(v);
  if (b >= 0) return kNever;  // moving away, or sliding past: no hit
  const double c = d.squaredNorm() - contact * contact;
  const double discriminant = b * b - v.squaredNorm() * c;
  if (discriminant < 0) return kNever;  // passes beside the point
  return std::max(c / (-b + std::sqrt(discriminant)), 0.0);
}

// Unit normal of a wall of non-zero length (either of the two; the sign does not matter).
Vector unit_normal(const Wall& wall) {
  const Vector along = (wall.b - wall.a).normalized();
  return Vector(-along(1), along(0));
}

// Time until the circle touches a face of the wall, away from its end points. The signed
// distance of the centre from the wall's line is d(t) = d0 + (v.n) t; the circle touches a
// face when |d(t)| = contact while moving towards the line (d0 and v.n of opposite signs),
// i.e. at t = (|d0| - contact) / |v.n|, and only if the foot of the perpendicular from the
// centre then lies between a and b. Otherwise the circle passes beyond an end, where the end
// point (time_to_point) catches it. A circle sliding parallel to the wall (v.n = 0) never
// touches its face.
double time_to_face(const Vector& r, const Vector& v, const Wall& wall, double contact) {
  const double length = (wall.b - wall.a).norm();
  if (length == 0) return kNever;  // a wall of zero length is only a point
  const Vector n = unit_normal(wall);
  const double d0 = (r - wall.a).dot(n);
  const double vn = v.dot(n);
  if (!(d0 * vn < 0)) return kNever;  // moving away from the line, or parallel to it
  // A circle touching the face after a bounce has |d0| = contact up to rounding, but it then
  // moves away and was rejected above. Rounding can leave an approaching circle a hair inside
  // (|d0| < contact): it collides now.
  const double t = std::max((std::abs(d0) - contact) / std::abs(vn), 0.0);
  const double foot = (r + t * v - wall.a).dot(wall.b - wall.a) / length;  // along the wall from a
  return foot >= 0 && foot <= length ? t : kNever;
}

// What a circle hits: the table, a face of walls[k], or an end point of walls[k].
enum class Obstacle { table, face, point, circle };

struct Event {
  double time = kNever;
  int circle = -1;
  int other = kWall;  // kWall, wall_id(k) or a circle's row
  Obstacle obstacle = Obstacle::table;
  Vector point = Vector::Zero();  // the end point, for Obstacle::point
};

}  // namespace

Collision propagate_walls(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                          Velocities& velocities, const std::vector<Wall>& walls) {
  checks::table(table_radius, circle_radius, n);
  checks::rows(coordinates, n, "coordinates");
  checks::rows(velocities, n, "velocities");
  checks::placement(table_radius, circle_radius, coordinates);
  checks::walls(table_radius, walls);
  checks::clear_of_walls(table_radius, circle_radius, coordinates, walls);

  const double reach = table_radius - circle_radius;
  const double diameter = 2 * circle_radius;
  const int wall_count = static_cast<int>(walls.size());

  // The earliest event of all: table, walls (faces and end points), pairs.
  Event next;
  auto consider = [&next](const Event& candidate) {
    if (candidate.time < next.time) next = candidate;
  };
  for (int i = 0; i < n; ++i) {
    const Vector r = coordinates.row(i);
    const Vector v = velocities.row(i);
    consider({time_to_table(r, v, reach), i, kWall, Obstacle::table, Vector::Zero()});
    for (int k = 0; k < wall_count; ++k) {
      consider({time_to_face(r, v, walls[k], circle_radius), i, wall_id(k), Obstacle::face, Vector::Zero()});
      for (const Vector& p : {walls[k].a, walls[k].b}) {
        consider({time_to_point(r - p, v, circle_radius), i, wall_id(k), Obstacle::point, p});
      }
    }
    for (int j = i + 1; j < n; ++j) {
      const double t = time_to_point(r - coordinates.row(j), v - velocities.row(j), diameter);
      consider({t, i, j, Obstacle::circle, Vector::Zero()});
    }
  }
  if (next.time == kNever) {
    throw std::invalid_argument(n == 0 ? "n = 0: with no circles there is no collision to propagate to"
                                       : "velocities: all circles are at rest, so no collision will ever happen");
  }

  // Every circle flies straight to the moment of the event.
  coordinates += next.time * velocities;

  const int i = next.circle;
  if (next.obstacle == Obstacle::circle) {
    // Equal masses: exchange the velocity components along the line of centres, as in propagate.
    const int j = next.other;
    const Vector normal = (coordinates.row(j) - coordinates.row(i)).normalized();
    const Vector exchange = (velocities.row(i) - velocities.row(j)).dot(normal) * normal;
    velocities.row(i) -= exchange;
    velocities.row(j) += exchange;
    return {next.time, i, j};
  }
  // A fixed obstacle: reverse the velocity's component along its unit normal at contact.
  Vector normal;
  if (next.obstacle == Obstacle::table) {
    normal = coordinates.row(i).normalized();
  } else if (next.obstacle == Obstacle::face) {
    normal = unit_normal(walls[static_cast<std::size_t>(-2 - next.other)]);  // other = wall_id(k) = -2 - k
  } else {
    normal = (coordinates.row(i) - next.point).normalized();  // from the end point to the centre
  }
  velocities.row(i) -= 2 * velocities.row(i).dot(normal) * normal;
  return {next.time, i, next.other};
}

}  // namespace billiard
