// Geometry of walls: distances used to check input, to place walls in cells and to find the
// contact normal.
#include "billiard/engine/wall.hpp"

#include <algorithm>
#include <cmath>

namespace billiard {

double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double s = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + s * ab)).norm();
}

Vec2 closest_point(const WallShape& wall, const Vec2& p) {
  switch (wall.kind) {
    case WallKind::Segment: {
      const Vec2 ab = wall.b - wall.a;
      const double length2 = ab.squaredNorm();
      const double s = length2 > 0 ? std::clamp((p - wall.a).dot(ab) / length2, 0.0, 1.0) : 0.0;
      return wall.a + s * ab;
    }
    case WallKind::Point:
      return wall.a;
    case WallKind::Circle: {
      const Vec2 d = p - wall.a;
      const double norm = d.norm();
      return norm > 0 ? Vec2(wall.a + wall.radius / norm * d) : Vec2(wall.a + Vec2(wall.radius, 0));
    }
  }
  return wall.a;
}

double point_rectangle_distance(const Vec2& p, const Vec2& lo, const Vec2& hi) {
  const double dx = std::max({lo.x() - p.x(), 0.0, p.x() - hi.x()});
  const double dy = std::max({lo.y() - p.y(), 0.0, p.y() - hi.y()});
  return std::hypot(dx, dy);
}

namespace {
// Do the segments p1-p2 and q1-q2 cross or touch?
bool segments_meet(const Vec2& p1, const Vec2& p2, const Vec2& q1, const Vec2& q2) {
  const double d1 = cross(q2 - q1, p1 - q1);
  const double d2 = cross(q2 - q1, p2 - q1);
  const double d3 = cross(p2 - p1, q1 - p1);
  const double d4 = cross(p2 - p1, q2 - p1);
  return ((d1 <= 0 && d2 >= 0) || (d1 >= 0 && d2 <= 0)) && ((d3 <= 0 && d4 >= 0) || (d3 >= 0 && d4 <= 0));
}
}  // namespace

double segment_rectangle_distance(const Vec2& a, const Vec2& b, const Vec2& lo, const Vec2& hi) {
  if (point_rectangle_distance(a, lo, hi) == 0 || point_rectangle_distance(b, lo, hi) == 0) return 0.0;
  const Vec2 corners[4] = {lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y())};
  for (int k = 0; k < 4; ++k) {
    if (segments_meet(a, b, corners[k], corners[(k + 1) % 4])) return 0.0;
  }
  // Apart: the closest pair involves an end point of the segment or a corner of the rectangle.
  double best = std::min(point_rectangle_distance(a, lo, hi), point_rectangle_distance(b, lo, hi));
  for (const Vec2& corner : corners) best = std::min(best, distance_to_segment(corner, a, b));
  return best;
}

bool inside_polygon(const Points& vertices, const Vec2& p) {
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
