// PLACEHOLDER: being written.
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"
namespace billiard {
Collision propagate(double, double, int, Coordinates&, Velocities&) { throw NotImplemented(4, "propagate", "tasks/propagate.cpp"); }
}
