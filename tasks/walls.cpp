// Task 8 (extension stage): walls -- straight walls inside the table.
//
// Write propagate_walls below (declared in lib/include/billiard/extensions.hpp). It is your
// propagate (task 4) with more obstacles: start from a copy of it. Each wall k is the segment
// from walls[k].a to walls[k].b, and a circle can hit it in two ways:
//   - on a FACE (either side), somewhere between the end points;
//   - at an END POINT p (a or b), which a circle passing the end of the wall hits like a circle
//     of radius 0.
// Both are reported as Collision{time, circle, wall_id(k)} (wall_id(k) = -2 - k; kWall stays
// the table's rim, rows >= 0 stay circles).
//
//   1. Table and pairs: exactly as in propagate.
//   2. A face of wall k. Take the unit normal n = (-u_y, u_x) with u = (b - a) / |b - a| (divide
//      by the length, or every distance below is scaled by it). The signed distance of the centre
//      from the wall's line is d(t) = d0 + (v.n) t with d0 = (r - a).n. The circle touches a face
//      when |d(t)| = circle_radius while it moves towards the line, i.e. only if d0 and v.n have
//      opposite signs (either sign of d0: the wall has two faces); then
//          t = (|d0| - circle_radius) / |v.n|.
//      It counts only if the foot of the perpendicular then lies on the segment:
//          0 <= s <= |b - a|,  s = (r + v t - a).u.
//      Beyond the ends the end points take over. A wall of zero length (a == b) has no faces,
//      only its point: skip the face, do not divide by 0.
//   3. An end point p of wall k: |r - p + v t| = circle_radius is the pair equation of propagate
//      with the point at rest and contact distance circle_radius instead of 2 circle_radius:
//      with d = r - p, b = d.v, c = d.d - circle_radius^2, D = b^2 - v.v c, a hit needs
//      b < 0 (approaching) and D >= 0, and then t = c / (-b + sqrt(D)) (the first contact,
//      without cancellation). Do both end points of every wall.
//   4. Take the earliest event of all, move EVERY circle by v t, then reflect. Reflection off
//      anything fixed reverses the velocity component along a unit normal, v' = v - 2 (v.n) n:
//        table:      n = r / |r|;
//        face:       n = the wall's unit normal (its sign does not matter);
//        end point:  n = (r - p) / |r - p| at contact (NOT the wall's normal).
//      Pairs exchange their normal components as in propagate.
//
// Numerical traps:
//   - Right after a bounce the circle touches the wall: |d0| = circle_radius up to rounding,
//     or |r - p| = circle_radius. It must not hit it again at once. Decide with the direction of
//     motion (d0 (v.n) < 0 for a face, b < 0 for a point), never with a time epsilon such as
//     t > 1e-9: with an epsilon, a circle pushed against a wall by another circle (touching and
//     moving towards it, t = 0) passes straight through.
//   - Rounding can leave a touching circle a hair inside the wall; a time that comes out a tiny
//     negative number then means "now": clamp it to 0.
//   - A circle sliding parallel to a wall (v.n = 0) never hits its face, even while touching
//     it: check the direction before dividing by v.n.
//   - A circle hitting a face exactly at an end point touches the face and the point at the same
//     moment; both give the same normal, so either may be taken. Include both ends in the face
//     test (0 <= s <= |b - a|).
//   - Walls may cross each other, share end points or end on the table's rim. Nothing special
//     is needed: the faces and the end points together close every gap where walls meet.
//
// Check the arguments first, before moving anything: checks::table(...), checks::rows(...) for
// both matrices, checks::placement(...), checks::walls(table_radius, walls) and
// checks::clear_of_walls(table_radius, circle_radius, coordinates, walls). As in propagate,
// throw std::invalid_argument if no event exists (n = 0, or all circles at rest).
//
// Run this task's tests:   ./build.sh test -L walls
#include "billiard/argument_checks.hpp"
#include "billiard/extensions.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

Collision propagate_walls(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                          Velocities& velocities, const std::vector<Wall>& walls) {
  // Delete these two lines and write the task.
  throw NotImplemented(8, "propagate_walls", "tasks/walls.cpp");
  (void)table_radius, (void)circle_radius, (void)n, (void)coordinates, (void)velocities, (void)walls;
}

}  // namespace billiard
