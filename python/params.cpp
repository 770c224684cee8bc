#include "params.h"

#include <string>
#include <type_traits>

#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "query.h"

namespace retroprism::python {

namespace {

using nlohmann::json;

// A Python value as the JSON value the reader expects; the reader checks types and ranges.
json to_json(const pyb::handle& v, const std::string& field) {
    const pyb::object numpyBool = pyb::module_::import("numpy").attr("bool_");
    if (pyb::isinstance<pyb::bool_>(v) || pyb::isinstance(v, numpyBool))
        return bool(pyb::bool_(pyb::reinterpret_borrow<pyb::object>(v)));
    if (pyb::isinstance<pyb::str>(v)) return v.cast<std::string>();
    const bool scalarArray =
        pyb::isinstance<pyb::array>(v) && pyb::reinterpret_borrow<pyb::array>(v).ndim() == 0;
    if (pyb::isinstance<pyb::sequence>(v) && !scalarArray) {
        json a = json::array();
        const pyb::sequence s = pyb::reinterpret_borrow<pyb::sequence>(v);
        for (std::size_t i = 0; i < s.size(); ++i)
            a.push_back(to_json(s[i], field + "[" + std::to_string(i) + "]"));
        return a;
    }
    if (pyb::hasattr(v, "__float__"))
        return double(pyb::float_(pyb::reinterpret_borrow<pyb::object>(v)));
    throw pyb::value_error(field + ": expected a number, a string, a boolean or a sequence, got " +
                           std::string(pyb::str(pyb::type::of(v).attr("__name__"))));
}

pyb::tuple triple(const Vec3d& v) {
    return pyb::make_tuple(v[0], v[1], v[2]);
}

} // namespace

Params params_from_python(const pyb::args& args, const pyb::kwargs& kwargs) {
    if (args.size() > 1 || (args.size() == 1 && kwargs.size() > 0))
        throw pyb::value_error("Node: give the inputs as one dict or as keywords, not both");
    pyb::dict inputs = kwargs;
    if (args.size() == 1) {
        if (!pyb::isinstance<pyb::dict>(args[0]))
            throw pyb::value_error("Node: expected a dict of inputs, got " +
                                   std::string(pyb::str(pyb::type::of(args[0]).attr("__name__"))));
        inputs = pyb::reinterpret_borrow<pyb::dict>(args[0]);
    }
    json j = json::object();
    for (const auto& item : inputs) {
        if (!pyb::isinstance<pyb::str>(item.first))
            throw pyb::value_error("Node: input names must be strings");
        const std::string name = item.first.cast<std::string>();
        j[name] = to_json(item.second, "Node." + name);
    }
    return params_from_json(j, "Node");
}

pyb::dict params_to_python(const Params& p) {
    pyb::dict d;
    for_each_input(p, [&](const ParamInfo& info, const auto& field) {
        using T = std::decay_t<decltype(field)>;
        if constexpr (std::is_same_v<T, Vec3d>)
            d[info.name] = triple(field);
        else if constexpr (std::is_same_v<T, int>)
            d[info.name] = enum_values(info).at(std::size_t(field));
        else
            d[info.name] = field;
    });
    return d;
}

pyb::list param_table_python() {
    pyb::list out;
    for (const ParamInfo& info : param_table()) {
        pyb::dict row;
        row["name"] = info.name;
        const Vec3d def = {info.default_value[0], info.default_value[1], info.default_value[2]};
        switch (info.type) {
        case ParamType::Float:
            row["type"] = "float";
            row["default"] = def[0];
            break;
        case ParamType::Color:
        case ParamType::Vector:
            row["type"] = info.type == ParamType::Color ? "color3" : "vector3";
            row["default"] = triple(def);
            break;
        case ParamType::Enum:
            row["type"] = "string";
            row["default"] = enum_values(info).at(std::size_t(def[0]));
            row["values"] = enum_values(info);
            break;
        case ParamType::Bool:
            row["type"] = "boolean";
            row["default"] = def[0] != 0;
            break;
        }
        if (info.type == ParamType::Float || info.type == ParamType::Color) {
            row["min"] = info.min_value;
            row["max"] = info.max_value;
        }
        row["doc"] = info.doc;
        out.append(row);
    }
    return out;
}

} // namespace retroprism::python
