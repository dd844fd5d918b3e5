// PLACEHOLDER: being written.
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"
namespace billiard {
Velocities init_velocities(int, const Coordinates&, Rng&) { throw NotImplemented(2, "init_velocities", "tasks/init_velocities.cpp"); }
}
