// Python bindings of the time-stepped integrator (billiard/stepping/level_set.hpp, stepper.hpp):
// the submodule billiard._billiard.stepping, re-exported as billiard.stepping (stepping.py adds
// the replays as generators). Level sets written in Python are two vectorised numpy functions,
// called once per step for all the particles that need them. No physics here: only conversions
// and the checks of what the user's functions return.
#include "bindings.hpp"

#include "billiard/stepping/level_set.hpp"
#include "billiard/stepping/stepper.hpp"

#include <pybind11/stl.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

namespace py = pybind11;

namespace billiard::python {
namespace {

using stepping::Domain;
using stepping::Integrator;
using stepping::LevelSet;
using stepping::Stepper;
using stepping::StepperState;

std::string shape_of(const py::array& array) {
  std::string s = "(";
  for (py::ssize_t k = 0; k < array.ndim(); ++k) s += (k ? ", " : "") + std::to_string(array.shape(k));
  return s + (array.ndim() == 1 ? ",)" : ")");
}

// What the user's function returned, as float64, with its shape checked: (n,) for omega, (n, 2)
// for the gradient.
py::array_t<double, py::array::c_style> returned_array(const py::object& result, const char* name, py::ssize_t n, int columns) {
  py::array array = py::array::ensure(result);
  const std::string wanted = columns == 0 ? "(" + std::to_string(n) + ",)" : "(" + std::to_string(n) + ", 2)";
  if (!array) {
    throw std::invalid_argument(std::string("level_set: ") + name + " must return a numpy array of shape " + wanted +
                                ", got " + short_repr(result));
  }
  const bool shape_ok = columns == 0 ? array.ndim() == 1 && array.shape(0) == n
                                     : array.ndim() == 2 && array.shape(0) == n && array.shape(1) == 2;
  if (!shape_ok) {
    throw std::invalid_argument(std::string("level_set: ") + name + " returned an array of shape " + shape_of(array) + " for " +
                                std::to_string(n) + " points; it must return shape " + wanted);
  }
  const char kind = array.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw std::invalid_argument(std::string("level_set: ") + name + " must return real numbers, got dtype " +
                                py::str(array.dtype()).cast<std::string>());
  }
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
}

// A level set given as omega(points (n, 2)) -> (n,) and grad(points (n, 2)) -> (n, 2).
class PythonLevelSet final : public LevelSet {
 public:
  PythonLevelSet(py::function omega, py::function grad) : omega_(std::move(omega)), grad_(std::move(grad)) {}
  // The functions are Python objects: release them with the interpreter's lock held.
  ~PythonLevelSet() override {
    py::gil_scoped_acquire lock;
    omega_ = py::function();
    grad_ = py::function();
  }
  Eigen::VectorXd values(const Coordinates& at) const override {
    const auto n = static_cast<py::ssize_t>(at.rows());
    const auto array = returned_array(omega_(to_numpy(at)), "omega", n, 0);
    Eigen::VectorXd w(at.rows());
    const auto view = array.unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) w[i] = view(i);
    return w;
  }
  Coordinates gradients(const Coordinates& at) const override {
    const auto n = static_cast<py::ssize_t>(at.rows());
    const auto array = returned_array(grad_(to_numpy(at)), "grad", n, 2);
    Coordinates g(at.rows(), 2);
    const auto view = array.unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
      g(i, 0) = view(i, 0);
      g(i, 1) = view(i, 1);
    }
    return g;
  }

 private:
  py::function omega_;
  py::function grad_;
};

// The Python object for one level set: the shared C++ level set and how it was made.
struct Part {
  std::shared_ptr<const LevelSet> level_set;
  std::string description;
};

