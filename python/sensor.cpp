#include "sensor.h"

#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <optional>

#include "lidar.h"
#include "batch.h"

namespace retroprism::python {

namespace {

namespace pyb = pybind11;

glm::dvec3 vec(const std::array<double, 3>& v) {
    return glm::dvec3(v[0], v[1], v[2]);
}

pyb::dict lidar_return_of(const Node& node, double wavelength, double range, double entrance,
                          double rotation, const std::array<double, 3>& offset, double divergence,
                          double aperture, const std::optional<std::array<double, 2>>& size,
                          int channel) {
    LidarSensor s;
    s.receiver_offset = vec(offset);
    s.divergence_mrad = divergence;
    s.aperture_m = aperture;
    LidarTarget t;
    t.range_m = range;
    t.entrance_deg = entrance;
    t.rotation_deg = rotation;
    if (size) t.width_m = (*size)[0], t.height_m = (*size)[1];
    check_lidar_inputs(s, t);
    LidarReturn r;
    {
        pyb::gil_scoped_release release;
        r = lidar_return(lidar_node_brdf(node.params, wavelength, channel), s, t);
    }
    pyb::dict d;
    d["fraction"] = r.fraction;
    d["lambertian_fraction"] = r.lambertian_fraction;
    d["reflectance"] = r.reflectance;
    d["intercepted"] = r.intercepted;
    d["observation_mrad"] = r.observation_mrad;
    d["albedo"] = lidar_node_albedo(node.params, wavelength, channel, entrance, rotation);
    return d;
}

double
aperture_reflectance_of(const Node& node, double wavelength, const std::array<double, 3>& position,
                        const std::array<double, 3>& normal, const std::array<double, 3>& tangent,
                        const std::array<double, 3>& emitter, const std::array<double, 3>& centre,
                        const std::array<double, 3>& axis, double diameter, int channel) {
    for (const auto* v : {&position, &normal, &tangent, &emitter, &centre, &axis})
        for (double x : *v)
            if (!std::isfinite(x)) throw pyb::value_error("vectors must be finite");
    if (!(diameter > 0.0 && diameter <= 1.0))
        throw pyb::value_error("diameter: must be in (0, 1] m");
    const LidarHit hit{vec(position), vec(normal), vec(tangent)};
    const LidarAperture ap{vec(centre), vec(axis), diameter};
    return aperture_reflectance(lidar_node_brdf(node.params, wavelength, channel), hit,
                                vec(emitter), ap);
}

} // namespace

void define_lidar(pyb::module_& m) {
    m.def("lidar_return", &lidar_return_of, pyb::arg("node"), pyb::arg("wavelength") = 905.0,
          pyb::arg("range") = 20.0, pyb::arg("entrance") = 0.0, pyb::arg("rotation") = 0.0,
          pyb::arg("offset") = std::array<double, 3>{0.03, 0.0, 0.0}, pyb::arg("divergence") = 3.0,
          pyb::arg("aperture") = 0.025, pyb::arg("size") = pyb::none(), pyb::arg("channel") = 0,
          "The LiDAR return of a flat target of the node's material as `retroprism lidar` "
          "computes it (sensor frame: emitter at the origin, beam along +z, y up; wavelength "
          "nm, range m, entrance and rotation degrees, offset of the receiver aperture m, "
          "divergence mrad full at 1/e^2, aperture diameter m, size (width, height) m or None "
          "for larger than the footprint, channel 0-2): {'fraction' P_r/P, "
          "'lambertian_fraction' (reflectance 1), 'reflectance' (equivalent Lambertian), "
          "'intercepted', 'observation_mrad', 'albedo' (the node's at the entrance angle)}.");
    m.def("aperture_reflectance", &aperture_reflectance_of, pyb::arg("node"),
          pyb::arg("wavelength"), pyb::arg("position"), pyb::arg("normal"), pyb::arg("tangent"),
          pyb::arg("emitter"), pyb::arg("centre"), pyb::arg("axis"), pyb::arg("diameter"),
          pyb::arg("channel") = 0,
          "The fraction of a ray's power, arriving at `position` (a surface of the node's "
          "material with `normal` and `tangent`) from `emitter`, that a receiver aperture (a "
          "disc of `diameter` m at `centre`, facing along `axis`) collects: the per-ray "
          "function of a ray-traced LiDAR. All vectors in one frame, metres.");
}

} // namespace retroprism::python
