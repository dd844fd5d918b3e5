// The calls a worker answers: every function of the course's contract (course.hpp,
// extensions.hpp) that the graded suites call, one line each, as the contract declares it:
//
//   CALL(return type, name, (parameters), (the parameters' names))
//
// The judge's proxies are made from this list (proxy.cpp), and so is the worker's table of what
// it answers (worker_main.cpp); adding a task adds its functions here. A parameter that is a
// reference to something the function may change (a state, a generator) crosses both ways; a
// file's path (const std::filesystem::path&) crosses as the file (files.hpp).
#pragma once

#include "billiard/extensions.hpp"

#define BILLIARD_COURSE_CALLS(CALL)                                                                             \
  CALL(Coordinates, init_billiard, (double table_radius, double circle_radius, int n, Rng& rng),               \
       (table_radius, circle_radius, n, rng))                                                                   \
  CALL(Velocities, init_velocities, (int n, const Coordinates& coordinates, Rng& rng), (n, coordinates, rng))  \
  CALL(void, visualize_table,                                                                                   \
       (double table_radius, double circle_radius, int n, const Coordinates& coordinates,                       \
        const std::filesystem::path& svg_file),                                                                 \
       (table_radius, circle_radius, n, coordinates, svg_file))                                                 \
  CALL(Collision, propagate,                                                                                    \
       (double table_radius, double circle_radius, int n, Coordinates& coordinates, Velocities& velocities),    \
       (table_radius, circle_radius, n, coordinates, velocities))                                               \
  CALL(void, movie,                                                                                             \
       (double table_radius, double circle_radius, int n, Coordinates& coordinates, Velocities& velocities,     \
        int collisions, const std::filesystem::path& svg_file),                                                 \
       (table_radius, circle_radius, n, coordinates, velocities, collisions, svg_file))                         \
  CALL(double, kinetic_energy, (int n, const Velocities& velocities), (n, velocities))                         \
  CALL(void, correct_energy_drift, (int n, Velocities& velocities, double target_mean_square),                  \
       (n, velocities, target_mean_square))                                                                     \
  CALL(Collision, propagate_gravity,                                                                            \
       (double table_radius, double circle_radius, int n, Coordinates& coordinates, Velocities& velocities,     \
        const Vector& g),                                                                                       \
       (table_radius, circle_radius, n, coordinates, velocities, g))                                            \
  CALL(double, mean_energy, (int n, const Coordinates& coordinates, const Velocities& velocities, const Vector& g), \
       (n, coordinates, velocities, g))                                                                         \
  CALL(Collision, propagate_walls,                                                                              \
       (double table_radius, double circle_radius, int n, Coordinates& coordinates, Velocities& velocities,     \
        const std::vector<Wall>& walls),                                                                        \
       (table_radius, circle_radius, n, coordinates, velocities, walls))                                        \
  CALL(Collision, propagate_sectors,                                                                            \
       (double table_radius, double circle_radius, int n, Coordinates& coordinates, Velocities& velocities,     \
        double cell_size),                                                                                      \
       (table_radius, circle_radius, n, coordinates, velocities, cell_size))                                    \
  /* Counted where task 9's code calls pair_time: in the worker. */                                            \
  CALL(long long, pair_time_calls, (), ())
