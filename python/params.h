// params.h: the node's inputs between Python and C++, by the parameter table. Python values go
// through the JSON reader (io/query.h), so the module accepts the names, types and ranges of a
// JSON material and raises its error texts (as ValueError, retroprism.InputError).
#pragma once

#include <pybind11/pybind11.h>

#include "prismatic_retroreflector.h"

namespace retroprism::python {

namespace pyb = pybind11;

// Node(**inputs) or Node(dict): numbers, strings (enums), booleans and sequences of 3 numbers
// (colours, vectors; lists, tuples or NumPy arrays), named "Node.<input>" in errors.
Params params_from_python(const pyb::args& args, const pyb::kwargs& kwargs);

// Every input of p by name: floats, (r, g, b) tuples, enum strings, booleans.
pyb::dict params_to_python(const Params& p);

// The parameter table: one dict per input (name, type, default, min, max, values, doc).
pyb::list param_table_python();

} // namespace retroprism::python
