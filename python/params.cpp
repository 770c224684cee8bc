#include "params.h"

#include <string>

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

// A value of params_to_json as Python: numbers, strings, booleans, arrays as tuples.
pyb::object from_json(const json& v) {
    if (v.is_boolean()) return pyb::bool_(v.get<bool>());
    if (v.is_string()) return pyb::str(v.get<std::string>());
    if (v.is_array()) {
        pyb::tuple t(v.size());
        for (std::size_t i = 0; i < v.size(); ++i)
            t[i] = from_json(v[i]);
        return std::move(t);
    }
    return pyb::float_(v.get<double>());
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
    // The JSON writer's names and values (enums by name), in the parameter table's order.
    const json j = params_to_json(p);
    pyb::dict d;
    for (const ParamInfo& info : param_table())
        d[info.name] = from_json(j.at(info.name));
    return d;
}

pyb::list param_table_python() {
    const pyb::dict defaults = params_to_python(Params());
    pyb::list out;
    for (const ParamInfo& info : param_table()) {
        pyb::dict row;
        row["name"] = info.name;
        switch (info.type) {
        case ParamType::Float:
            row["type"] = "float";
            break;
        case ParamType::Color:
            row["type"] = "color3";
            break;
        case ParamType::Vector:
            row["type"] = "vector3";
            break;
        case ParamType::Enum:
            row["type"] = "string";
            break;
        case ParamType::Bool:
            row["type"] = "boolean";
            break;
        }
        row["default"] = defaults[info.name];
        if (info.type == ParamType::Enum) row["values"] = enum_values(info);
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
