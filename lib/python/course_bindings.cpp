// Python bindings of the six course functions (billiard/course.hpp), for the notebooks and for
// students exploring their own code. No logic here beyond converting arrays: numpy (n, 2)
// float64 arrays in, numpy arrays out, and the in-place updates of propagate, movie and
// correct_energy_drift written back into the caller's arrays, as in C++.
#include "bindings.hpp"

#include "billiard/course.hpp"

#include <pybind11/stl/filesystem.h>

#include <cstdint>
#include <string>

namespace py = pybind11;

namespace billiard::python {
namespace {

// A generator object, so that repeated calls draw fresh numbers as in C++.
struct PyRng {
  Rng engine;
};

// Calls `draw` with the generator: a billiard.Rng (advanced in place) or an int seed.
template <class Draw>
auto with_rng(const py::object& rng, Draw&& draw) {
  if (py::isinstance<PyRng>(rng)) return draw(rng.cast<PyRng&>().engine);
  if (py::isinstance<py::int_>(rng)) {
    // (Python ints are unbounded; a cast_error here would arrive as a RuntimeError.)
    const unsigned long long seed = PyLong_AsUnsignedLongLong(rng.ptr());
    if (PyErr_Occurred()) {
      PyErr_Clear();
      throw std::invalid_argument("rng: an int seed must be in [0, 2**64), got " + short_repr(rng));
    }
    Rng engine(seed);
    return draw(engine);
  }
  throw std::invalid_argument("rng must be a billiard.Rng or an int seed, got " +
                              py::str(py::type::of(rng)).cast<std::string>());
}

}  // namespace

void bind_course(py::module_& m) {
  m.attr("WALL") = kWall;

  py::class_<PyRng>(m, "Rng", "The course's random generator (std::mt19937_64), seeded once; each call that "
                              "draws from it advances it, as in C++.")
      .def(py::init([](std::uint64_t seed) { return PyRng{Rng(seed)}; }), py::arg("seed"))
      .def("__repr__", [](const PyRng&) { return std::string("billiard.Rng(...)"); });

  py::class_<Collision>(m, "Collision", "What propagate returns: the time advanced and who collided.")
      .def_readonly("time", &Collision::time, "time advanced to reach this collision (>= 0)")
      .def_readonly("circle", &Collision::circle, "the circle that collided (row index)")
      .def_readonly("other", &Collision::other, "the other circle's row index, or billiard.WALL (-1)")
      .def("__repr__", [](const Collision& c) {
        return "Collision(time=" + py::repr(py::float_(c.time)).cast<std::string>() + ", circle=" +
               std::to_string(c.circle) + ", other=" + (c.other == kWall ? std::string("WALL") : std::to_string(c.other)) +
               ")";
      });

  m.def(
      "init_billiard",
      [](double table_radius, double circle_radius, int n, const py::object& rng) {
        return to_numpy(with_rng(rng, [&](Rng& engine) { return init_billiard(table_radius, circle_radius, n, engine); }));
      },
      py::arg("table_radius"), py::arg("circle_radius"), py::arg("n"), py::arg("rng"),
      "Task 1. Random centres (n by 2 array) of n circles of radius circle_radius inside the table of radius\n"
      "table_radius, not overlapping. rng: a billiard.Rng (advanced) or an int seed.");

  m.def(
      "init_velocities",
      [](const py::array& coordinates, const py::object& rng) {
        const Coordinates c = from_numpy(coordinates, "coordinates");
        const int n = static_cast<int>(c.rows());
        return to_numpy(with_rng(rng, [&](Rng& engine) { return init_velocities(n, c, engine); }));
      },
      py::arg("coordinates"), py::arg("rng"),
      "Task 2. Random velocities (n by 2 array) for the circles at `coordinates` (n by 2).");

  m.def(
      "visualize_table",
      [](double table_radius, double circle_radius, const py::array& coordinates, const std::filesystem::path& svg_file) {
        const Coordinates c = from_numpy(coordinates, "coordinates");
        visualize_table(table_radius, circle_radius, static_cast<int>(c.rows()), c, svg_file);
      },
      py::arg("table_radius"), py::arg("circle_radius"), py::arg("coordinates"), py::arg("svg_file"),
      "Task 3. Writes an SVG picture of the table and the circles to svg_file.");

  m.def(
      "propagate",
      [](double table_radius, double circle_radius, py::array& coordinates, py::array& velocities) {
        Coordinates c = from_numpy(coordinates, "coordinates", true);
        Velocities v = from_numpy(velocities, "velocities", true);
        const Collision collision = propagate(table_radius, circle_radius, static_cast<int>(c.rows()), c, v);
        write_back(c, coordinates);
        write_back(v, velocities);
        return collision;
      },
      py::arg("table_radius"), py::arg("circle_radius"), py::arg("coordinates"), py::arg("velocities"),
      "Task 4. One event step: moves every circle to the next collision and updates the velocities, in place\n"
      "(coordinates and velocities: writable float64 n by 2 arrays). Returns the Collision.");

  m.def(
      "movie",
      [](double table_radius, double circle_radius, py::array& coordinates, py::array& velocities, int collisions,
         const std::filesystem::path& svg_file) {
        Coordinates c = from_numpy(coordinates, "coordinates", true);
        Velocities v = from_numpy(velocities, "velocities", true);
        movie(table_radius, circle_radius, static_cast<int>(c.rows()), c, v, collisions, svg_file);
        write_back(c, coordinates);
        write_back(v, velocities);
      },
      py::arg("table_radius"), py::arg("circle_radius"), py::arg("coordinates"), py::arg("velocities"),
      py::arg("collisions"), py::arg("svg_file"),
      "Task 5. Runs `collisions` steps of propagate (arrays updated in place) and writes an animated SVG.");

  m.def(
      "kinetic_energy",
      [](const py::array& velocities) {
        const Velocities v = from_numpy(velocities, "velocities");
        return kinetic_energy(static_cast<int>(v.rows()), v);
      },
      py::arg("velocities"), "Task 6. The mean squared velocity <v^2> = (1/n) sum |v_i|^2 (0 for no circles).");

  m.def(
      "correct_energy_drift",
      [](py::array& velocities, double target_mean_square) {
        Velocities v = from_numpy(velocities, "velocities", true);
        correct_energy_drift(static_cast<int>(v.rows()), v, target_mean_square);
        write_back(v, velocities);
      },
      py::arg("velocities"), py::arg("target_mean_square"),
      "Task 6. Rescales all velocities (in place) by one factor so that <v^2> becomes target_mean_square.");
}

}  // namespace billiard::python