// A Part or a list or tuple of them.
Domain to_domain(const py::object& value) {
  const char* const how = "domain must be a level set (billiard.stepping.circle, ellipse, box or level_set) or a list of them";
  Domain domain;
  if (py::isinstance<Part>(value)) {
    domain.push_back(value.cast<const Part&>().level_set);
    return domain;
  }
  if (!py::isinstance<py::list>(value) && !py::isinstance<py::tuple>(value)) {
    throw std::invalid_argument(std::string(how) + ", got " + short_repr(value));
  }
  for (const py::handle item : value) {
    if (!py::isinstance<Part>(item)) throw std::invalid_argument(std::string(how) + "; one item is " + short_repr(item));
    domain.push_back(item.cast<const Part&>().level_set);
  }
  if (domain.empty()) throw std::invalid_argument(std::string(how) + ", got an empty " + short_repr(value));
  return domain;
}

Integrator to_integrator(const std::string& name) {
  if (name == "leapfrog") return Integrator::Leapfrog;
  if (name == "euler") return Integrator::Euler;
  throw std::invalid_argument("integrator must be 'leapfrog' or 'euler', got '" + name + "'");
}

// The integer counters (parts, reflections) as numpy vectors.
template <class T>
py::array_t<T> counts(const std::vector<T>& v) {
  py::array_t<T> out(static_cast<py::ssize_t>(v.size()));
  auto view = out.template mutable_unchecked<1>();
  for (std::size_t i = 0; i < v.size(); ++i) view(static_cast<py::ssize_t>(i)) = v[i];
  return out;
}

// Same key names as Simulation's states where the meaning is the same (time, position, velocity).
py::dict state_dict(const Stepper& stepper, const StepperState& state) {
  py::dict d;
  d["time"] = state.time;
  d["steps"] = state.steps;
  d["position"] = to_numpy(state.positions);
  d["velocity"] = to_numpy(state.velocities);
  d["part"] = counts(state.parts);
  d["reflections"] = counts(state.reflections);
  d["energy"] = vector(stepping::energies(state, stepper.gravity()));
  return d;
}

}  // namespace

