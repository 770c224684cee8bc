#include "mtlx_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>

#include <pugixml.hpp>

#include "parse.h"
#include "query.h"
#include "text_file.h"

namespace retroprism {

namespace {

// Attributes that connect an input instead of giving it a value.
const char* const kConnectionAttributes[] = {"nodename", "nodegraph", "output", "interfacename"};

std::string join(const std::vector<std::string>& v, const char* sep = ", ") {
    std::string out;
    for (const std::string& s : v)
        out += (out.empty() ? "" : sep) + s;
    return out;
}

const char* mtlx_type(ParamType t) {
    switch (t) {
    case ParamType::Float:
        return "float";
    case ParamType::Color:
        return "color3";
    case ParamType::Enum:
        return "integer"; // an integer enum: enumvalues 0, 1, ... stand for the names
    case ParamType::Vector:
        return "vector3";
    case ParamType::Bool:
        return "boolean";
    }
    return "?";
}

// The reading context: the file's text for line numbers, and error formatting.
class Reader {
  public:
    Reader(const std::string& text, const std::string& name) : name_(name) {
        lineStarts_.push_back(0);
        for (size_t i = 0; i < text.size(); ++i)
            if (text[i] == '\n') lineStarts_.push_back(i + 1);
    }

    int line_of(ptrdiff_t offset) const {
        if (offset < 0) return 0;
        auto it = std::upper_bound(lineStarts_.begin(), lineStarts_.end(), size_t(offset));
        return int(it - lineStarts_.begin());
    }
    int line(const pugi::xml_node& n) const { return line_of(n.offset_debug()); }

    // <category name="..."> of an element.
    static std::string describe(const pugi::xml_node& n) {
        std::string s = std::string("<") + n.name();
        if (n.attribute("name")) s += std::string(" name=\"") + n.attribute("name").value() + "\"";
        return s + ">";
    }
    // An input, with the node it belongs to.
    static std::string describe_input(const pugi::xml_node& input) {
        return describe(input) + " of " + describe(input.parent());
    }

    [[noreturn]] void fail(const pugi::xml_node& n, const std::string& msg) const {
        const std::string what = std::string(n.name()) == "input" ? describe_input(n) : describe(n);
        throw InputError(name_ + ":" + std::to_string(line(n)) + ": " + what + ": " + msg);
    }
    [[noreturn]] void fail_at(ptrdiff_t offset, const std::string& msg) const {
        const int l = line_of(offset);
        const size_t col = offset >= 0 ? size_t(offset) - lineStarts_[size_t(l - 1)] + 1 : 0;
        throw InputError(name_ + ":" + std::to_string(l) + ":" + std::to_string(col) + ": " + msg);
    }

    const std::string& name() const { return name_; }

