// PLACEHOLDER: being written.
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"
namespace billiard {
void movie(double, double, int, Coordinates&, Velocities&, int, const std::filesystem::path&) { throw NotImplemented(5, "movie", "tasks/movie.cpp"); }
}
