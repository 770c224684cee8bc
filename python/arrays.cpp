#include "arrays.h"

#include <cmath>
#include <sstream>

namespace retroprism::python {

namespace {

std::string shape_text(const pyb::array& a) {
    std::string s = "(";
    for (pyb::ssize_t i = 0; i < a.ndim(); ++i)
        s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

template <class Real>
bool all_in(const Real* v, std::size_t count, double lo, double hi) {
    for (std::size_t i = 0; i < count; ++i)
        if (!(std::isfinite(v[i]) && v[i] >= lo && v[i] < hi)) return false;
    return true;
}

} // namespace

Batch batch_arg(const pyb::handle& value, const std::string& name) {
    pyb::array a = pyb::array::ensure(value);
    if (!a)
        throw pyb::value_error(name + ": expected an array of shape (N, 3), got " +
                               std::string(pyb::str(pyb::type::of(value).attr("__name__"))));
    Precision precision;
    if (a.dtype().is(pyb::dtype::of<float>()))
        precision = Precision::Float;
    else if (a.dtype().is(pyb::dtype::of<double>()))
        precision = Precision::Double;
    else
        throw pyb::value_error(name + ": expected float32 or float64 values, got " +
                               std::string(pyb::str(a.dtype())));
    if (a.ndim() != 2 || a.shape(1) != 3)
        throw pyb::value_error(name + ": expected shape (N, 3), got " + shape_text(a));
    if (precision == Precision::Float)
        a = pyb::array_t<float, pyb::array::c_style>::ensure(a);
    else
        a = pyb::array_t<double, pyb::array::c_style>::ensure(a);
    return {a, precision, std::size_t(a.shape(0))};
}

void require_same(const Batch& first, const std::string& firstName, const Batch& second,
                  const std::string& secondName) {
    if (second.precision != first.precision)
        throw pyb::value_error(secondName + ": dtype " +
                               std::string(pyb::str(second.array.dtype())) + " differs from " +
                               firstName + "'s " + std::string(pyb::str(first.array.dtype())));
    if (second.n != first.n)
        throw pyb::value_error(secondName + ": " + std::to_string(second.n) + " rows, " +
                               firstName + " has " + std::to_string(first.n));
}

void require_in(const Batch& b, const std::string& name, double lo, double hi) {
    const std::size_t count = b.n * 3;
    const bool ok = b.precision == Precision::Float
                        ? all_in(static_cast<const float*>(b.data()), count, lo, hi)
                        : all_in(static_cast<const double*>(b.data()), count, lo, hi);
    if (!ok) {
        std::ostringstream ss;
        ss << name << ": values must be finite and in [" << lo << ", " << hi << ")";
        throw pyb::value_error(ss.str());
    }
}

pyb::array_t<double> finite_doubles(const pyb::handle& value, const std::string& name) {
    pyb::array a = pyb::array::ensure(value);
    if (!a || !(a.dtype().kind() == 'f' || a.dtype().kind() == 'i' || a.dtype().kind() == 'u'))
        throw pyb::value_error(name + ": expected a number or an array of numbers");
    pyb::array_t<double, pyb::array::c_style> d =
        pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(a);
    const double* v = d.data();
    for (pyb::ssize_t i = 0; i < d.size(); ++i)
        if (!std::isfinite(v[i])) {
            std::ostringstream ss;
            ss << name << ": values must be finite, got " << v[i];
            throw pyb::value_error(ss.str());
        }
    return d;
}

} // namespace retroprism::python