  private:
    std::string name_;
    std::vector<size_t> lineStarts_;
};

bool parse_float(const std::string& text, double& v) {
    const std::optional<double> x = try_parse_number(trim(text));
    if (x) v = *x;
    return x.has_value();
}

// "x, y, z" (MaterialX's vector and colour syntax).
bool parse_vec3(const std::string& text, Vec3d& v) {
    std::vector<std::string> parts;
    std::string cur;
    for (char c : text) {
        if (c == ',') {
            parts.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    parts.push_back(cur);
    if (parts.size() != 3) return false;
    for (int k = 0; k < 3; ++k)
        if (!parse_float(parts[size_t(k)], v[size_t(k)])) return false;
    return true;
}

bool is_known_colorspace(const std::string& cs) {
    const auto& all = mtlx_colorspaces();
    return std::find(all.begin(), all.end(), cs) != all.end();
}

void check_colorspace_attribute(const Reader& r, const pugi::xml_node& n) {
    const pugi::xml_attribute a = n.attribute("colorspace");
    if (a && !is_known_colorspace(a.value()))
        r.fail(n, std::string("colorspace \"") + a.value() +
                      "\" is not supported; expected one of " + join(mtlx_colorspaces()));
}

// Children of a node element must be <input>s with distinct names; returns them by name.
std::map<std::string, pugi::xml_node> inputs_of(const Reader& r, const pugi::xml_node& node) {
    std::map<std::string, pugi::xml_node> out;
    for (pugi::xml_node c : node.children()) {
        if (c.type() != pugi::node_element) continue;
        if (std::string(c.name()) != "input")
            r.fail(c, std::string("unsupported element inside ") + Reader::describe(node) +
                          "; only <input> elements with constant values are supported");
        const std::string name = c.attribute("name").value();
        if (name.empty()) r.fail(c, "an <input> needs a name attribute");
        if (!c.attribute("type")) r.fail(c, "an <input> needs a type attribute");
        auto prev = out.find(name);
        if (prev != out.end())
            r.fail(c,
                   "duplicate input (first at line " + std::to_string(r.line(prev->second)) + ")");
        out[name] = c;
    }
    return out;
}

bool is_connected(const pugi::xml_node& input) {
    for (const char* a : kConnectionAttributes)
        if (input.attribute(a)) return true;
    return false;
}

// A constant input: no connection attribute, a value attribute, the expected type.
std::string constant_value(const Reader& r, const pugi::xml_node& input, const char* type) {
    if (std::string(input.attribute("type").value()) != type)
        r.fail(input, std::string("type \"") + input.attribute("type").value() + "\", expected \"" +
                          type + "\"");
    for (const char* a : kConnectionAttributes)
        if (input.attribute(a))
            r.fail(input, std::string("connected inputs (") + a + "=\"" +
                              input.attribute(a).value() +
                              "\") are not supported here; give a constant value=\"...\"");
    if (!input.attribute("value")) r.fail(input, "needs a constant value=\"...\" attribute");
    return input.attribute("value").value();
}

// The element a connected input (nodename=...) points to.
pugi::xml_node connected_node(const Reader& r, const pugi::xml_node& input, const char* type,
                              const std::map<std::string, pugi::xml_node>& nodes) {
    if (std::string(input.attribute("type").value()) != type)
        r.fail(input, std::string("type \"") + input.attribute("type").value() + "\", expected \"" +
                          type + "\"");
    for (const char* a : {"nodegraph", "output", "interfacename"})
        if (input.attribute(a))
            r.fail(input, std::string("connections through ") + a +
                              "= are not supported; connect with nodename=\"...\" to a node of "
                              "this document");
    const std::string target = input.attribute("nodename").value();
    if (target.empty())
        r.fail(input, "must be connected with nodename=\"...\" to a node of this document");
    auto it = nodes.find(target);
    if (it == nodes.end())
        r.fail(input, "nodename=\"" + target + "\": no node of that name in the document");
    return it->second;
}

void set_param(const Reader& r, const pugi::xml_node& input, const ParamInfo& info,
               const std::string& text, Params& p, MtlxColorInput& color) {
    const std::string name = info.name;
    const std::string range =
        "[" + number_text(info.min_value) + ", " + number_text(info.max_value) + "]";
    switch (info.type) {
    case ParamType::Float: {
        double v;
        if (!parse_float(text, v))
            r.fail(input, "value \"" + text + "\" is not a number; expected a float in " + range);
        if (v < info.min_value || v > info.max_value)
            r.fail(input, "value " + number_text(v) + " is outside its range " + range);
        *input_field<double>(p, name) = v;
        break;
    }
    case ParamType::Color: {
        Vec3d v;
        if (!parse_vec3(text, v))
            r.fail(input, "value \"" + text +
                              "\" is not a color3; expected three numbers \"r, g, b\" in [0, 1]");
        for (int k = 0; k < 3; ++k)
            if (v[size_t(k)] < 0.0 || v[size_t(k)] > 1.0)
                r.fail(input, "component " + std::to_string(k) + " = " + number_text(v[size_t(k)]) +
                                  " is outside its range [0, 1]");
        color.value = v;
        *input_field<Color3>(p, name) = v;
        break;
    }
    case ParamType::Enum: {
        // type="integer": the enum's value (0, 1, ...); type="string": its name, the form of
        // documents written before the node's enums were integers.
        const std::vector<std::string> names = enum_values(info);
        std::string allowed;
        for (size_t k = 0; k < names.size(); ++k)
            allowed += (k ? ", " : "") + std::to_string(k) + " (" + names[k] + ")";
        int idx = -1;
        if (std::string(input.attribute("type").value()) == "string") {
            idx = enum_index(info, text);
            if (idx < 0)
                r.fail(input, "value \"" + text + "\" is not one of " + join(names) +
                                  " (or give type=\"integer\" with one of " + allowed + ")");
        } else {
            const std::string t = trim(text);
            for (size_t k = 0; k < names.size(); ++k)
                if (t == std::to_string(k)) idx = int(k);
            if (idx < 0)
                r.fail(input, "value \"" + text + "\" is not one of the integers " + allowed);
        }
        *input_field<int>(p, name) = idx;
        break;
    }
    case ParamType::Vector: {
        Vec3d v;
        if (!parse_vec3(text, v))
            r.fail(input, "value \"" + text + "\" is not a vector3; expected \"x, y, z\"");
        if (!(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0.0))
            r.fail(input, "a direction must not be the zero vector");
        *input_field<Vec3d>(p, name) = v;
        break;
    }
    case ParamType::Bool: {
        const std::string t = trim(text);
        if (t != "true" && t != "false")
            r.fail(input, "value \"" + text + "\" is not a boolean; expected true or false");
        *input_field<bool>(p, name) = t == "true";
        break;
    }
    }
}

// The rp_prismatic_retroreflector_bsdf node's inputs into `m`.
void read_bsdf(const Reader& r, const MtlxDocument& doc, const pugi::xml_node& node,
               MtlxMaterial& m) {
    if (std::string(node.attribute("type").value()) != "BSDF")
        r.fail(node, std::string("type \"") + node.attribute("type").value() +
                         "\", expected type=\"BSDF\"");
    check_colorspace_attribute(r, node);
    m.bsdf = node.attribute("name").value();
    m.bsdf_line = r.line(node);
    m.params = Params();
    m.inputs.clear();
    m.colors.clear();
    // Inputs in document order (inputs_of checks names and duplicates).
    inputs_of(r, node);
    for (pugi::xml_node input : node.children("input")) {
        const std::string name = input.attribute("name").value();
        const ParamInfo* info = find_param(name);
        if (!info) {
            std::vector<std::string> names;
            for (const ParamInfo& i : param_table())
                names.push_back(i.name);
            r.fail(input, "unknown input of " + std::string(kMtlxNodeCategory) +
                              " (inputs: " + join(names) + ")");
        }
        // An enum also reads as its name with type="string" (set_param).
        const bool legacyEnum = info->type == ParamType::Enum &&
                                std::string(input.attribute("type").value()) == "string";
        const std::string text =
            constant_value(r, input, legacyEnum ? "string" : mtlx_type(info->type));
        check_colorspace_attribute(r, input);
        MtlxColorInput color;
        set_param(r, input, *info, text, m.params, color);
        m.inputs.push_back(name);
        if (info->type == ParamType::Color) {
            color.input = name;
            color.line = r.line(input);
            if (input.attribute("colorspace"))
                color.colorspace = input.attribute("colorspace").value();
            else if (node.attribute("colorspace"))
                color.colorspace = node.attribute("colorspace").value();
            else if (!doc.colorspace.empty())
                color.colorspace = doc.colorspace;
            else
                color.colorspace = kMtlxWorkingSpace;
            m.colors.push_back(color);
        }
    }
}

// The surface node: bsdf -> the retroreflector node; opacity 1 and thin_walled false allowed.
pugi::xml_node read_surface(const Reader& r, const pugi::xml_node& surface,
                            const std::map<std::string, pugi::xml_node>& nodes) {
    if (std::string(surface.attribute("type").value()) != "surfaceshader")
        r.fail(surface, std::string("type \"") + surface.attribute("type").value() +
                            "\", expected type=\"surfaceshader\"");
    pugi::xml_node bsdf;
    for (const auto& kv : inputs_of(r, surface)) {
        const std::string& name = kv.first;
        const pugi::xml_node& input = kv.second;
        if (name == "bsdf") {
            bsdf = connected_node(r, input, "BSDF", nodes);
            if (std::string(bsdf.name()) != kMtlxNodeCategory)
                r.fail(input, "connected to " + Reader::describe(bsdf) + " (line " +
                                  std::to_string(r.line(bsdf)) + "); expected a <" +
                                  kMtlxNodeCategory + "> node");
        } else if (name == "edf") {
            if (is_connected(input) || trim(input.attribute("value").value()) != "")
                r.fail(input, "emission is not supported; leave the edf input out");
        } else if (name == "opacity") {
            double v;
            if (!parse_float(constant_value(r, input, "float"), v) || v != 1.0)
                r.fail(input, "only opacity 1 is supported (the preview renders opaque surfaces)");
        } else if (name == "thin_walled") {
            if (trim(constant_value(r, input, "boolean")) != "false")
                r.fail(input, "only thin_walled = false is supported");
        } else {
            r.fail(input, "unknown input of <surface> (inputs: bsdf, edf, opacity, thin_walled)");
        }
    }
    if (!bsdf)
        r.fail(surface,
               std::string("needs an input bsdf (type BSDF) connected with nodename to a <") +
                   kMtlxNodeCategory + "> node");
    return bsdf;
}

} // namespace

const std::vector<std::string>& mtlx_colorspaces() {
    static const std::vector<std::string> names = {
        "lin_rec709",    "srgb_texture",   "g22_rec709",   "g18_rec709",
        "acescg",        "lin_ap1",        "g22_ap1",      "g18_ap1",
        "lin_displayp3", "srgb_displayp3", "lin_adobergb", "adobergb"};
    return names;
}

MtlxDocument parse_mtlx(const std::string& text, const std::string& name) {
    const Reader r(text, name);
    pugi::xml_document xml;
    const pugi::xml_parse_result res = xml.load_buffer(text.data(), text.size());
    if (!res) r.fail_at(res.offset, std::string("malformed XML: ") + res.description());

    MtlxDocument doc;
    doc.file = name;
    const pugi::xml_node root = xml.document_element();
    if (!root) r.fail_at(0, "empty document; expected a <materialx> element");
    if (std::string(root.name()) != "materialx")
        r.fail(root, "expected the root element <materialx version=\"1.39\">");
    doc.version = root.attribute("version").value();
    {
        int major = 0, minor = 0;
        char dot = 0;
        std::istringstream vs(doc.version);
        if (doc.version.empty() || !(vs >> major >> dot >> minor) || dot != '.' || major != 1 ||
            minor < 38)
            r.fail(root, "version=\"" + doc.version +
                             "\": expected a MaterialX version 1.38 or later, e.g. "
                             "version=\"1.39\"");
    }
    if (root.attribute("namespace"))
        r.fail(root, "namespaces (namespace=\"...\") are not supported");
    check_colorspace_attribute(r, root);
    doc.colorspace = root.attribute("colorspace").value();

    // Top-level elements: only the three categories of the chain, with unique names.
    std::map<std::string, pugi::xml_node> nodes;
    std::vector<pugi::xml_node> ordered, materials;
    for (pugi::xml_node n : root.children()) {
        if (n.type() != pugi::node_element) continue;
        const std::string cat = n.name();
        if (cat == "nodegraph")
            r.fail(n, "node graphs are not supported; this reader takes the chain surfacematerial "
                      "-> surface -> " +
                          std::string(kMtlxNodeCategory) + " with constant inputs");
        if (cat != "surfacematerial" && cat != "surface" && cat != kMtlxNodeCategory)
            r.fail(n, "unsupported element (node category or element \"" + cat +
                          "\"); a document may hold only <surfacematerial>, <surface> and <" +
                          kMtlxNodeCategory + "> nodes with constant inputs");
        const std::string nm = n.attribute("name").value();
        if (nm.empty()) r.fail(n, "needs a name attribute");
        auto prev = nodes.find(nm);
        if (prev != nodes.end())
            r.fail(n, "duplicate name \"" + nm + "\" (first used at line " +
                          std::to_string(r.line(prev->second)) + ")");
        nodes[nm] = n;
        ordered.push_back(n);
        if (cat == "surfacematerial") materials.push_back(n);
    }
    if (materials.empty())
        r.fail(root,
               "no <surfacematerial> in the document; expected <surfacematerial "
               "type=\"material\"> with an input surfaceshader connected to a <surface> node");

    // Every node is checked in document order, used or not.
    for (const pugi::xml_node& n : ordered)
        if (std::string(n.name()) == kMtlxNodeCategory) {
            MtlxMaterial scratch;
            read_bsdf(r, doc, n, scratch);
        } else if (std::string(n.name()) == "surface") {
            read_surface(r, n, nodes);
        }

    for (const pugi::xml_node& mat : materials) {
        MtlxMaterial m;
        m.name = mat.attribute("name").value();
        m.line = r.line(mat);
        if (std::string(mat.attribute("type").value()) != "material")
            r.fail(mat, std::string("type \"") + mat.attribute("type").value() +
                            "\", expected type=\"material\"");
        pugi::xml_node surface;
        for (const auto& kv : inputs_of(r, mat)) {
            if (kv.first == "surfaceshader") {
                surface = connected_node(r, kv.second, "surfaceshader", nodes);
                if (std::string(surface.name()) != "surface")
                    r.fail(kv.second, "connected to " + Reader::describe(surface) + " (line " +
                                          std::to_string(r.line(surface)) +
                                          "); expected a <surface> node of type surfaceshader");
            } else if (kv.first == "backsurfaceshader" || kv.first == "displacementshader") {
                r.fail(kv.second, "not supported; a material here has only a surfaceshader");
            } else {
                r.fail(kv.second, "unknown input of <surfacematerial> (expected surfaceshader)");
            }
        }
        if (!surface)
            r.fail(mat, "needs an input surfaceshader (type surfaceshader) connected with nodename "
                        "to a <surface> node");
        m.surface = surface.attribute("name").value();
        read_bsdf(r, doc, read_surface(r, surface, nodes), m);
        doc.materials.push_back(std::move(m));
    }
    return doc;
}

MtlxOutline outline_mtlx_text(const std::string& text, const std::string& name) {
    const Reader r(text, name);
    pugi::xml_document xml;
    const pugi::xml_parse_result res = xml.load_buffer(text.data(), text.size());
    if (!res) r.fail_at(res.offset, std::string("malformed XML: ") + res.description());
    const pugi::xml_node root = xml.document_element();
    if (!root || std::string(root.name()) != "materialx")
        r.fail_at(0, "expected the root element <materialx version=\"1.39\">");
    MtlxOutline out;
    for (pugi::xml_node n : root.children()) {
        if (n.type() != pugi::node_element) continue;
        const std::string cat = n.name();
        if (cat == "surfacematerial") out.materials.push_back(n.attribute("name").value());
        const bool chain = cat == "surfacematerial" || cat == "surface" || cat == kMtlxNodeCategory;
        if (!chain) {
            if (std::find(out.otherCategories.begin(), out.otherCategories.end(), cat) ==
                out.otherCategories.end())
                out.otherCategories.push_back(cat);
            continue;
        }
        for (pugi::xml_node input : n.children("input")) {
            const bool chainLink =
                (cat == "surfacematerial" &&
                 std::string(input.attribute("name").value()) == "surfaceshader") ||
                (cat == "surface" && std::string(input.attribute("name").value()) == "bsdf");
            if (chainLink) continue;
            for (const char* a : {"nodename", "nodegraph", "output", "interfacename"})
                if (input.attribute(a)) out.connectedInputs = true;
        }
    }
    return out;
}

MtlxOutline outline_mtlx(const std::string& path) {
    return outline_mtlx_text(read_text_file(path), path);
}

std::string MtlxOutline::graph_description() const {
    std::string s;
    if (!otherCategories.empty()) s = "nodes " + join(otherCategories);
    if (connectedInputs)
        s += std::string(s.empty() ? "" : " and ") + "connected inputs of the chain's nodes";
    return s;
}

MtlxDocument read_mtlx(const std::string& path) {
    return parse_mtlx(read_text_file(path), path);
}

const MtlxMaterial& select_material(const MtlxDocument& doc, const std::string& name) {
    if (name.empty()) return doc.materials.front();
    std::vector<std::string> names;
    for (const MtlxMaterial& m : doc.materials) {
        if (m.name == name) return m;
        names.push_back(m.name);
    }
    throw InputError(doc.file + ": no material named \"" + name + "\" (materials: " + join(names) +
                     ")");
}

Params to_working_space(const MtlxDocument& doc, const MtlxMaterial& m,
                        const ColorConverter& convert) {
    Params p = m.params;
    for (const MtlxColorInput& c : m.colors) {
        if (c.colorspace == kMtlxWorkingSpace) continue;
        Color3 v = convert(c.colorspace, c.value);
        for (int k = 0; k < 3; ++k) {
            double& x = v[size_t(k)];
            if (!(x >= -1e-5 && x <= 1.0 + 1e-5)) {
                std::ostringstream ss;
                ss << doc.file << ":" << c.line << ": <input name=\"" << c.input << "\"> of <"
                   << kMtlxNodeCategory << " name=\"" << m.bsdf << "\">: (" << c.value[0] << ", "
                   << c.value[1] << ", " << c.value[2] << ") in " << c.colorspace << " is (" << v[0]
                   << ", " << v[1] << ", " << v[2] << ") in " << kMtlxWorkingSpace
                   << ", outside the input's range [0, 1] per channel";
                throw InputError(ss.str());
            }
            x = std::clamp(x, 0.0, 1.0);
        }
        const ParamInfo* info = find_param(c.input);
        if (info && info->type == ParamType::Color) *input_field<Color3>(p, c.input) = v;
    }
    return p;
}

} // namespace retroprism
