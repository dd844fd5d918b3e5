// Geometry of walls (wall.hpp): points of arcs, distances, bounding boxes and the inside tests
// the containers and the cells are built from (wall.cpp). Internal: not installed.
#pragma once

#include "billiard/engine/plane.hpp"
#include "billiard/engine/wall.hpp"

#include <vector>

namespace billiard {

// The point of an arc's circle at `angle`: its end points are arc_point(arc, start_angle) and
// arc_point(arc, start_angle + sweep) (segments joining an arc are built from these, so that they
// meet it exactly).
Vector arc_point(const WallShape& arc, double angle);

// Distance between an arc and the axis-aligned rectangle [lo, hi] (0 if they meet).
double arc_rectangle_distance(const WallShape& arc, const Vector& lo, const Vector& hi);

// The smallest axis-aligned box holding the arc.
void arc_bounds(const WallShape& arc, Vector& lo, Vector& hi);

// Even-odd rule for a closed curve made of segments and arcs (in any order; several closed
// curves may be mixed): does a ray from p towards +x cross the pieces an odd number of times?
// For segments it is inside_polygon's rule; an arc counts like the y-monotone pieces it splits
// into at its highest and lowest points.
bool inside_pieces(const std::vector<WallShape>& pieces, const Vector& p);

// Closest point of a wall to the point p (for a circle: on its rim, towards p).
Vector closest_point(const WallShape& wall, const Vector& p);

// Distance from p to the segment a-b.
double distance_to_segment(const Vector& p, const Vector& a, const Vector& b);

// Distance between the segment a-b and the axis-aligned rectangle [lo, hi] (0 if they meet).
double segment_rectangle_distance(const Vector& a, const Vector& b, const Vector& lo, const Vector& hi);

// Distance between the point p and the rectangle [lo, hi] (0 inside).
double point_rectangle_distance(const Vector& p, const Vector& lo, const Vector& hi);

// Even-odd rule: is p inside the closed polygon with these vertices (N by 2)?
bool inside_polygon(const Coordinates& vertices, const Vector& p);

}  // namespace billiard
