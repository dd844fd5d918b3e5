// Geometry of walls: distances used to check input, to place walls in cells and to find the
// contact normal.
#include "wall_geometry.hpp"

#include "time_of_impact.hpp"

#include <algorithm>
#include <cmath>

namespace billiard {

double distance_to_segment(const Vector& p, const Vector& a, const Vector& b) {
  const Vector ab = b - a;
  const double length2 = ab.squaredNorm();
  const double s = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + s * ab)).norm();
}

Vector closest_point(const WallShape& wall, const Vector& p) {
  switch (wall.kind) {
    case WallKind::Segment: {
      const Vector ab = wall.b - wall.a;
      const double length2 = ab.squaredNorm();
      const double s = length2 > 0 ? std::clamp((p - wall.a).dot(ab) / length2, 0.0, 1.0) : 0.0;
      return wall.a + s * ab;
    }
    case WallKind::Point:
      return wall.a;
    case WallKind::Circle: {
      const Vector d = p - wall.a;
      const double norm = d.norm();
      return norm > 0 ? Vector(wall.a + wall.radius / norm * d) : Vector(wall.a + Vector(wall.radius, 0));
    }
    case WallKind::Arc: {
      // On the arc: radially; off it, the nearer end point (the distance to the circle's points
      // grows with the angle from p's direction).
      const Vector d = p - wall.a;
      const double norm = d.norm();
      if (norm > 0 && arc_contains(wall.start_angle, wall.sweep, d)) return wall.a + wall.radius / norm * d;
      if (wall.sweep >= 2 * M_PI) return arc_point(wall, wall.start_angle);  // (p at the centre)
      const Vector first = arc_point(wall, wall.start_angle);
      const Vector last = arc_point(wall, wall.start_angle + wall.sweep);
      return (first - p).squaredNorm() <= (last - p).squaredNorm() ? first : last;
    }
  }
  return wall.a;
}

double point_rectangle_distance(const Vector& p, const Vector& lo, const Vector& hi) {
  const double dx = std::max({lo.x() - p.x(), 0.0, p.x() - hi.x()});
  const double dy = std::max({lo.y() - p.y(), 0.0, p.y() - hi.y()});
  return std::hypot(dx, dy);
}

namespace {
// Do the segments p1-p2 and q1-q2 cross or touch?
bool segments_meet(const Vector& p1, const Vector& p2, const Vector& q1, const Vector& q2) {
  const double d1 = cross(q2 - q1, p1 - q1);
  const double d2 = cross(q2 - q1, p2 - q1);
  const double d3 = cross(p2 - p1, q1 - p1);
  const double d4 = cross(p2 - p1, q2 - p1);
  return ((d1 <= 0 && d2 >= 0) || (d1 >= 0 && d2 <= 0)) && ((d3 <= 0 && d4 >= 0) || (d3 >= 0 && d4 <= 0));
}
}  // namespace

double segment_rectangle_distance(const Vector& a, const Vector& b, const Vector& lo, const Vector& hi) {
  if (point_rectangle_distance(a, lo, hi) == 0 || point_rectangle_distance(b, lo, hi) == 0) return 0.0;
  const Vector corners[4] = {lo, Vector(hi.x(), lo.y()), hi, Vector(lo.x(), hi.y())};
  for (int k = 0; k < 4; ++k) {
    if (segments_meet(a, b, corners[k], corners[(k + 1) % 4])) return 0.0;
  }
  // Apart: the closest pair involves an end point of the segment or a corner of the rectangle.
  double best = std::min(point_rectangle_distance(a, lo, hi), point_rectangle_distance(b, lo, hi));
  for (const Vector& corner : corners) best = std::min(best, distance_to_segment(corner, a, b));
  return best;
}

Vector arc_point(const WallShape& arc, double angle) {
  return arc.a + arc.radius * Vector(std::cos(angle), std::sin(angle));
}

namespace {
// The angles (within the arc) where its circle is farthest in x or y: 0, pi/2, pi, 3 pi/2.
template <class Visit>
void arc_extremes(const WallShape& arc, Visit visit) {
  for (int quarter = 0; quarter < 4; ++quarter) {
    const double angle = quarter * M_PI / 2;
    const Vector direction(quarter == 0 ? 1.0 : quarter == 2 ? -1.0 : 0.0, quarter == 1 ? 1.0 : quarter == 3 ? -1.0 : 0.0);
    if (arc_contains(arc.start_angle, arc.sweep, direction)) visit(angle, Vector(arc.a + arc.radius * direction));
  }
}
}  // namespace

void arc_bounds(const WallShape& arc, Vector& lo, Vector& hi) {
  if (arc.sweep >= 2 * M_PI) {
    lo = arc.a - Vector::Constant(arc.radius);
    hi = arc.a + Vector::Constant(arc.radius);
    return;
  }
  lo = hi = arc_point(arc, arc.start_angle);
  const Vector last = arc_point(arc, arc.start_angle + arc.sweep);
  lo = lo.cwiseMin(last);
  hi = hi.cwiseMax(last);
  arc_extremes(arc, [&](double, const Vector& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  });
}

