// Python bindings of the extension stages (billiard/extensions.hpp) as the submodule
// billiard.stages: the stages this course builds (tests/grader/course.txt), named in
// billiard.stages.available, with the same array conventions as the six tasks.
#include "bindings.hpp"

#include "billiard/extensions.hpp"

#include <string>
#include <vector>

namespace py = pybind11;

namespace billiard::python {
namespace {

// g as a pair of numbers (any sequence of two).
[[maybe_unused]] Vector gravity_from(const py::object& g) {
  const auto values = py::array_t<double, py::array::forcecast>::ensure(g);
  if (!values || values.ndim() != 1 || values.shape(0) != 2) {
    throw std::invalid_argument("g must be two numbers (gx, gy), got " + short_repr(g));
  }
  return Vector(values.at(0), values.at(1));
}

// Walls as rows (ax, ay, bx, by): an array of shape (k, 4), or a list of such rows.
[[maybe_unused]] std::vector<Wall> walls_from(const py::object& walls) {
  const auto values = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(walls);
  const bool empty = values && values.size() == 0;
  if (!values || (!empty && (values.ndim() != 2 || values.shape(1) != 4))) {
    throw std::invalid_argument("walls must be rows (ax, ay, bx, by), an array of shape (k, 4), got " +
                                short_repr(walls));
  }
  std::vector<Wall> out;
  for (py::ssize_t k = 0; !empty && k < values.shape(0); ++k) {
    out.push_back(Wall{Vector(values.at(k, 0), values.at(k, 1)), Vector(values.at(k, 2), values.at(k, 3))});
  }
  return out;
}

// Runs one stage step on the caller's arrays: updated in place only when the step succeeds.
template <class Step>
Collision in_place(py::array& coordinates, py::array& velocities, Step&& step) {
  Coordinates c = from_numpy(coordinates, "coordinates", true);
  Velocities v = from_numpy(velocities, "velocities", true);
  const Collision collision = step(static_cast<int>(c.rows()), c, v);
  write_back(c, coordinates);
  write_back(v, velocities);
  return collision;
}

}  // namespace

void bind_stages(py::module_& parent) {
  py::module_ m = parent.def_submodule(
      "stages", "The course's extension stages (tasks 7 gravity, 8 walls, 9 sectors) that this build has.");
  py::list available;
  m.def("wall_id", &wall_id, py::arg("k"), "Collision.other for a collision with walls[k]: -2 - k.");
  m.def("pair_time_calls", &pair_time_calls, "How many pair tests task 9 has made through pair_time so far.");

#ifdef BILLIARD_WITH_GRAVITY
  available.append("gravity");
  m.def(
      "propagate_gravity",
      [](double table_radius, double circle_radius, py::array& coordinates, py::array& velocities, const py::object& g) {
        const Vector gravity = gravity_from(g);
        return in_place(coordinates, velocities, [&](int n, Coordinates& c, Velocities& v) {
          return propagate_gravity(table_radius, circle_radius, n, c, v, gravity);
        });
      },
      py::arg("table_radius"), py::arg("circle_radius"), py::arg("coordinates"), py::arg("velocities"), py::arg("g"),
      "Task 7. Like propagate, with uniform gravity g = (gx, gy); arrays updated in place.");
  m.def(
      "mean_energy",
      [](const py::array& coordinates, const py::array& velocities, const py::object& g) {
        const Coordinates c = from_numpy(coordinates, "coordinates");
        const Velocities v = from_numpy(velocities, "velocities");
        return mean_energy(static_cast<int>(c.rows()), c, v, gravity_from(g));
      },
      py::arg("coordinates"), py::arg("velocities"), py::arg("g"),
      "Task 7. Mean energy per circle, (1/n) sum (|v_i|^2 / 2 - g . r_i).");
#endif
#ifdef BILLIARD_WITH_WALLS
  available.append("walls");
  m.def(
      "propagate_walls",
      [](double table_radius, double circle_radius, py::array& coordinates, py::array& velocities,
         const py::object& walls) {
        const std::vector<Wall> segments = walls_from(walls);
        return in_place(coordinates, velocities, [&](int n, Coordinates& c, Velocities& v) {
          return propagate_walls(table_radius, circle_radius, n, c, v, segments);
        });
      },
      py::arg("table_radius"), py::arg("circle_radius"), py::arg("coordinates"), py::arg("velocities"),
      py::arg("walls"),
      "Task 8. Like propagate, with straight walls (rows ax, ay, bx, by); Collision.other is WALL for the table,\n"
      "wall_id(k) for walls[k]. Arrays updated in place.");
#endif
#ifdef BILLIARD_WITH_SECTORS
  available.append("sectors");
  m.def(
      "propagate_sectors",
      [](double table_radius, double circle_radius, py::array& coordinates, py::array& velocities, double cell_size) {
        return in_place(coordinates, velocities, [&](int n, Coordinates& c, Velocities& v) {
          return propagate_sectors(table_radius, circle_radius, n, c, v, cell_size);
        });
      },
      py::arg("table_radius"), py::arg("circle_radius"), py::arg("coordinates"), py::arg("velocities"),
      py::arg("cell_size"),
      "Task 9. Like propagate, finding the next collision through square cells of side cell_size.");
#endif
  m.attr("available") = available;
}

}  // namespace billiard::python
