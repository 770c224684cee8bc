// arrays.h: NumPy arguments of the Python module, checked: batches of directions of shape
// (N, 3) in float32 or float64, and the arrays the module returns. Every check raises
// ValueError naming the argument.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <pybind11/numpy.h>

namespace retroprism::python {

namespace pyb = pybind11;

// The precision of a batch: float32 arrays run the float node, float64 arrays the double node.
enum class Precision { Float, Double };

// A batch argument: a C-contiguous (N, 3) array of float32 or float64 (anything NumPy turns
// into one: lists of floats become float64).
struct Batch {
    pyb::array array;
    Precision precision;
    std::size_t n;
    const void* data() const { return array.data(); }
};

// `value` as a batch, or ValueError naming `name`: not convertible to an array, a dtype other
// than float32 or float64, a shape other than (N, 3).
Batch batch_arg(const pyb::handle& value, const std::string& name);

// `second` must have the precision and the length of `first`, or ValueError naming it.
void require_same(const Batch& first, const std::string& firstName, const Batch& second,
                  const std::string& secondName);

// ValueError naming `name` unless every value of the batch is finite and in [lo, hi).
void require_in(const Batch& b, const std::string& name, double lo, double hi);

// A new C-contiguous array of Real of the given shape.
template <class Real>
pyb::array_t<Real> new_array(const std::vector<std::size_t>& shape) {
    return pyb::array_t<Real>(std::vector<pyb::ssize_t>(shape.begin(), shape.end()));
}

// A float64 array of the values of `value` (a number or anything NumPy turns into an array of
// numbers), or ValueError naming `name`; non-finite values are errors.
pyb::array_t<double> finite_doubles(const pyb::handle& value, const std::string& name);

} // namespace retroprism::python
