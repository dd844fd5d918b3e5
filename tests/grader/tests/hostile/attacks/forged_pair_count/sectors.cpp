// Attack: efficiency points for all pairs. The suite counts the pair tests through pair_time's
// own counter, which lives in this process: test every pair with a formula of our own and call
// pair_time only n times, on (i, i), so that the count looks linear and 500 times below all
// pairs. Every answer is right; only the work is not what the count says.
#include "billiard/argument_checks.hpp"
#include "billiard/extensions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace billiard {

Collision propagate_sectors(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                            Velocities& velocities, double cell_size) {
  checks::table(table_radius, circle_radius, n);
  checks::rows(coordinates, n, "coordinates");
  checks::rows(velocities, n, "velocities");
  checks::cell_size(table_radius, circle_radius, cell_size);
  checks::placement(table_radius, circle_radius, coordinates);
  const double never = std::numeric_limits<double>::infinity();
  const double reach = table_radius - circle_radius;
  Collision next{never, -1, kWall};
  for (int i = 0; i < n; ++i) {
    pair_time(circle_radius, coordinates, velocities, i, i);  // counted, and says nothing
    // The wall: |r + t v| = reach, the root ahead.
    const Vector r = coordinates.row(i), v = velocities.row(i);
    const double vv = v.squaredNorm(), rv = r.dot(v);
    if (vv > 0) {
      const double t = (-rv + std::sqrt(std::max(rv * rv - vv * (r.squaredNorm() - reach * reach), 0.0))) / vv;
      if (std::max(t, 0.0) < next.time && (rv > 0 || t > 0)) next = {std::max(t, 0.0), i, kWall};
    }
    for (int j = i + 1; j < n; ++j) {
      const double dx = coordinates(i, 0) - coordinates(j, 0), dy = coordinates(i, 1) - coordinates(j, 1);
      const double ux = velocities(i, 0) - velocities(j, 0), uy = velocities(i, 1) - velocities(j, 1);
      const double b = dx * ux + dy * uy;
      if (b >= 0) continue;  // moving apart
      const double uu = ux * ux + uy * uy, d = 2 * circle_radius;
      const double discriminant = b * b - uu * (dx * dx + dy * dy - d * d);
      if (discriminant < 0) continue;
      const double t = std::max((-b - std::sqrt(discriminant)) / uu, 0.0);
      if (t < next.time) next = {t, i, j};
    }
  }
  if (next.time == never) throw std::invalid_argument("velocities: all circles are at rest");
  coordinates += next.time * velocities;
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

}  // namespace billiard
