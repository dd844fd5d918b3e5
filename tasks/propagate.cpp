// Task 4: propagate -- one event step of the simulation.
//
// Write propagate below (declared in lib/include/billiard/course.hpp). Between collisions
// every circle moves in a straight line, r(t) = r + v t, so we jump from collision to
// collision:
//   1. For every circle, the time until it hits the wall:  |r + v t| = R - a.
//      With A = v.v, B = r.v, C = r.r - (R - a)^2 (C <= 0 inside) the positive root is
//      t = (-B + sqrt(B^2 - A C)) / A; when B > 0 use the same root written as
//      t = -C / (B + sqrt(B^2 - A C)), which avoids subtracting two nearly equal numbers.
//      A circle at rest never hits anything.
//   2. For every pair i < j, the time until they touch: |dr + dv t| = 2a with
//      dr = r_i - r_j, dv = v_i - v_j. Let b = dr.dv, c = dr.dr - (2a)^2, d = b^2 - dv.dv c.
//      They can only collide if they approach (b < 0) and d >= 0; then the EARLIER root is
//      t = c / (-b + sqrt(d)). (The other root is when they would separate again.)
//      Two circles that have just collided have c ~ 0 but b > 0: correctly "no collision".
//      Do not add small epsilons to times: use b < 0 to reject pairs moving apart.
//      Times are never negative: a negative time is a contact in the past. Rounding is the one
//      exception: after a collision the circles (or the circle and the wall) touch, so c (or C)
//      is 0 give or take 1e-16, and a root can come out a hair below 0 (like -1e-17). That
//      event is happening now: clamp the root to 0 with std::max(t, 0.0). A circle that
//      rounding left a hair outside the wall (C > 0) and moving outward (B > 0) hits it now,
//      at time 0; one sliding along it (B = 0) never does.
//   3. Take the smallest time over all of these. If there is none (n = 0, or all circles at
//      rest), throw std::invalid_argument.
//   4. Move EVERY circle for that time: r += v t.
//   5. Update the velocities of the colliding circle(s):
//      wall:  n = r / |r|,  v' = v - 2 (v.n) n   (only the normal component reverses);
//      pair:  n = (r_j - r_i) / |r_j - r_i|,  p = ((v_i - v_j).n) n,  v_i' = v_i - p,
//             v_j' = v_j + p   (only the components along n are exchanged).
//   6. Return Collision{time, circle, other}, with other = kWall for the wall.
// Check the arguments first: checks::table(...), checks::rows(...) for both matrices.
//
// Run this task's tests:   ./build.sh test -L propagate
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

Collision propagate(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                    Velocities& velocities) {
  // Delete these two lines and write the task.
  throw NotImplemented(4, "propagate", "tasks/propagate.cpp");
  (void)table_radius, (void)circle_radius, (void)n, (void)coordinates, (void)velocities;
}

}  // namespace billiard
