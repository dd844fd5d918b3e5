// Stand-ins for a submitted task file that does not compile (see CMakeLists.txt here): the
// task's functions throw the usual "not implemented yet" error, so that the other tasks'
// suites still build and are graded normally. BILLIARD_STUB_<TASK> chooses the task.
#include "billiard/course.hpp"
#include "billiard/extensions.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

#ifdef BILLIARD_STUB_INIT_BILLIARD
Coordinates init_billiard(double, double, int, Rng&) { throw NotImplemented(1, "init_billiard", "init_billiard.cpp"); }
#endif
#ifdef BILLIARD_STUB_INIT_VELOCITIES
Velocities init_velocities(int, const Coordinates&, Rng&) {
  throw NotImplemented(2, "init_velocities", "init_velocities.cpp");
}
#endif
#ifdef BILLIARD_STUB_VISUALIZE_TABLE
void visualize_table(double, double, int, const Coordinates&, const std::filesystem::path&) {
  throw NotImplemented(3, "visualize_table", "visualize_table.cpp");
}
#endif
#ifdef BILLIARD_STUB_PROPAGATE
Collision propagate(double, double, int, Coordinates&, Velocities&) {
  throw NotImplemented(4, "propagate", "propagate.cpp");
}
#endif
#ifdef BILLIARD_STUB_MOVIE
void movie(double, double, int, Coordinates&, Velocities&, int, const std::filesystem::path&) {
  throw NotImplemented(5, "movie", "movie.cpp");
}
#endif
#ifdef BILLIARD_STUB_KINETIC_ENERGY
double kinetic_energy(int, const Velocities&) { throw NotImplemented(6, "kinetic_energy", "kinetic_energy.cpp"); }
void correct_energy_drift(int, Velocities&, double) {
  throw NotImplemented(6, "correct_energy_drift", "kinetic_energy.cpp");
}
#endif

#ifdef BILLIARD_STUB_GRAVITY
Collision propagate_gravity(double, double, int, Coordinates&, Velocities&, const Vector&) {
  throw NotImplemented(7, "propagate_gravity", "gravity.cpp");
}
double mean_energy(int, const Coordinates&, const Velocities&, const Vector&) {
  throw NotImplemented(7, "mean_energy", "gravity.cpp");
}
#endif
#ifdef BILLIARD_STUB_WALLS
Collision propagate_walls(double, double, int, Coordinates&, Velocities&, const std::vector<Wall>&) {
  throw NotImplemented(8, "propagate_walls", "walls.cpp");
}
#endif
#ifdef BILLIARD_STUB_SECTORS
Collision propagate_sectors(double, double, int, Coordinates&, Velocities&, double) {
  throw NotImplemented(9, "propagate_sectors", "sectors.cpp");
}
#endif

}  // namespace billiard
