// Walls: the fixed obstacles discs bounce off. Four shapes cover every container the engine
// supports: straight segments (a box is four, a polygon one per side), circular arcs (curved
// outlines such as a stadium, disc obstacles), points (the end points of segments and arcs,
// which discs passing a free end or a concave corner hit), and the circular table (discs inside
// a circle). Walls have infinite mass and inertia.
#pragma once

#include "billiard/engine/plane.hpp"

namespace billiard {

enum class WallKind : int { Segment, Point, Circle, Arc };

// One wall. Segment: from `a` to `b`, hit on either face. Point: at `a`. Circle: centre `a`,
// radius `radius`, discs live inside it. Arc: centre `a`, radius `radius`, from the angle
// `start_angle` counter-clockwise through `sweep` radians (0 < sweep <= 2 pi; 2 pi is a full
// circle), hit on either face (from inside the circle or from outside).
struct WallShape {
  WallKind kind = WallKind::Point;
  Vector a = Vector::Zero();
  Vector b = Vector::Zero();
  double radius = 0.0;
  double start_angle = 0.0;
  double sweep = 0.0;
};

}  // namespace billiard
