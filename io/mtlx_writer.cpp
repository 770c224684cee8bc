#include "mtlx_writer.h"

#include <cctype>
#include <cstdio>
#include <fstream>
#include <type_traits>

#include "error.h"
#include "mtlx_reader.h"

namespace retroprism {

namespace {

// Nine significant digits: every float the shaders see, and every value printed with six.
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

bool is_mtlx_name(const std::string& s) {
    if (s.empty() || !(std::isalpha((unsigned char)s[0]) || s[0] == '_')) return false;
    for (char c : s)
        if (!(std::isalnum((unsigned char)c) || c == '_')) return false;
    return true;
}

// An XML comment cannot hold "--".
std::string comment_text(std::string s) {
    for (size_t at = s.find("--"); at != std::string::npos; at = s.find("--", at))
        s.replace(at, 2, "- -");
    return s;
}

std::string input_line(const ParamInfo& info, const char* type, const std::string& value) {
    return std::string("    <input name=\"") + info.name + "\" type=\"" + type + "\" value=\"" +
           value + "\" />\n";
}

std::string bsdf_inputs(const Params& p) {
    std::string out;
    for_each_input(p, [&](const ParamInfo& info, const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, double>) {
            out += input_line(info, "float", num(v));
        } else if constexpr (std::is_same_v<T, Color3>) {
            if (info.type == ParamType::Color)
                out += input_line(info, "color3", num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]));
        } else if constexpr (std::is_same_v<T, int>) {
            // An integer enum (the nodedef's enumvalues 0, 1, ...), its name in a comment.
            std::string line = input_line(info, "integer", std::to_string(v));
            line.insert(line.size() - 1, " <!-- " + enum_values(info).at(size_t(v)) + " -->");
            out += line;
        } else {
            out += input_line(info, "boolean", v ? "true" : "false");
        }
    });
    return out;
}

} // namespace

std::string mtlx_document(const std::vector<MtlxMaterialOut>& materials,
                          const std::vector<std::string>& comment) {
    std::string doc = "<?xml version=\"1.0\"?>\n";
    if (!comment.empty()) {
        doc += "<!--\n";
        for (const std::string& line : comment)
            doc += "  " + comment_text(line) + "\n";
        doc += "-->\n";
    }
    doc += "<materialx version=\"1.39\" colorspace=\"" + std::string(kMtlxWorkingSpace) + "\">\n";
    for (const MtlxMaterialOut& m : materials) {
        if (!is_mtlx_name(m.name))
            throw InputError("material name \"" + m.name +
                             "\": expected a MaterialX name (a letter or '_', then letters, digits "
                             "or '_')");
        const std::string bsdf = m.name + "_bsdf", surface = m.name + "_surface";
        doc += "  <" + std::string(kMtlxNodeCategory) + " name=\"" + bsdf + "\" type=\"BSDF\">\n";
        doc += bsdf_inputs(m.params);
        doc += "  </" + std::string(kMtlxNodeCategory) + ">\n";
        doc += "  <surface name=\"" + surface + "\" type=\"surfaceshader\">\n";
        doc += "    <input name=\"bsdf\" type=\"BSDF\" nodename=\"" + bsdf + "\" />\n";
        doc += "  </surface>\n";
        doc += "  <surfacematerial name=\"" + m.name + "\" type=\"material\">\n";
        doc += "    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"" + surface +
               "\" />\n";
        doc += "  </surfacematerial>\n";
    }
    return doc + "</materialx>\n";
}

void write_mtlx(const std::string& path, const std::vector<MtlxMaterialOut>& materials,
                const std::vector<std::string>& comment) {
    const std::string text = mtlx_document(materials, comment);
    std::ofstream f(path, std::ios::binary);
    if (!f || !(f << text) || (f.close(), !f))
        throw InputError(path + ": cannot write the document");
}

} // namespace retroprism
