// module.cpp: the Python module `retroprism`: the node over NumPy batches, the ERA and R_A
// tables. Inputs by the parameter table (params.h), batches checked and spread over the cores
// (arrays.h, batch.h); bad input raises ValueError naming the argument.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "arrays.h"
#include "batch.h"
#include "error.h"
#include "params.h"
#include "photometry.h"
#include "sensor.h"

namespace retroprism::python {

namespace {

// The node at pairs (wi, wo) of one precision and length: lobes, and the pdf when withPdf.
pyb::dict eval_pairs(const Node& n, const pyb::handle& wi, const pyb::handle& wo, bool withPdf) {
    Batch a = batch_arg(wi, "wi");
    Batch b = batch_arg(wo, "wo");
    require_same(a, "wi", b, "wo");
    return eval_batch(n, a, b, withPdf);
}

pyb::object era_of(const pyb::handle& thetaT, const pyb::handle& phi, const std::string& mode,
                   double cant) {
    const ParamInfo& cantInfo = *find_param("cant_angle");
    if (!(cant >= cantInfo.min_value && cant <= cantInfo.max_value))
        throw pyb::value_error("cant: must be in [" + std::to_string(cantInfo.min_value) + ", " +
                               std::to_string(cantInfo.max_value) + "] degrees");
    const int modeIndex = enum_index(*find_param("era_mode"), mode);
    if (modeIndex < 0)
        throw pyb::value_error("mode: expected one of \"" +
                               std::string(find_param("era_mode")->enum_values) + "\", got \"" +
                               mode + "\"");
    pyb::array_t<double> t = finite_doubles(thetaT, "theta_t");
    pyb::array_t<double> p = finite_doubles(phi, "phi");
    for (pyb::ssize_t i = 0; i < t.size(); ++i)
        if (t.data()[i] < 0 || t.data()[i] >= 90)
            throw pyb::value_error("theta_t: must be in [0, 90) degrees, got " +
                                   std::string(pyb::str(pyb::float_(t.data()[i]))));
    const pyb::tuple both = pyb::module_::import("numpy").attr("broadcast_arrays")(t, p);
    const auto tb =
        pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(both[0]);
    const auto pb =
        pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(both[1]);
    std::vector<pyb::ssize_t> shape(tb.shape(), tb.shape() + tb.ndim());
    pyb::array_t<double> out(shape);
    for (pyb::ssize_t i = 0; i < tb.size(); ++i)
        out.mutable_data()[i] =
            era(tb.data()[i] * M_PI / 180.0, pb.data()[i] * M_PI / 180.0, modeIndex, cant);
    if (out.ndim() == 0) return pyb::float_(out.data()[0]);
    return std::move(out);
}

std::vector<double> angles_or(const pyb::handle& value, const std::string& name,
                              const std::vector<double>& standard) {
    if (value.is_none()) return standard;
    pyb::array_t<double> a = finite_doubles(value, name);
    if (a.ndim() != 1) throw pyb::value_error(name + ": expected a 1-D sequence of angles");
    return std::vector<double>(a.data(), a.data() + a.size());
}

// The node at `wavelength` (nm, in (0, 2000]: its `wavelength` input set), or the node itself
// for None.
Node at_wavelength(const Node& node, const pyb::object& wavelength) {
    if (wavelength.is_none()) return node;
    const double nm = wavelength.cast<double>();
    if (!(nm > 0.0 && nm <= 2000.0))
        throw pyb::value_error("wavelength: must be in (0, 2000] nm, got " + std::to_string(nm));
    Params p = node.params;
    p.wavelength = nm;
    return Node(p);
}

pyb::dict ra_table_of(const Node& node0, double rotation, const pyb::handle& observation,
                      const pyb::handle& entrance, const pyb::object& wavelength, bool photopic) {
    if (!std::isfinite(rotation)) throw pyb::value_error("rotation: must be finite");
    if (photopic && !wavelength.is_none())
        throw pyb::value_error("give either wavelength=NM or photopic=True, not both");
    const Node node = at_wavelength(node0, wavelength);
    const RaTable t = ra_table(node.params, rotation,
                               angles_or(observation, "observation", ra_observation_angles()),
                               angles_or(entrance, "entrance", ra_entrance_angles()),
                               photopic ? RaSpectrum::Photopic : RaSpectrum::Channels);
    const std::size_t rows = t.observation.size(), cols = t.entrance.size();
    pyb::array_t<double> rgb = new_array<double>({rows, cols, 3});
    pyb::array_t<double> y = new_array<double>({rows, cols});
    for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < cols; ++c) {
            for (int k = 0; k < 3; ++k)
                rgb.mutable_data()[(r * cols + c) * 3 + k] = t.rgb[r][c][k];
            y.mutable_data()[r * cols + c] = luminance_709(t.rgb[r][c]);
        }
    pyb::dict d;
    d["observation"] = pyb::array_t<double>(pyb::ssize_t(rows), t.observation.data());
    d["entrance"] = pyb::array_t<double>(pyb::ssize_t(cols), t.entrance.data());
    d["rotation"] = rotation;
    d["rgb"] = rgb;
    d["Y"] = y;
    return d;
}

void define_node(pyb::module_& m) {
    pyb::class_<Node>(m, "Node",
                      "The prismatic retroreflector node (Guo, Guo & Pan 2018) for one set of "
                      "inputs: Node(roughness=0.1, ior=1.586) or Node({'roughness': 0.1}); the "
                      "names, types and ranges of retroprism.param_table(). Directions are "
                      "(N, 3) arrays in the frame of `normal` and `tangent` (the local shading "
                      "frame by default), wi toward the light, wo toward the viewer; float32 "
                      "batches run the float node, float64 the double node. eval, f, pdf, "
                      "sample and ra_table take wavelength=NM to evaluate every channel there.")
        .def(pyb::init([](const pyb::args& args, const pyb::kwargs& kwargs) {
            return Node(params_from_python(args, kwargs));
        }))
        .def_property_readonly(
            "inputs", [](const Node& n) { return params_to_python(n.params); },
            "Every input by name, as given (omitted ones at their defaults).")
        .def("__repr__",
             [](const Node& n) {
                 return "retroprism.Node(" + std::string(pyb::repr(params_to_python(n.params))) +
                        ")";
             })
        .def(
            "eval",
            [](const Node& n0, const pyb::handle& wi, const pyb::handle& wo,
               const pyb::object& wavelength) {
                const Node n = at_wavelength(n0, wavelength);
                return eval_pairs(n, wi, wo, true);
            },
            pyb::arg("wi"), pyb::arg("wo"), pyb::arg("wavelength") = pyb::none(),
            "BRDF without the cosine (1/sr) per lobe and in total, and the sampling pdf: "
            "{'f', 'surface', 'retro', 'diffuse': (N, 3), 'pdf': (N,)}.")
        .def(
            "f",
            [](const Node& n0, const pyb::handle& wi, const pyb::handle& wo,
               const pyb::object& wavelength) {
                const Node n = at_wavelength(n0, wavelength);
                return eval_pairs(n, wi, wo, false);
            },
            pyb::arg("wi"), pyb::arg("wo"), pyb::arg("wavelength") = pyb::none(),
            "eval() without the pdf (cheaper): {'f', 'surface', 'retro', 'diffuse': (N, 3)}.")
        .def(
            "pdf",
            [](const Node& n0, const pyb::handle& wi, const pyb::handle& wo,
               const pyb::object& wavelength) {
                const Node n = at_wavelength(n0, wavelength);
                return pyb::object(eval_pairs(n, wi, wo, true)["pdf"]);
            },
            pyb::arg("wi"), pyb::arg("wo"), pyb::arg("wavelength") = pyb::none(),
            "The one-sample-mixture sampling pdf (N,) in 1/sr.")
        .def(
            "sample",
            [](const Node& n0, const pyb::handle& wi, const pyb::handle& u,
               const pyb::object& wavelength) {
                const Node n = at_wavelength(n0, wavelength);
                Batch a = batch_arg(wi, "wi");
                Batch b = batch_arg(u, "u");
                require_same(a, "wi", b, "u");
                require_in(b, "u", 0.0, 1.0);
                return sample_batch(n, a, b);
            },
            pyb::arg("wi"), pyb::arg("u"), pyb::arg("wavelength") = pyb::none(),
            "Sampled directions for random numbers u in [0, 1) (u[:, 2] picks the lobe): "
            "{'wo', 'f', 'surface', 'retro', 'diffuse': (N, 3), 'pdf': (N,), 'lobe': (N,) "
            "0 surface, 1 retro, 2 diffuse, -1 none, 'valid': (N,) bool}.")
        .def(
            "albedo",
            [](const Node& n, const pyb::handle& wi, int grid) {
                if (grid < 1 || grid > 4096)
                    throw pyb::value_error("grid: must be in [1, 4096], got " +
                                           std::to_string(grid));
                return albedo_batch(n, batch_arg(wi, "wi"), grid);
            },
            pyb::arg("wi"), pyb::arg("grid") = 128,
            "Directional albedo (integral of f cos theta_o) per lobe: {'surface', 'retro', "
            "'diffuse', 'total': (N, 3)}; surface and retro by grid x grid quadrature.")
        .def(
            "retro_fraction",
            [](const Node& n, const pyb::handle& wi) {
                return retro_fraction_batch(n, batch_arg(wi, "wi"));
            },
            pyb::arg("wi"),
            "Retroreflected fraction E = A R1 R2 R3 of the mean refracted direction (N,).")
        .def("ra_table", &ra_table_of, pyb::arg("rotation") = 0.0,
             pyb::arg("observation") = pyb::none(), pyb::arg("entrance") = pyb::none(),
             pyb::arg("wavelength") = pyb::none(), pyb::arg("photopic") = false,
             "Coefficient of retroreflection R_A (cd/lx/m^2) as `retroprism ra` computes it: "
             "{'observation', 'entrance' (degrees), 'rotation', 'rgb': (rows, columns, 3), 'Y': "
             "(rows, columns)}; standard angles unless given. photopic=True: as a photometer "
             "under illuminant A sees it (15 wavelengths weighted by illuminant A x V(lambda), "
             "`ra --photopic`; every channel holds it).");
}

} // namespace

} // namespace retroprism::python

PYBIND11_MODULE(retroprism, m) {
    namespace pyb = pybind11;
    using namespace retroprism::python;
    m.doc() = "retroprism: the BRDF of retroreflective prismatic sheeting (Guo, Guo & Pan 2018).";
    m.attr("__version__") = RP_VERSION;
    pyb::register_exception<retroprism::InputError>(m, "InputError", PyExc_ValueError);
    define_node(m);
    define_lidar(m);
    m.def("param_table", &param_table_python,
          "The node's inputs: name, type, default, range (min, max) or values, doc.");
    m.def("era", &era_of, pyb::arg("theta_t"), pyb::arg("phi") = 0.0, pyb::arg("mode") = "averaged",
          pyb::arg("cant") = 0.0,
          "Effective retroreflective area A (the geometry alone) of inner directions at polar "
          "angle theta_t in [0, 90) and azimuth phi from an aperture vertex, in degrees (numbers "
          "or arrays, broadcast), for cube corners of cant `cant` degrees (the node's cant_angle), "
          "as `retroprism era` computes it.");
}