double arc_rectangle_distance(const WallShape& arc, const Vector& lo, const Vector& hi) {
  const bool full = arc.sweep >= 2 * M_PI;
  const Vector first = arc_point(arc, arc.start_angle);
  const Vector last = arc_point(arc, arc.start_angle + arc.sweep);
  if (!full && (point_rectangle_distance(first, lo, hi) == 0 || point_rectangle_distance(last, lo, hi) == 0)) return 0.0;
  // Does the arc cross a side of the rectangle? The circle meets the line x = X (or y = Y) where
  // the other coordinate is the centre's +- sqrt(radius^2 - (X - centre)^2).
  for (int axis = 0; axis < 2; ++axis) {
    const int other = 1 - axis;
    for (const double side : {lo[axis], hi[axis]}) {
      const double offset = side - arc.a[axis];
      const double half = arc.radius * arc.radius - offset * offset;
      if (half < 0) continue;
      for (const double sign : {-1.0, 1.0}) {
        Vector d;
        d[axis] = offset;
        d[other] = sign * std::sqrt(half);
        const double along = arc.a[other] + d[other];
        if (along >= lo[other] && along <= hi[other] && (d.squaredNorm() == 0 || arc_contains(arc.start_angle, arc.sweep, d))) return 0.0;
      }
    }
  }
  // Apart: the closest pair is an end point of the arc with the rectangle, a corner with the arc,
  // or a point of the arc where its normal is parallel to a side (its extremes in x and y).
  auto to_arc = [&](const Vector& p) {
    const WallShape& wall = arc;
    return (closest_point(wall, p) - p).norm();
  };
  double best = kNever;
  if (!full) best = std::min(point_rectangle_distance(first, lo, hi), point_rectangle_distance(last, lo, hi));
  for (const Vector& corner : {lo, Vector(hi.x(), lo.y()), hi, Vector(lo.x(), hi.y())}) best = std::min(best, to_arc(corner));
  arc_extremes(arc, [&](double, const Vector& p) { best = std::min(best, point_rectangle_distance(p, lo, hi)); });
  return best;
}

bool inside_pieces(const std::vector<WallShape>& pieces, const Vector& p) {
  bool inside = false;
  // One y-monotone piece from u to v: crossed if its ends lie on either side of the ray's line
  // (an end exactly on it counts as below, as in inside_polygon), at x = x_at.
  auto cross_piece = [&](const Vector& u, const Vector& v, auto x_at) {
    if ((u.y() > p.y()) != (v.y() > p.y()) && p.x() < x_at()) inside = !inside;
  };
  for (const WallShape& piece : pieces) {
    if (piece.kind == WallKind::Segment) {
      const Vector& u = piece.a;
      const Vector& v = piece.b;
      cross_piece(u, v, [&] { return (u.x() - v.x()) * (p.y() - v.y()) / (u.y() - v.y()) + v.x(); });
      continue;
    }
    if (piece.kind != WallKind::Arc) continue;
    // Split at the highest and lowest points of the circle (angles pi/2 + k pi) inside the arc.
    const double end = piece.start_angle + piece.sweep;
    double from = piece.start_angle;
    const Vector first = arc_point(piece, from);
    Vector u = first;
    while (from < end) {
      double to = (std::floor((from - M_PI / 2) / M_PI) + 1) * M_PI + M_PI / 2;  // next split after `from`
      if (to <= from) to += M_PI;
      const bool last = to >= end;
      if (last) to = end;
      // A whole circle ends exactly where it starts: arc_point(start + 2 pi) differs from it by
      // rounding, which would leave a band of one ulp in y that the ray crosses once only (a point
      // there taken for inside an obstacle).
      const Vector v = last ? (piece.sweep >= 2 * M_PI ? first : arc_point(piece, end)) : arc_point(piece, to);
      const double side = std::cos(0.5 * (from + to)) >= 0 ? 1.0 : -1.0;  // right or left half
      cross_piece(u, v, [&] {
        const double dy = p.y() - piece.a.y();
        return piece.a.x() + side * std::sqrt(std::max(piece.radius * piece.radius - dy * dy, 0.0));
      });
      from = to;
      u = v;
    }
  }
  return inside;
}

bool inside_polygon(const Coordinates& vertices, const Vector& p) {
  bool inside = false;
  const Eigen::Index n = vertices.rows();
  for (Eigen::Index k = 0, previous = n - 1; k < n; previous = k++) {
    const double xk = vertices(k, 0), yk = vertices(k, 1);
    const double xp = vertices(previous, 0), yp = vertices(previous, 1);
    if ((yk > p.y()) != (yp > p.y()) && p.x() < (xp - xk) * (p.y() - yk) / (yp - yk) + xk) inside = !inside;
  }
  return inside;
}

}  // namespace billiard
