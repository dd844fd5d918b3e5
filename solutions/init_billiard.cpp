// PLACEHOLDER: being written.
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"
namespace billiard {
Coordinates init_billiard(double, double, int, Rng&) { throw NotImplemented(1, "init_billiard", "tasks/init_billiard.cpp"); }
}
