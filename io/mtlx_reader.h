// mtlx_reader.h: MaterialX documents (.mtlx) that use the node `rp_prismatic_retroreflector_bsdf`
// with constant inputs, read with pugixml.
//
// Supported: a `<materialx version="1.38" or later>` root holding only these elements:
// - `<surfacematerial name=".." type="material">` with one input surfaceshader (nodename) ->
// - `<surface name=".." type="surfaceshader">` with input bsdf (nodename), and optionally
//   opacity = 1, thin_walled = false ->
// - `<rp_prismatic_retroreflector_bsdf name=".." type="BSDF">` with constant inputs (`value`
//   attributes) named and typed as in the node's parameter table (float, color3, string enums,
//   boolean, vector3), within its ranges.
//
// Several materials may share a document; they are listed in document order. Colour inputs
// carry a colour space: the input's `colorspace` attribute, else its node's, else the
// document's, else lin_rec709 (MaterialX's default working space). The reader keeps colours as
// written and names their colour space; to_working_space() converts them.
// Anything else (node graphs, other node categories, connections other than the chain above,
// unknown or duplicate inputs, wrong types, malformed or out-of-range values, a missing chain
// element, malformed XML) is an InputError `FILE:LINE: <element name="..">: what is expected`.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "prismatic_retroreflector.h"

namespace retroprism {

// The node's category in MaterialX documents (the nodedef is the maintainer's
// materialx/ library).
inline constexpr const char* kMtlxNodeCategory = "rp_prismatic_retroreflector_bsdf";
// MaterialX's default working colour space; the node's colours are used in it.
inline constexpr const char* kMtlxWorkingSpace = "lin_rec709";

struct MtlxColorInput {
    std::string input;      // the node input (diffuse_color, retro_color)
    std::string colorspace; // its effective colour space
    Color3 value{};         // as written in the document
    int line = 0;
};

struct MtlxMaterial {
    std::string name; // the surfacematerial's name
    int line = 0;
    std::string surface; // the surface node's name
    std::string bsdf;    // the rp_prismatic_retroreflector_bsdf node's name
    int bsdf_line = 0;
    Params params;                   // the inputs as written (colours not converted)
    std::vector<std::string> inputs; // the inputs the document sets, in document order
    std::vector<MtlxColorInput> colors;
};

struct MtlxDocument {
    std::string file; // the name used in messages
    std::string version;
    std::string colorspace;              // the root's attribute, "" when absent
    std::vector<MtlxMaterial> materials; // in document order, at least one
};

MtlxDocument read_mtlx(const std::string& path);

// What a document holds, read without the reader's checks: its materials (surfacematerial
// names in document order) and what it holds beyond the chain this reader takes: the other
// top-level element categories (e.g. image, layer, mix, nodegraph; each once, in document
// order) and whether an input of the chain's nodes is connected to anything other than the
// chain (nodename, nodegraph, output or interfacename). A document with neither is the
// reader's (read_mtlx takes it or names what is wrong); one with either is a graph, which real
// MaterialX renders (backends/mx_night.h). Malformed XML or a root other than `<materialx>` is
// an InputError "FILE:LINE:COL: ...".
struct MtlxOutline {
    std::vector<std::string> materials;
    std::vector<std::string> otherCategories;
    bool connectedInputs = false;
    bool graph() const { return !otherCategories.empty() || connectedInputs; }
    // "nodes image, layer, mix" / "connected inputs of the chain's nodes": what makes it a graph.
    std::string graph_description() const;
};
MtlxOutline outline_mtlx(const std::string& path);
MtlxOutline outline_mtlx_text(const std::string& text, const std::string& name);
// The same from text in memory; `name` stands for the file in messages.
MtlxDocument parse_mtlx(const std::string& text, const std::string& name);

// The material called `name`, or the first one when `name` is empty.
const MtlxMaterial& select_material(const MtlxDocument& doc, const std::string& name);

// The colour-space names the reader accepts (MaterialX's standard names): lin_rec709,
// srgb_texture, g22_rec709, g18_rec709, acescg, lin_ap1, g22_ap1, g18_ap1, lin_displayp3,
// srgb_displayp3, lin_adobergb, adobergb.
const std::vector<std::string>& mtlx_colorspaces();

// A colour from `colorspace` to lin_rec709 (io/color.h does it with OpenColorIO).
using ColorConverter = std::function<Color3(const std::string& colorspace, const Color3& c)>;

// The material's parameters in the working space: each colour input not already in
// lin_rec709 goes through `convert`; a converted colour outside [0, 1] (beyond 1e-5, e.g. a
// saturated ACEScg colour) is an InputError naming the input, within it is clamped.
Params to_working_space(const MtlxDocument& doc, const MtlxMaterial& m,
                        const ColorConverter& convert);

} // namespace retroprism
