// Task 7 (extension stage): gravity -- circles on parabolas.
//
// Write both functions below (declared in lib/include/billiard/extensions.hpp). Start from a
// copy of your propagate: the event step is the same, only the motion between events changes.
//
// propagate_gravity: one event step under a uniform acceleration g (any direction). Between
// events each circle flies on a parabola and speeds up:
//      r(t) = r + v t + g t^2 / 2,      v(t) = v + g t.
//   1. Pairs. The relative position of circles i and j is (r_i - r_j) + (v_i - v_j) t: the
//      g t^2 / 2 is the same for both and cancels. So the time until two circles touch is
//      EXACTLY the one of propagate (approach check b < 0, stable root c / (-b + sqrt(d))).
//      Do not put g into it.
//   2. The wall. The circle touches it when |r(t)| = R - a. Squared, with L = R - a:
//      f(t) = |r + v t + g t^2/2|^2 - L^2
//           = (g.g/4) t^4 + (v.g) t^3 + (v.v + r.g) t^2 + 2 (r.v) t + (r.r - L^2),
//      a QUARTIC in t, negative while the circle is inside. The wall is hit at the first t > 0
//      where f crosses zero UPWARD (the circle moving out). Traps:
//      - Right after a wall bounce the circle sits on the wall: f(0) is 0 up to rounding, maybe
//        a hair positive, and f is falling (moving in). That root near t = 0 is no hit; a
//        "smallest positive root" returns ~1e-16 and the circle hits the wall again at once.
//      - A circle on (or a hair outside) the wall that moves out (f(0) >= 0, f'(0) = 2 r.v > 0)
//        must bounce now: return time 0.
//      - An arc that just grazes the wall has two roots very close together (a double root when
//        it only touches). Sampling f at fixed steps can step over the short time outside, and
//        the closed-form quartic formula loses most of its digits there: do not use either.
//      A robust method: first bound the search. |r(t)| >= |g| t^2/2 - |v| t - |r|, so once
//      |g| t^2/2 - |v| t - |r| >= L the circle is surely outside: the larger root T of
//      |g|/2 t^2 - |v| t - (|r| + L) = 0 bounds the hit. The bound is tight (a circle dropped
//      from rest at the centre arrives exactly at T), so search [0, t_max] with t_max = 2 T,
//      lest rounding put the root a hair beyond. Split [0, t_max] at the roots of f' (a cubic):
//      between them f is monotone and crosses zero at most once. Find the roots of f' the same
//      way (split at the roots of f'', a quadratic, and bisect each piece where f' changes
//      sign). Take the first piece where f goes from < 0 to >= 0 and bisect it until the two
//      ends are adjacent doubles (about 60 halvings; stop when the midpoint equals an end).
//      With g = 0 the quartic degenerates: use propagate's quadratic, so that the stage then
//      behaves exactly like propagate.
//   3. Take the smallest time. With g != 0 every circle reaches the wall, even from rest; throw
//      std::invalid_argument only if there is no event at all (n = 0, or g = 0 and all at rest).
//   4. Move EVERY circle: r += v t + g t^2/2, and v += g t.
//   5. Collide with the velocities at contact (after step 4), as in propagate: wall n = r / |r|,
//      v' = v - 2 (v.n) n; pair: exchange the components along the line of centres.
//   6. Return Collision{time, circle, other}.
// Check the arguments first, as propagate does: checks::table(...), checks::rows(...) for both
// matrices, checks::vector(g, "g"), checks::placement(...). Throw before changing anything.
//
// mean_energy: the energy per circle (unit mass), kinetic plus potential,
//      (1/n) sum_i (|v_i|^2 / 2 - g.r_i),      0 for n = 0.
// The potential -g.r grows against gravity: with g = (0, -9.81) it is 9.81 y ("m g h"). Elastic
// collisions and free flight conserve it, so it stays constant (to rounding, ~1e-12 relative
// over thousands of events) while the kinetic energy alone does not; neither does momentum
// (gravity and the curved wall push the circles). Check the arguments with checks::rows(...)
// for both matrices and checks::vector(g, "g").
//
// Run this task's tests:   ./build.sh test -L gravity
#include "billiard/argument_checks.hpp"
#include "billiard/extensions.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

Collision propagate_gravity(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                            Velocities& velocities, const Vector& g) {
  // Delete these two lines and write the task.
  throw NotImplemented(7, "propagate_gravity", "tasks/gravity.cpp");
  (void)table_radius, (void)circle_radius, (void)n, (void)coordinates, (void)velocities, (void)g;
}

double mean_energy(int n, const Coordinates& coordinates, const Velocities& velocities, const Vector& g) {
  // Delete these two lines and write the task.
  throw NotImplemented(7, "mean_energy", "tasks/gravity.cpp");
  (void)n, (void)coordinates, (void)velocities, (void)g;
}

}  // namespace billiard
