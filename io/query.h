// query.h: the JSON queries every backend answers (`retroprism eval`) and the JSON material
// reader. Inputs are named and ranged by the node's parameter table.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "error.h"
#include "prismatic_retroreflector.h"

namespace retroprism {

// Reads a JSON document from a file, or from standard input when path is "-".
nlohmann::json read_json(const std::string& path);

// The node's parameters from a JSON object `{<input>: value}`: floats as numbers, colours as
// [r, g, b], enums as one of their strings, vectors as [x, y, z]. Omitted inputs take their
// defaults; unknown names, wrong types and values outside the table's range are InputErrors
// naming `where` (e.g. "query.json: material").
Params params_from_json(const nlohmann::json& j, const std::string& where);
nlohmann::json params_to_json(const Params& p);

struct DirectionPair {
    Vec3d wi;
    Vec3d wo;
};

struct Query {
    Params material;
    std::vector<DirectionPair> samples;
};

// {"material": {...}, "samples": [{"wi": [x,y,z], "wo": [x,y,z]} | {"wi_deg": [theta, phi],
// "wo_deg": [theta, phi]}, ...]}. Directions need not be unit; they must be finite.
Query parse_query(const nlohmann::json& j, const std::string& source);

// The parameter table as Markdown (name, type, default, range or values, description): the
// inputs table of docs/model.md is this text.
std::string params_markdown();

// The parameter table as JSON, an array in table order of {"name", "type" (MaterialX's: float,
// color3, string, boolean, vector3), "default" (as params_to_json writes it), "doc", and for
// floats and colours "min" and "max" (per channel), for enums "values", for vectors
// "geomprop"; "uniform": true for enums and booleans}: what the look-dev page builds its
// controls from (`retroprism params --json`).
nlohmann::json params_table_json();

} // namespace retroprism
