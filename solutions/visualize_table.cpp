// PLACEHOLDER: being written.
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"
namespace billiard {
void visualize_table(double, double, int, const Coordinates&, const std::filesystem::path&) { throw NotImplemented(3, "visualize_table", "tasks/visualize_table.cpp"); }
}
