// Shared by the binding files of the Python module: numpy <-> Eigen conversion with errors that
// say what the caller passed and how to fix it (they arrive in Python as ValueError).
#pragma once

#include "billiard/course.hpp"
#include "billiard/engine/plane.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

namespace billiard::python {

// n by 2 arrays are Coordinates (billiard/vectors.hpp) in both layers.

// An n by 2 float64 numpy array as an Eigen matrix (a copy). With `writable`, the array must
// also be one we can write the result back into: float64, C-contiguous, writeable.
Coordinates from_numpy(const pybind11::array& array, const char* name, bool writable = false);

// Copies the matrix back into the caller's array (same shape, checked by from_numpy).
void write_back(const Coordinates& matrix, pybind11::array& array);

// A point (x, y): two real numbers in any sequence or array; `name` is the argument's name.
Vector to_vector(const pybind11::object& value, const char* name);

// An n by 2 array of real numbers from any array-like value.
Coordinates to_coordinates(const pybind11::object& value, const char* name);

// New numpy arrays: an n by 2 float64 array, and a vector.
pybind11::array_t<double> to_numpy(const Coordinates& matrix);
pybind11::array_t<double> vector(const Eigen::VectorXd& v);

// repr(value) for an error message, at most about 60 characters (and never an error itself).
std::string short_repr(const pybind11::handle& value);

void bind_course(pybind11::module_& m);
void bind_stages(pybind11::module_& parent);
void bind_simulation(pybind11::module_& m);
void bind_stepping(pybind11::module_& parent);

}  // namespace billiard::python