void bind_stepping(py::module_& parent) {
  py::module_ m = parent.def_submodule("stepping", "Time stepping of point particles in level-set domains.");

  py::class_<Part>(m, "LevelSet", R"(One region {x : omega(x) > 0}: made by circle, ellipse, box or level_set.
omega(points) and grad(points) evaluate it at points (n, 2).)")
      .def(
          "omega", [](const Part& p, const py::object& at) { return vector(p.level_set->values(to_coordinates(at, "points"))); },
          py::arg("points"), "omega at each row of points (n, 2): shape (n,).")
      .def(
          "grad", [](const Part& p, const py::object& at) { return to_numpy(p.level_set->gradients(to_coordinates(at, "points"))); },
          py::arg("points"), "The gradient of omega at each row of points (n, 2): shape (n, 2).")
      .def("__repr__", [](const Part& p) { return p.description; });

  m.def(
      "circle",
      [](const py::object& centre, double radius) {
        return Part{stepping::circle(to_vector(centre, "centre"), radius),
                    "circle(centre=" + short_repr(centre) + ", radius=" + short_repr(py::float_(radius)) + ")"};
      },
      py::arg("centre"), py::arg("radius"), "Disc about centre: omega = radius - |x - centre| (the signed distance).");
  m.def(
      "ellipse",
      [](const py::object& centre, const py::object& semi_axes) {
        return Part{stepping::ellipse(to_vector(centre, "centre"), to_vector(semi_axes, "semi_axes")),
                    "ellipse(centre=" + short_repr(centre) + ", semi_axes=" + short_repr(semi_axes) + ")"};
      },
      py::arg("centre"), py::arg("semi_axes"),
      "Ellipse about centre with semi-axes (a, b) along x and y: omega = 1 - ((x - cx)/a)^2 - ((y - cy)/b)^2.");
  m.def(
      "box",
      [](const py::object& lower, const py::object& upper) {
        return Part{stepping::box(to_vector(lower, "lower"), to_vector(upper, "upper")),
                    "box(lower=" + short_repr(lower) + ", upper=" + short_repr(upper) + ")"};
      },
      py::arg("lower"), py::arg("upper"),
      "Box [lower, upper]: omega = the distance to the nearest face; its gradient is that face's inward normal.");
  m.def(
      "level_set",
      [](const py::object& omega, const py::object& grad) {
        if (!PyCallable_Check(omega.ptr())) throw std::invalid_argument("level_set: omega must be a function, got " + short_repr(omega));
        if (!PyCallable_Check(grad.ptr())) throw std::invalid_argument("level_set: grad must be a function, got " + short_repr(grad));
        return Part{std::make_shared<PythonLevelSet>(py::reinterpret_borrow<py::function>(omega), py::reinterpret_borrow<py::function>(grad)),
                    "level_set(omega=" + short_repr(omega) + ", grad=" + short_repr(grad) + ")"};
      },
      py::arg("omega"), py::arg("grad"),
      "A level set written in Python: omega(points (n, 2)) -> (n,) and grad(points (n, 2)) -> (n, 2), both\n"
      "vectorised (called once per step for all the particles that need them) and deterministic.");

  py::class_<Stepper>(m, "Stepper", R"(Time-stepped point particles (unit mass) in a domain {omega > 0} under gravity.

Stepper(domain, positions, velocities, dt, gravity=(0, 0), integrator='leapfrog'): domain is a level
set or a list of them (their union). Each step: kick, straight drift, kick ('leapfrog': half kicks
g dt/2; 'euler': x += v dt, then v += g dt). A drift that ends outside is cut at the crossing
(linear interpolation of omega), the velocity is reflected about the normal there, and the rest of
the drift follows. States are dicts: time, steps, position (n, 2), velocity (n, 2), part (n,: the
part each particle is in, the last it was inside), reflections (n,), energy (n,: |v|^2/2 - g.x).
Bad input raises ValueError naming the argument; the stepper is then unchanged.)")
      .def(py::init([](const py::object& domain, const py::object& positions, const py::object& velocities, double dt,
                       const py::object& gravity, const std::string& integrator) {
             return Stepper(to_domain(domain), to_coordinates(positions, "positions"), to_coordinates(velocities, "velocities"), dt,
                            to_vector(gravity, "gravity"), to_integrator(integrator));
           }),
           py::arg("domain"), py::arg("positions"), py::arg("velocities"), py::arg("dt"), py::arg("gravity") = py::make_tuple(0.0, 0.0),
           py::arg("integrator") = "leapfrog")
      .def("step", &Stepper::step, py::arg("n") = 1, "Takes n >= 0 steps.")
      .def("advance_to", &Stepper::advance_to, py::arg("time"),
           "Takes the steps that end at or before `time` (a whole number of steps is reached despite rounding).")
      .def("restarted", &Stepper::restarted, "A copy back at the initial state (running it again repeats the run).")
      .def_property_readonly("time", &Stepper::time, "The current time: steps * dt.")
      .def_property_readonly("steps", &Stepper::steps, "Steps taken.")
      .def_property_readonly("dt", &Stepper::dt, "The time step.")
      .def_property_readonly("gravity", [](const Stepper& s) { return py::make_tuple(s.gravity().x(), s.gravity().y()); },
                             "Uniform gravity (gx, gy).")
      .def_property_readonly("integrator",
                             [](const Stepper& s) { return s.integrator() == Integrator::Leapfrog ? "leapfrog" : "euler"; },
                             "'leapfrog' or 'euler'.")
      .def("__len__", &Stepper::size, "Number of particles.")
      .def_property_readonly(
          "current_state", [](const Stepper& s) { return state_dict(s, s.state()); }, "The particles now, as a dict of numpy arrays.")
      .def_property_readonly(
          "initial_state", [](const Stepper& s) { return state_dict(s, s.initial_state()); }, "The particles at time 0.")
      .def("energy", &Stepper::energy, "Total energy sum |v|^2/2 - g.x (unit masses).")
      .def("initial_energy", &Stepper::initial_energy, "The total energy at time 0.")
      .def_property_readonly("total_reflections", &Stepper::total_reflections, "Reflections of all particles since time 0.")
      .def_property_readonly("unresolved_steps", &Stepper::unresolved_steps,
                             "Particle-steps left outside after the most reflections one step allows (8).");
}

}  // namespace billiard::python
