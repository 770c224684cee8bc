#include "query.h"
#include "text_file.h"

#include <cmath>
#include <iostream>
#include <sstream>

namespace retroprism {

using nlohmann::json;

json read_json(const std::string& path) {
    std::string text;
    if (path == "-") {
        std::stringstream ss;
        ss << std::cin.rdbuf();
        text = ss.str();
    } else {
        text = read_text_file(path);
    }
    const std::string name = path == "-" ? "<stdin>" : path;
    // "file:line:column" of a byte offset.
    auto where = [&](size_t byte) {
        size_t line = 1, col = 1;
        for (size_t i = 0; i < byte && i < text.size(); ++i) {
            if (text[i] == '\n') {
                ++line;
                col = 1;
            } else {
                ++col;
            }
        }
        return name + ":" + std::to_string(line) + ":" + std::to_string(col);
    };
    try {
        return json::parse(text);
    } catch (const json::parse_error& e) {
        // nlohmann gives the byte offset of the error.
        throw InputError(where(e.byte) + ": invalid JSON (" + e.what() + ")");
    } catch (const json::out_of_range& e) {
        // A number beyond double's range (error 406, "number overflow parsing '1e400'"): no
        // offset is given, so the number's first occurrence in the text is reported.
        const std::string msg = e.what();
        const size_t open = msg.find("parsing '");
        const size_t close = open == std::string::npos ? open : msg.find('\'', open + 9);
        size_t at = std::string::npos;
        if (close != std::string::npos) at = text.find(msg.substr(open + 9, close - open - 9));
        throw InputError((at == std::string::npos ? name : where(at)) +
                         ": a number beyond double's range (" + msg + ")");
    }
}

namespace {

std::string range_text(double lo, double hi) {
    std::ostringstream ss;
    ss << "[" << lo << ", " << hi << "]";
    return ss.str();
}

double number_in_range(const json& v, const std::string& field, double lo, double hi) {
    if (!v.is_number()) throw InputError(field + ": expected a number in " + range_text(lo, hi));
    double x = v.get<double>();
    if (!std::isfinite(x) || x < lo || x > hi) {
        std::ostringstream ss;
        ss << field << " = " << x << " is outside its range " << range_text(lo, hi);
        throw InputError(ss.str());
    }
    return x;
}

Vec3d vector3(const json& v, const std::string& field, double lo, double hi) {
    if (!v.is_array() || v.size() != 3)
        throw InputError(field + ": expected an array of 3 numbers in " + range_text(lo, hi));
    Vec3d out;
    for (int c = 0; c < 3; ++c)
        out[c] = number_in_range(v[c], field + "[" + std::to_string(c) + "]", lo, hi);
    return out;
}

Vec3d direction(const json& v, const std::string& field) {
    const double big = 1e30;
    Vec3d d = vector3(v, field, -big, big);
    double len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (!(len2 > 0)) throw InputError(field + ": a direction must not be the zero vector");
    return d;
}

Vec3d direction_deg(const json& v, const std::string& field) {
    if (!v.is_array() || v.size() != 2)
        throw InputError(field + ": expected [theta, phi] in degrees, theta in [0, 180]");
    double theta = number_in_range(v[0], field + "[0] (theta)", 0.0, 180.0);
    double phi = number_in_range(v[1], field + "[1] (phi)", -360.0, 360.0);
    const double t = theta * M_PI / 180.0, p = phi * M_PI / 180.0;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

} // namespace

Params params_from_json(const json& j, const std::string& where) {
    if (!j.is_object()) throw InputError(where + ": expected an object of node inputs");
    Params p;
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string field = where + "." + it.key();
        const ParamInfo* info = find_param(it.key());
        if (!info) {
            std::string names;
            for (const ParamInfo& i : param_table())
                names += std::string(names.empty() ? "" : ", ") + i.name;
            throw InputError(field + ": unknown input (inputs: " + names + ")");
        }
        const json& v = it.value();
        const std::string name = info->name;
        switch (info->type) {
        case ParamType::Float:
            *input_field<double>(p, name) =
                number_in_range(v, field, info->min_value, info->max_value);
            break;
        case ParamType::Color:
            *input_field<Vec3d>(p, name) = vector3(v, field, info->min_value, info->max_value);
            break;
        case ParamType::Enum: {
            const int idx = v.is_string() ? enum_index(*info, v.get<std::string>()) : -1;
            if (idx < 0)
                throw InputError(field + ": expected one of \"" + info->enum_values + "\"");
            *input_field<int>(p, name) = idx;
            break;
        }
        case ParamType::Vector:
            *input_field<Vec3d>(p, name) = direction(v, field);
            break;
        case ParamType::Bool:
            if (!v.is_boolean()) throw InputError(field + ": expected true or false");
            *input_field<bool>(p, name) = v.get<bool>();
            break;
        }
    }
    return p;
}

json params_to_json(const Params& p) {
    json j = json::object();
    for (const ParamInfo& info : param_table()) {
        switch (info.type) {
        case ParamType::Float:
            j[info.name] = *input_field<double>(p, info.name);
            break;
        case ParamType::Color:
        case ParamType::Vector:
            j[info.name] = *input_field<Vec3d>(p, info.name);
            break;
        case ParamType::Enum:
            j[info.name] = enum_values(info).at(size_t(*input_field<int>(p, info.name)));
            break;
        case ParamType::Bool:
            j[info.name] = *input_field<bool>(p, info.name);
            break;
        }
    }
    return j;
}

Query parse_query(const json& j, const std::string& source) {
    if (!j.is_object())
        throw InputError(source + ": expected an object with \"material\" and \"samples\"");
    for (auto it = j.begin(); it != j.end(); ++it)
        if (it.key() != "material" && it.key() != "samples")
            throw InputError(source + ": unknown field \"" + it.key() +
                             "\" (fields: material, samples)");
    Query q;
    if (j.contains("material")) q.material = params_from_json(j["material"], source + ": material");
    if (!j.contains("samples") || !j["samples"].is_array())
        throw InputError(
            source +
            ": \"samples\" must be an array of {\"wi\", \"wo\"} or {\"wi_deg\", \"wo_deg\"}");
    const json& samples = j["samples"];
    q.samples.reserve(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
        const std::string where = source + ": samples[" + std::to_string(i) + "]";
        const json& s = samples[i];
        if (!s.is_object()) throw InputError(where + ": expected an object");
        DirectionPair d;
        const bool cart = s.contains("wi") || s.contains("wo");
        const bool deg = s.contains("wi_deg") || s.contains("wo_deg");
        if (cart == deg || s.size() != 2)
            throw InputError(where + ": give exactly \"wi\" and \"wo\" ([x, y, z]) or \"wi_deg\" "
                                     "and \"wo_deg\" ([theta, phi])");
        if (cart) {
            if (!s.contains("wi") || !s.contains("wo"))
                throw InputError(where + ": needs both \"wi\" and \"wo\"");
            d.wi = direction(s["wi"], where + ".wi");
            d.wo = direction(s["wo"], where + ".wo");
        } else {
            if (!s.contains("wi_deg") || !s.contains("wo_deg"))
                throw InputError(where + ": needs both \"wi_deg\" and \"wo_deg\"");
            d.wi = direction_deg(s["wi_deg"], where + ".wi_deg");
            d.wo = direction_deg(s["wo_deg"], where + ".wo_deg");
        }
        q.samples.push_back(d);
    }
    return q;
}

std::string params_markdown() {
    auto num = [](double v) {
        std::ostringstream ss;
        ss << v;
        return ss.str();
    };
    std::string out = "| input | type | default | range / values | description |\n"
                      "|---|---|---|---|---|\n";
    for (const ParamInfo& i : param_table()) {
        std::string type, def, range;
        switch (i.type) {
        case ParamType::Float:
            type = "float";
            def = num(i.default_value[0]);
            range = "[" + num(i.min_value) + ", " + num(i.max_value) + "]";
            break;
        case ParamType::Color:
            type = "color3";
            def = num(i.default_value[0]) + ", " + num(i.default_value[1]) + ", " +
                  num(i.default_value[2]);
            range = "[0, 1] per channel";
            break;
        case ParamType::Enum:
            // Its names in JSON, the CLI and Python; in MaterialX an integer enum of the values
            // in parentheses.
            type = "enum (uniform)";
            def = enum_values(i).at(size_t(i.default_value[0]));
            for (const std::string& name : enum_values(i))
                range += (range.empty() ? "" : ", ") + name + " (" +
                         std::to_string(enum_index(i, name)) + ")";
            break;
        case ParamType::Bool:
            type = "boolean (uniform)";
            def = i.default_value[0] != 0 ? "true" : "false";
            range = "true, false";
            break;
        case ParamType::Vector:
            type = "vector3";
            def = std::string(i.geomprop) + " (" + num(i.default_value[0]) + ", " +
                  num(i.default_value[1]) + ", " + num(i.default_value[2]) + ")";
            range = "any non-zero";
            break;
        }
        out += "| `" + std::string(i.name) + "` | " + type + " | " + def + " | " + range + " | " +
               i.doc + " |\n";
    }
    return out;
}

json params_table_json() {
    const json defaults = params_to_json(Params{});
    json table = json::array();
    for (const ParamInfo& i : param_table()) {
        json e = {{"name", i.name}, {"default", defaults.at(i.name)}, {"doc", i.doc}};
        switch (i.type) {
        case ParamType::Float:
            e["type"] = "float";
            e["min"] = i.min_value;
            e["max"] = i.max_value;
            break;
        case ParamType::Color:
            e["type"] = "color3";
            e["min"] = 0.0;
            e["max"] = 1.0;
            break;
        case ParamType::Enum:
            e["type"] = "string";
            e["values"] = enum_values(i);
            e["uniform"] = true;
            break;
        case ParamType::Bool:
            e["type"] = "boolean";
            e["uniform"] = true;
            break;
        case ParamType::Vector:
            e["type"] = "vector3";
            e["geomprop"] = i.geomprop;
            break;
        }
        table.push_back(e);
    }
    return table;
}

} // namespace retroprism
