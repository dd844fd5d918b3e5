// The compiled part of the Python package `billiard` (billiard/_billiard.*.so); the package's
// __init__.py re-exports it. Errors: std::invalid_argument arrives as ValueError (pybind11's
// own translation), a task that is not implemented yet as NotImplementedError.
#include "bindings.hpp"

#include "billiard/not_implemented.hpp"

#include <string>

namespace py = pybind11;

namespace billiard::python {

Coordinates from_numpy(const py::array& array, const char* name, bool writable) {
  if (!array) throw std::invalid_argument(std::string(name) + " must be an array of numbers of shape (n, 2)");
  const auto shape = [&] {
    std::string s = "(";
    for (py::ssize_t k = 0; k < array.ndim(); ++k) s += (k ? ", " : "") + std::to_string(array.shape(k));
    return s + (array.ndim() == 1 ? ",)" : ")");
  };
  if (array.ndim() != 2 || array.shape(1) != 2) {
    throw std::invalid_argument(std::string(name) + " must be an array of shape (n, 2), got shape " + shape());
  }
  const bool is_double = array.dtype().is(py::dtype::of<double>());
  if (writable) {
    if (!is_double || !(array.flags() & py::array::c_style) || !array.writeable()) {
      throw std::invalid_argument(std::string(name) + " is updated in place, so it must be a writable float64 array "
                                  "(make one with numpy.array(" + name + ", dtype=float)), got dtype " +
                                  py::str(array.dtype()).cast<std::string>());
    }
  }
  // Only real numbers: numpy would also cast complex numbers (dropping the imaginary part),
  // booleans and strings such as "1.5" to float64.
  const char kind = array.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw std::invalid_argument(std::string(name) + " must hold real numbers (an integer or float dtype), got dtype " +
                                py::str(array.dtype()).cast<std::string>());
  }
  const auto values = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!values) throw std::invalid_argument(std::string(name) + " must hold numbers");
  Coordinates m(values.shape(0), 2);
  const auto view = values.unchecked<2>();
  for (py::ssize_t i = 0; i < values.shape(0); ++i) {
    m(i, 0) = view(i, 0);
    m(i, 1) = view(i, 1);
  }
  return m;
}

void write_back(const Coordinates& matrix, py::array& array) {
  auto target = py::array_t<double, py::array::c_style>::ensure(array);
  auto view = target.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < matrix.rows(); ++i) {
    view(i, 0) = matrix(i, 0);
    view(i, 1) = matrix(i, 1);
  }
}

// (ensure() gives a null array when numpy cannot read the value at all.)
Vector to_vector(const py::object& value, const char* name) {
  py::array array = py::array::ensure(value);
  if (!array || array.size() != 2) {
    throw std::invalid_argument(std::string(name) + " must be a point (x, y) of two numbers, got " + short_repr(value));
  }
  const Coordinates m = from_numpy(array.reshape({1, 2}), name);
  return m.row(0);
}

Coordinates to_coordinates(const py::object& value, const char* name) {
  return from_numpy(py::array::ensure(value), name);  // (from_numpy refuses a null array)
}

std::string short_repr(const py::handle& value) {
  std::string text;
  try {
    text = py::repr(value).cast<std::string>();
  } catch (const py::error_already_set&) {  // e.g. an int of more than 4300 digits
    text = "a " + py::str(py::type::of(value)).cast<std::string>();
  }
  return text.size() > 60 ? text.substr(0, 57) + "..." : text;
}

py::array_t<double> to_numpy(const Coordinates& matrix) {
  py::array_t<double> out({static_cast<py::ssize_t>(matrix.rows()), py::ssize_t{2}});
  auto view = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < matrix.rows(); ++i) {
    view(i, 0) = matrix(i, 0);
    view(i, 1) = matrix(i, 1);
  }
  return out;
}

py::array_t<double> vector(const Eigen::VectorXd& v) {
  py::array_t<double> out(static_cast<py::ssize_t>(v.size()));
  auto view = out.mutable_unchecked<1>();
  for (Eigen::Index i = 0; i < v.size(); ++i) view(i) = v[i];
  return out;
}

}  // namespace billiard::python

PYBIND11_MODULE(_billiard, m) {
  m.doc() = "Compiled core of the billiard package: the course functions and the event-driven Simulation.";
  m.attr("__version__") = BILLIARD_VERSION;  // the project's, from CMakeLists.txt
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const billiard::NotImplemented& e) {
      PyErr_SetString(PyExc_NotImplementedError, e.what());
    }
  });
  billiard::python::bind_course(m);
  billiard::python::bind_stages(m);
#ifdef BILLIARD_PYTHON_SIMULATION
  billiard::python::bind_simulation(m);
#endif
#ifdef BILLIARD_PYTHON_STEPPING
  billiard::python::bind_stepping(m);
#endif
  m.attr("course_implementation") = BILLIARD_COURSE_NAME;
}
