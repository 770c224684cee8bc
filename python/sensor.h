// sensor.h: the LiDAR return (analysis/lidar.h) in the Python module: retroprism.lidar_return and
// retroprism.aperture_reflectance.
#pragma once

#include <pybind11/pybind11.h>

namespace retroprism::python {

void define_lidar(pybind11::module_& m);

} // namespace retroprism::python
