// Walls: the fixed obstacles discs bounce off. Three shapes cover every container the engine
// supports: straight segments (a box is four, a polygon one per side), points (the end points
// of segments, which discs passing a free end or a concave corner hit), and the circular table
// (discs inside a circle). Walls have infinite mass and inertia.
#pragma once

#include "billiard/engine/vec2.hpp"

#include <vector>

namespace billiard {

enum class WallKind : int { Segment, Point, Circle };

// One wall. Segment: from `a` to `b`, hit on either face. Point: at `a`. Circle: centre `a`,
// radius `radius`, discs live inside it.
struct WallShape {
  WallKind kind = WallKind::Point;
  Vec2 a = Vec2::Zero();
  Vec2 b = Vec2::Zero();
  double radius = 0.0;
};

// Closest point of a wall to the point p (for a circle: on its rim, towards p).
Vec2 closest_point(const WallShape& wall, const Vec2& p);

// Distance from p to the segment a-b.
double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b);

// Distance between the segment a-b and the axis-aligned rectangle [lo, hi] (0 if they meet).
double segment_rectangle_distance(const Vec2& a, const Vec2& b, const Vec2& lo, const Vec2& hi);

// Distance between the point p and the rectangle [lo, hi] (0 inside).
double point_rectangle_distance(const Vec2& p, const Vec2& lo, const Vec2& hi);

// Even-odd rule: is p inside the closed polygon with these vertices (N by 2)?
bool inside_polygon(const Points& vertices, const Vec2& p);

}  // namespace billiard
