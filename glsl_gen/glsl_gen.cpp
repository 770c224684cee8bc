#include "glsl_gen.h"

#include "portable.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace retroprism::glsl {

namespace {

const char* const kEraNames[] = {"averaged", "matched_pair", "oriented"};
const char* const kPrismNames[] = {"ideal", "tir", "metallized"};
const char* const kEraConst[] = {"RP_ERA_AVERAGED", "RP_ERA_MATCHED_PAIR", "RP_ERA_ORIENTED"};
const char* const kPrismConst[] = {"RP_PRISM_IDEAL", "RP_PRISM_TIR", "RP_PRISM_METALLIZED"};
const char* const kFidelityNames[] = {"exact", "fast"};
const char* const kFidelityConst[] = {"RP_FIDELITY_EXACT", "RP_FIDELITY_FAST"};

const std::set<std::string>& known_features() {
    static const std::set<std::string> names = {
        "surface",          "retro",          "diffuse",       "era_averaged",
        "era_matched_pair", "era_oriented",   "prism_ideal",   "prism_tir",
        "prism_metallized", "fidelity_exact", "fidelity_fast", "canted",
        "dihedral",         "diffraction",    "node",          "cpp"};
    return names;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open file");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string trim(const std::string& s) {
    size_t a = s.find_first_not_of(" \t\r");
    size_t b = s.find_last_not_of(" \t\r");
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// "a&b|c": true when every feature of some '|'-term is kept.
bool evaluate(const std::string& expr, const std::set<std::string>& feats,
              const std::string& where) {
    std::stringstream terms(expr);
    std::string term;
    bool any = false;
    while (std::getline(terms, term, '|')) {
        std::stringstream names(term);
        std::string name;
        bool all = true;
        while (std::getline(names, name, '&')) {
            name = trim(name);
            if (!known_features().count(name))
                throw std::runtime_error(where + ": unknown feature '" + name + "' in @rp-if");
            all = all && feats.count(name) > 0;
        }
        any = any || all;
    }
    return any;
}

// Drops the "// @rp-if" regions a variant leaves out, and the marker lines themselves.
std::string select_regions(const std::string& text, const std::string& file,
                           const std::set<std::string>& feats) {
    std::stringstream in(text);
    std::string line, out;
    std::vector<bool> keep;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        const std::string where = file + ":" + std::to_string(lineNo);
        for (unsigned char c : line)
            if (c >= 0x80)
                throw std::runtime_error(where +
                                         ": non-ASCII character (GLSL sources must be ASCII)");
        const std::string t = trim(line);
        if (t.rfind("// @rp-if ", 0) == 0) {
            bool parent = keep.empty() || keep.back();
            keep.push_back(parent && evaluate(t.substr(10), feats, where));
            continue;
        }
        if (t == "// @rp-endif") {
            if (keep.empty()) throw std::runtime_error(where + ": @rp-endif without @rp-if");
            keep.pop_back();
            continue;
        }
        if (t.rfind("// @rp-", 0) == 0)
            throw std::runtime_error(where + ": unknown marker '" + t + "'");
        if (keep.empty() || keep.back()) out += line + "\n";
    }
    if (!keep.empty()) throw std::runtime_error(file + ": @rp-if without @rp-endif");
    return out;
}

// Identifier characters, for the whole-word matching below.
bool word_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// The position of the next occurrence of `word` at or after `from` that stands alone: no
// identifier character just before it when it begins with one, nor just after it when it ends
// with one (a regular expression's \b on each side). npos when there is none.
size_t find_word(const std::string& s, const std::string& word, size_t from) {
    for (size_t at = s.find(word, from); at != std::string::npos; at = s.find(word, at + 1)) {
        const size_t end = at + word.size();
        if (word_char(word.front()) && at > 0 && word_char(s[at - 1])) continue;
        if (word_char(word.back()) && end < s.size() && word_char(s[end])) continue;
        return at;
    }
    return std::string::npos;
}

// Every whole-word `word` replaced by `with`; with `readsOnly`, not where it is assigned (the
// next non-blank character an '=' that does not begin "==").
std::string replace_word(const std::string& s, const std::string& word, const std::string& with,
                         bool readsOnly = false) {
    std::string out;
    size_t from = 0;
    for (size_t at = find_word(s, word, 0); at != std::string::npos;
         at = find_word(s, word, at + word.size())) {
        if (readsOnly) {
            size_t next = s.find_first_not_of(" \t\r\n\f\v", at + word.size());
            if (next != std::string::npos && s[next] == '=' && next + 1 < s.size() &&
                s[next + 1] != '=')
                continue;
        }
        out.append(s, from, at - from);
        out += with;
        from = at + word.size();
    }
    out.append(s, from, std::string::npos);
    return out;
}

// Every whole-word call `name(identifier)` replaced by `with` followed by the identifier.
std::string replace_call(const std::string& s, const std::string& name, const std::string& with) {
    std::string out;
    size_t from = 0;
    const std::string open = name + "(";
    for (size_t at = find_word(s, open, 0); at != std::string::npos;
         at = find_word(s, open, at + open.size())) {
        size_t end = at + open.size();
        while (end < s.size() && word_char(s[end]))
            ++end;
        if (end == at + open.size() || end >= s.size() || s[end] != ')') continue;
        out.append(s, from, at - from);
        out += with + s.substr(at + open.size(), end - at - open.size());
        from = end + 1;
    }
    out.append(s, from, std::string::npos);
    return out;
}

// A GLSL float literal that round-trips a float.
std::string lit(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", x);
    std::string s = buf;
    if (s.find_first_of(".e") == std::string::npos) s += ".0";
    return s;
}

// The tables as GLSL: RP_TABLE_BEGIN(name, n) <numbers> RP_TABLE_END becomes a constant array of
// vec4 holding the n values four to a vector, at float precision (the tables carry 17 digits for
// the double C++ node, GLSL's float needs 9), and a function name_at(i) that reads value i; every
// access name[i] of the library becomes name_at(i). The values are those of the float array they
// replace. GLSL compilers handle an array constant element by element, and Mesa's time to compile
// one grows with the square of its element count: four values to an element compile the full
// library several times faster (docs/ARCHITECTURE.md).
std::string pack_tables(const std::string& text) {
    const std::string begin = "RP_TABLE_BEGIN(";
    std::string out;
    std::vector<std::string> names;
    size_t pos = 0;
    for (size_t at = find_word(text, begin, 0); at != std::string::npos;
         at = find_word(text, begin, pos)) {
        // RP_TABLE_BEGIN(name, n)
        const size_t nameStart = at + begin.size();
        size_t nameEnd = nameStart;
        while (nameEnd < text.size() && word_char(text[nameEnd]))
            ++nameEnd;
        size_t countEnd = nameEnd + 2;
        while (countEnd < text.size() && std::isdigit(static_cast<unsigned char>(text[countEnd])))
            ++countEnd;
        if (nameEnd == nameStart || text.compare(nameEnd, 2, ", ") != 0 ||
            countEnd == nameEnd + 2 || countEnd >= text.size() || text[countEnd] != ')')
            throw std::runtime_error("RP_TABLE_BEGIN at offset " + std::to_string(at) +
                                     ": not of the form RP_TABLE_BEGIN(name, count)");
        out.append(text, pos, at - pos);
        const std::string name = text.substr(nameStart, nameEnd - nameStart);
        const size_t n = std::stoul(text.substr(nameEnd + 2, countEnd - nameEnd - 2));
        const size_t bodyStart = countEnd + 1;
        const size_t bodyEnd = text.find("RP_TABLE_END", bodyStart);
        if (bodyEnd == std::string::npos)
            throw std::runtime_error("table " + name + ": no RP_TABLE_END");
        std::stringstream items(text.substr(bodyStart, bodyEnd - bodyStart));
        std::vector<std::string> values;
        std::string item;
        while (std::getline(items, item, ','))
            if (!(item = trim(item)).empty()) values.push_back(lit(std::stod(item)));
        if (values.size() != n)
            throw std::runtime_error("table " + name + ": " + std::to_string(values.size()) +
                                     " values where it declares " + std::to_string(n));
        while (values.size() % 4 != 0)
            values.push_back("0.0");
        const std::string count = std::to_string(values.size() / 4);
        out += "const vec4 " + name + "_v4[" + count + "] = vec4[" + count + "](";
        for (size_t i = 0; i < values.size(); i += 4)
            out += std::string(i % 8 == 0 ? "\n    " : " ") + "vec4(" + values[i] + ", " +
                   values[i + 1] + ", " + values[i + 2] + ", " + values[i + 3] + ")" +
                   (i + 4 < values.size() ? "," : "");
        out += ");\nfloat " + name + "_at(int i) {\n    return " + name + "_v4[i >> 2][i & 3];\n}";
        names.push_back(name);
        pos = bodyEnd + std::string("RP_TABLE_END").size();
    }
    out.append(text, pos, std::string::npos);
    // Accesses name[index] -> name_at(index), the index's own brackets matched.
    for (const std::string& name : names) {
        std::string rewritten;
        size_t from = 0;
        for (size_t at = find_word(out, name + "[", 0); at != std::string::npos;
             at = find_word(out, name + "[", from)) {
            const size_t open = at + name.size();
            size_t close = open + 1;
            for (int depth = 1; close < out.size(); ++close) {
                depth += out[close] == '[' ? 1 : out[close] == ']' ? -1 : 0;
                if (depth == 0) break;
            }
            if (close >= out.size()) throw std::runtime_error(name + "[: no closing bracket");
            rewritten += out.substr(from, open - from) + "_at(" +
                         out.substr(open + 1, close - open - 1) + ")";
            from = close + 1;
        }
        out = rewritten + out.substr(from);
    }
    return out;
}

// A variant's fixed modes as constants wherever they are read (their assignment in
// rp_prepare stays).
std::string fix_modes(std::string s, const Variant& v);

std::string fix_modes(std::string s, const Variant& v) {
    // A fixed mode is a constant wherever it is read (its assignment in rp_prepare stays).
    if (v.era_mode >= 0) s = replace_word(s, "m.era_mode", kEraConst[v.era_mode], true);
    if (v.prism_reflection >= 0)
        s = replace_word(s, "m.prism_reflection", kPrismConst[v.prism_reflection], true);
    if (v.fidelity >= 0) {
        s = replace_word(s, "m.fidelity", kFidelityConst[v.fidelity], true);
        s = replace_word(s,
                         "(fidelity == ", std::string("(") + kFidelityConst[v.fidelity] + " == ");
    }
    return s;
}

// The common-subset spellings as GLSL.
std::string to_glsl(std::string s, const Variant& v) {
    s = fix_modes(s, v);
    for (const char* fn : {"RP_FN ", "RP_FN_HOT ", "RP_FN_COLD "})
        s = replace_word(s, fn, "");
    s = replace_call(s, "RP_OUT", "out ");
    s = replace_call(s, "RP_INOUT", "inout ");
    s = replace_call(s, "RP_IN", "in ");
    return replace_word(s, "real", "float");
}

std::string entry_point(const Variant& v) {
    std::string sanitize;
    int enumIndex = 0;
#define RP_FLOAT(name, def, lo, hi, doc)                                                           \
    sanitize += "    " #name " = rp_sanitize(" #name ", " + lit(lo) + ", " + lit(hi) + ", " +      \
                lit(def) + ");\n";
#define RP_COLOR(name, r, g, b, doc)                                                               \
    sanitize += "    " #name " = vec3(rp_sanitize(" #name ".x, 0.0, 1.0, " + lit(r) +              \
                "), rp_sanitize(" #name ".y, 0.0, 1.0, " + lit(g) +                                \
                "), rp_sanitize(" #name ".z, 0.0, 1.0, " + lit(b) + "));\n";
#define RP_ENUM(name, def, values, doc)                                                            \
    {                                                                                              \
        int count = 1;                                                                             \
        for (const char* c = values; *c; ++c)                                                      \
            count += *c == ',';                                                                    \
        sanitize += "    if (" #name " < 0 || " #name " > " + std::to_string(count - 1) +          \
                    ") " #name " = " + std::to_string(def) + ";\n";                                \
        ++enumIndex;                                                                               \
    }
#define RP_VECTOR(name, x, y, z, geomprop, doc)
#define RP_BOOL(name, def, doc)
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
    (void)enumIndex;
    std::string fixed;
    if (v.era_mode >= 0) fixed += "    era_mode = " + std::string(kEraConst[v.era_mode]) + ";\n";
    if (v.prism_reflection >= 0)
        fixed += "    prism_reflection = " + std::string(kPrismConst[v.prism_reflection]) + ";\n";
    if (v.fidelity >= 0)
        fixed += "    fidelity = " + std::string(kFidelityConst[v.fidelity]) + ";\n";
    if (!v.canted) fixed += "    cant_angle = 0.0;\n";
    if (!v.dihedral) fixed += "    dihedral_error = 0.0;\n    dihedral_spread = 0.0;\n";
    if (!v.diffraction) fixed += "    prism_pitch = 0.0;\n";
    // The inputs in table order, as GLSL parameters and as arguments.
    std::string inputs = entry_signature();
    inputs = inputs.substr(0, inputs.find("vec3 wi,"));
    std::string names;
#define RP_FLOAT(name, def, lo, hi, doc) names += #name ", ";
#define RP_COLOR(name, r, g, b, doc) names += #name ", ";
#define RP_ENUM(name, def, values, doc) names += #name ", ";
#define RP_VECTOR(name, x, y, z, geomprop, doc) names += #name ", ";
#define RP_BOOL(name, def, doc) names += #name ", ";
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
    return "// The node's inputs, sanitised as in every backend (clamped into their ranges, NaN\n"
           "// replaced by the default), as the core's material and shading frame.\n"
           "rp_material rp_prismatic_retroreflector_material(" +
           inputs + "out vec3 fN, out vec3 fT, out vec3 fB) {\n" + sanitize + fixed +
           "    rp_make_frame(normal, tangent, fN, fT, fB);\n"
           "    return rp_prepare(weight, diffuse_color, retro_color, specular, roughness, ior,\n"
           "                      prism_reflection, metal_reflectance, era_mode, orientation,\n"
           "                      cant_angle, dihedral_error, dihedral_spread, prism_pitch,\n"
           "                      abbe_number, wavelength, retro_lobe,\n"
           "                      reciprocal ? 1 : 0,\n"
           "                      fidelity);\n"
           "}\n\n"
           "// The node, evaluated: f (1/sr, without the cosine) per lobe for wi (toward the "
           "light)\n"
           "// and wo (toward the viewer), both given in the space of `normal` and `tangent`, and\n"
           "// the pdf of the node's sampling.\n"
           "void rp_prismatic_retroreflector_eval(" +
           entry_signature() +
           ") {\n"
           "    surface = vec3(0.0);\n"
           "    retro = vec3(0.0);\n"
           "    diffuse = vec3(0.0);\n"
           "    pdf = 0.0;\n"
           "    vec3 fN;\n"
           "    vec3 fT;\n"
           "    vec3 fB;\n"
           "    rp_material m = rp_prismatic_retroreflector_material(" +
           names +
           "fN, fT, fB);\n"
           "    vec3 wiLocal;\n"
           "    vec3 woLocal;\n"
           "    if (!rp_to_local(fN, fT, fB, wi, wiLocal) || !rp_to_local(fN, fT, fB, wo, "
           "woLocal)) {\n"
           "        return;\n"
           "    }\n"
           "    rp_lobes lobes;\n"
           "    rp_eval(m, wiLocal, woLocal, lobes, pdf);\n"
           "    surface = lobes.surface;\n"
           "    retro = lobes.retro;\n"
           "    diffuse = lobes.diffuse;\n"
           "}\n\n"
           "// Each lobe's albedo estimate (rp_estimates_at, without `weight`) for light arriving\n"
           "// from w, and the retro lobe's width alpha_o there.\n"
           "void rp_prismatic_retroreflector_estimates(" +
           inputs +
           "vec3 w, out vec3 surface, out vec3 retro, out vec3 diffuse, out float alphaO) {\n"
           "    surface = vec3(0.0);\n"
           "    retro = vec3(0.0);\n"
           "    diffuse = vec3(0.0);\n"
           "    alphaO = 1.0;\n"
           "    vec3 fN;\n"
           "    vec3 fT;\n"
           "    vec3 fB;\n"
           "    rp_material m = rp_prismatic_retroreflector_material(" +
           names +
           "fN, fT, fB);\n"
           "    vec3 wLocal;\n"
           "    if (!rp_to_local(fN, fT, fB, w, wLocal) || !(wLocal.z >= RP_MIN_COS)) return;\n"
           "    rp_estimates_at(m, wLocal, surface, retro, diffuse, alphaO);\n"
           "}\n";
}

} // namespace

std::string Variant::describe() const {
    std::string lobes;
    if (surface) lobes += "surface ";
    if (retro) lobes += "retro ";
    if (diffuse) lobes += "diffuse ";
    return "lobes: " + lobes + "| era_mode: " + (era_mode < 0 ? "runtime" : kEraNames[era_mode]) +
           " | prism_reflection: " +
           (prism_reflection < 0 ? "runtime" : kPrismNames[prism_reflection]) +
           " | fidelity: " + (fidelity < 0 ? "runtime" : kFidelityNames[fidelity]) +
           " | cant_angle: " + (canted ? "runtime" : "0") +
           " | dihedral_error: " + (dihedral ? "runtime" : "0") +
           " | prism_pitch: " + (diffraction ? "runtime" : "0");
}

std::vector<Variant> standard_variants() {
    std::vector<Variant> out;
    out.push_back(Variant{"prismatic_retroreflector"});
    // Lobe subsets, modes at run time.
    for (int mask = 1; mask < 7; ++mask) {
        Variant v;
        v.surface = mask & 1;
        v.retro = mask & 2;
        v.diffuse = mask & 4;
        v.name = "prismatic_retroreflector";
        if (v.surface) v.name += "_surface";
        if (v.retro) v.name += "_retro";
        if (v.diffuse) v.name += "_diffuse";
        v.cpp = mask == 2 || mask == 6; // retro alone, retro and diffuse
        out.push_back(v);
    }
    // The fast tier, everything else at run time.
    {
        Variant v;
        v.fidelity = 1;
        v.name = "prismatic_retroreflector_fast";
        out.push_back(v);
    }
    // Fixed modes in the fast tier, the paper's cube: the cheapest three-lobe nodes.
    for (int prism : {0, 1}) {
        Variant v;
        v.era_mode = 0;
        v.prism_reflection = prism;
        v.fidelity = 1;
        v.canted = false;
        v.dihedral = false;
        v.diffraction = false;
        v.cpp = true;
        v.name = std::string("prismatic_retroreflector_averaged_") + kPrismNames[prism] + "_fast";
        out.push_back(v);
    }
    // Every ERA mode with every prism reflection, all lobes, the paper's cube.
    for (int era = 0; era < 3; ++era)
        for (int prism = 0; prism < 3; ++prism) {
            Variant v;
            v.era_mode = era;
            v.prism_reflection = prism;
            v.canted = false;
            v.dihedral = false;
            v.diffraction = false;
            v.name = std::string("prismatic_retroreflector_") + kEraNames[era] + "_" +
                     kPrismNames[prism];
            v.cpp = era == 0 && prism < 2;
            out.push_back(v);
        }
    return out;
}

// SPIR-V instructions of a shader after spirv-opt -O, counted from spirv-dis's listing; -1
// when the tools fail.
long spirv_instructions_of(const std::string& source, const std::string& stage,
                           const std::string& name, long* constants) {
    namespace fs = std::filesystem;
    const fs::path dir =
        fs::temp_directory_path() / ("retroprism_spirv_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path src = dir / (name + "." + stage), spv = dir / (name + ".spv"),
                   opt = dir / (name + "_opt.spv");
    std::ofstream(src) << source;
    const std::string cmd = "glslangValidator -V -o " + spv.string() + " " + src.string() +
                            " >/dev/null 2>&1 && spirv-opt -O " + spv.string() + " -o " +
                            opt.string() + " && spirv-dis --raw-id " + opt.string();
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return -1;
    long count = 0, constantCount = 0;
    char line[4096];
    while (std::fgets(line, sizeof line, p)) {
        std::string l = line;
        size_t op = l.find("Op");
        if (op == std::string::npos || l.find(';') == 0) continue;
        ++count;
        if (l.compare(op, 10, "OpConstant") == 0 || l.compare(op, 14, "OpSpecConstant") == 0)
            ++constantCount;
    }
    int st = pclose(p);
    fs::remove_all(dir);
    const bool ok = WIFEXITED(st) && WEXITSTATUS(st) == 0;
    if (constants) *constants = ok ? constantCount : -1;
    return ok ? count : -1;
}

// SPIR-V instructions of a variant's fragment wrapper.
long spirv_instructions(const std::string& library, const std::string& name, long* constants) {
    return spirv_instructions_of(wrap_fragment(library, Target::Vulkan), "frag", name, constants);
}

std::string generate_cpp_core(const Variant& v, const std::string& sourceDir) {
    const std::string rel = "nodes/prism_core.inc";
    std::set<std::string> feats = features(v);
    feats.insert("cpp");
    return "// Generated by retroprism_glsl_gen from nodes/prism_core.inc: do not edit. Variant:\n"
           "// " +
           v.describe() + ".\n" +
           fix_modes(select_regions(read_file(sourceDir + "/" + rel), rel, feats), v);
}

std::set<std::string> features(const Variant& v) {
    std::set<std::string> f = {"node"};
    if (v.surface) f.insert("surface");
    if (v.retro) f.insert("retro");
    if (v.diffuse) f.insert("diffuse");
    for (int i = 0; i < 3; ++i) {
        if (v.era_mode < 0 || v.era_mode == i) f.insert(std::string("era_") + kEraNames[i]);
        if (v.prism_reflection < 0 || v.prism_reflection == i)
            f.insert(std::string("prism_") + kPrismNames[i]);
        if (i < 2 && (v.fidelity < 0 || v.fidelity == i))
            f.insert(std::string("fidelity_") + kFidelityNames[i]);
    }
    if (v.canted) f.insert("canted");
    if (v.dihedral) f.insert("dihedral");
    if (v.diffraction) f.insert("diffraction");
    return f;
}

std::string entry_signature() {
    std::string sig;
#define RP_FLOAT(name, def, lo, hi, doc) sig += "float " #name ", ";
#define RP_COLOR(name, r, g, b, doc) sig += "vec3 " #name ", ";
#define RP_ENUM(name, def, values, doc) sig += "int " #name ", ";
#define RP_VECTOR(name, x, y, z, geomprop, doc) sig += "vec3 " #name ", ";
#define RP_BOOL(name, def, doc) sig += "bool " #name ", ";
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
    return sig +
           "vec3 wi, vec3 wo, out vec3 surface, out vec3 retro, out vec3 diffuse, out float pdf";
}

std::string generate_library(const Variant& v, const std::string& sourceDir) {
    const std::set<std::string> feats = features(v);
    auto part = [&](const std::string& rel) {
        return to_glsl(select_regions(read_file(sourceDir + "/" + rel), rel, feats), v);
    };
    std::string out;
    out +=
        "// " + v.name +
        ".glsl: the prismatic retroreflector node (Guo, Guo & Pan 2018) as GLSL.\n"
        "// Generated by retroprism_glsl_gen from nodes/prism_core.inc, nodes/prism_special.inc,\n"
        "// nodes/generated/prism_tables.inc, glsl_gen/prelude.glsl and the parameter table;\n"
        "// do not edit. Variant: " +
        v.describe() +
        ".\n"
        "// Valid as GLSL 4.x, ESSL 3.00 and Vulkan GLSL (the includer supplies #version and,\n"
        "// for ESSL, default precision). Entry point: rp_prismatic_retroreflector_eval.\n\n";
    out += part("glsl_gen/prelude.glsl") + "\n";
    out += part("nodes/prism_special.inc") + "\n";
    out += "float rp_erfinv(float x) {\n    return rp_erfinv_giles(x);\n}\n\n";
    if (v.diffuse) out += "float rp_fdr_external(float eta);\n\n";
    out += part("nodes/generated/prism_tables.inc") + "\n";
    out += part("nodes/prism_core.inc") + "\n";
    if (v.diffuse)
        out += "float rp_fdr_external(float eta) {\n    return rp_fdr_external_series(eta);\n}\n\n";
    out += entry_point(v);
    return pack_tables(out);
}

std::string generate_baseline_library(const std::string& sourceDir) {
    // No feature: of the node's core only what lies outside its "node" regions (the guards and
    // constants, the dielectric Fresnel factor, the shading frame).
    const std::set<std::string> none;
    const Variant plain;
    auto part = [&](const std::string& rel) {
        return to_glsl(select_regions(read_file(sourceDir + "/" + rel), rel, none), plain);
    };
    return "// mrm_ggx.glsl: the MaterialX-style retroreflective GGX baseline over a\n"
           "// Lambertian base (Portsmouth et al., JCGT 2026: MaterialX's dielectric_bsdf\n"
           "// with retroreflective = true), as GLSL. Generated by retroprism_glsl_gen from\n"
           "// nodes/mrm_core.inc and the parts of nodes/prism_core.inc outside its node\n"
           "// regions; do not edit. Valid as GLSL 4.x, ESSL 3.00 and Vulkan GLSL (the\n"
           "// includer supplies #version and, for ESSL, default precision). Entry points:\n"
           "// rp_mrm_lobes (local frame), rp_mrm_lobes_in_frame.\n\n" +
           part("nodes/prism_core.inc") + "\n" + part("nodes/mrm_core.inc");
}

std::string wrap_baseline_fragment(const std::string& library, Target target) {
    const std::string head = target == Target::Essl300
                                 ? "#version 300 es\nprecision highp float;\nprecision highp int;\n"
                                 : "#version 450\n";
    const std::string layout = target == Target::Vulkan
                                   ? "layout(set = 0, binding = 0, std140) uniform"
                                   : "layout(std140) uniform";
    return head + library + "\n" + layout +
           " MrmInputs {\n    vec4 roughness_ior_specular;\n    vec4 tint;\n    vec4 color;\n"
           "    vec4 normal;\n    vec4 tangent;\n    vec4 wi;\n    vec4 wo;\n} u;\n"
           "layout(location = 0) out vec4 fragColor;\n"
           "void main() {\n"
           "    vec3 specularLobe;\n    vec3 diffuseLobe;\n"
           "    rp_mrm_lobes_in_frame(u.roughness_ior_specular.x, u.roughness_ior_specular.y,\n"
           "                          u.roughness_ior_specular.z, u.tint.xyz, u.color.xyz,\n"
           "                          u.normal.xyz, u.tangent.xyz, u.wi.xyz, u.wo.xyz,\n"
           "                          specularLobe, diffuseLobe);\n"
           "    fragColor = vec4(specularLobe + diffuseLobe, 1.0);\n"
           "}\n";
}

std::string wrap_fragment(const std::string& library, Target target) {
    // The node's inputs as a uniform block (Vulkan GLSL has no loose uniforms).
    std::string block, args;
#define RP_FLOAT(name, def, lo, hi, doc)                                                           \
    block += "    float " #name ";\n";                                                             \
    args += "u." #name ", ";
#define RP_COLOR(name, r, g, b, doc)                                                               \
    block += "    vec4 " #name ";\n";                                                              \
    args += "u." #name ".xyz, ";
#define RP_ENUM(name, def, values, doc)                                                            \
    block += "    int " #name ";\n";                                                               \
    args += "u." #name ", ";
#define RP_VECTOR(name, x, y, z, geomprop, doc)                                                    \
    block += "    vec4 " #name ";\n";                                                              \
    args += "u." #name ".xyz, ";
#define RP_BOOL(name, def, doc)                                                                    \
    block += "    bool " #name ";\n";                                                              \
    args += "u." #name ", ";
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
    std::string head;
    std::string layout = "layout(std140) uniform";
    switch (target) {
    case Target::Glsl450:
        head = "#version 450\n";
        break;
    case Target::Essl300:
        head = "#version 300 es\nprecision highp float;\nprecision highp int;\n";
        break;
    case Target::Vulkan:
        head = "#version 450\n";
        layout = "layout(set = 0, binding = 0, std140) uniform";
        break;
    }
    return head + library + "\n" + layout + " RpInputs {\n" + block +
           "    vec4 wi;\n    vec4 wo;\n} u;\n"
           "layout(location = 0) out vec4 fragColor;\n"
           "void main() {\n"
           "    vec3 surface;\n    vec3 retro;\n    vec3 diffuse;\n    float pdf;\n"
           "    rp_prismatic_retroreflector_eval(" +
           args +
           "u.wi.xyz, u.wo.xyz, surface, retro, diffuse, pdf);\n"
           "    fragColor = vec4(surface + retro + diffuse, pdf);\n"
           "}\n";
}

namespace {

std::string xml_escape(const std::string& in) {
    std::string out;
    for (char c : in) {
        if (c == '&')
            out += "&amp;";
        else if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '"')
            out += "&quot;";
        else
            out += c;
    }
    return out;
}

std::string mtlx_num(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return buf;
}

const char* kNodeDoc =
    "Retroreflective prismatic sheeting (traffic signs, safety garments, licence plates): a rough "
    "dielectric top surface, cube-corner prisms and a diffuse substrate (Guo, Guo and Pan, "
    "Graphical Models 2018). Reflection only.";

// The first lines of each generated MaterialX document.
std::string materialx_header() {
    return "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n"
           "  <!-- Generated by retroprism_glsl_gen from the parameter table "
           "(nodes/prismatic_retroreflector_params.def); do not edit. -->\n";
}

// The node's inputs as MaterialX and as the genglsl function sees them, from the parameter table.
struct MaterialxInputs {
    std::string nodedef; // the <input> elements of the nodedef
    std::string params;  // GLSL parameter list of the MaterialX function, in nodedef order
    std::string args;    // the same names, passed on to the entry point
    // "rp_sanitize(name, lo, hi, default)" of each float input, for the environment lookups.
    std::map<std::string, std::string> sanitized;
};

MaterialxInputs materialx_inputs() {
    MaterialxInputs in;
#define RP_FLOAT(name, def, lo, hi, doc)                                                           \
    in.sanitized[#name] =                                                                          \
        "rp_sanitize(" #name ", " + lit(lo) + ", " + lit(hi) + ", " + lit(def) + ")";              \
    in.nodedef += "    <input name=\"" #name "\" type=\"float\" value=\"" + mtlx_num(def) +        \
                  "\" uimin=\"" + mtlx_num(lo) + "\" uimax=\"" + mtlx_num(hi) +                    \
                  "\"\n           doc=\"" + xml_escape(doc) + "\"/>\n";                            \
    in.params += ", float " #name;                                                                 \
    in.args += #name ", ";
#define RP_COLOR(name, r, g, b, doc)                                                               \
    in.nodedef += "    <input name=\"" #name "\" type=\"color3\" value=\"" + mtlx_num(r) + ", " +  \
                  mtlx_num(g) + ", " + mtlx_num(b) +                                               \
                  "\" uimin=\"0, 0, 0\" uimax=\"1, 1, 1\"\n           doc=\"" + xml_escape(doc) +  \
                  "\"/>\n";                                                                        \
    in.params += ", vec3 " #name;                                                                  \
    in.args += #name ", ";
#define RP_ENUM(name, def, values, doc)                                                            \
    {                                                                                              \
        std::string indices;                                                                       \
        std::stringstream ss(values);                                                              \
        std::string item;                                                                          \
        for (int k = 0; std::getline(ss, item, ','); ++k)                                          \
            indices += (k ? "," : "") + std::to_string(k);                                         \
        in.nodedef += "    <input name=\"" #name "\" type=\"integer\" value=\"" +                  \
                      std::to_string(def) + "\" enum=\"" values "\" enumvalues=\"" + indices +     \
                      "\" uniform=\"true\"\n           doc=\"" + xml_escape(doc) + "\"/>\n";       \
    }                                                                                              \
    in.params += ", int " #name;                                                                   \
    in.args += #name ", ";
#define RP_VECTOR(name, x, y, z, geomprop, doc)                                                    \
    in.nodedef += "    <input name=\"" #name "\" type=\"vector3\" defaultgeomprop=\"" geomprop     \
                  "\"\n           doc=\"" +                                                        \
                  xml_escape(doc) + "\"/>\n";                                                      \
    in.params += ", vec3 " #name;                                                                  \
    in.args += #name ", ";
#define RP_BOOL(name, def, doc)                                                                    \
    in.nodedef += "    <input name=\"" #name "\" type=\"boolean\" value=\"" +                      \
                  std::string(def ? "true" : "false") + "\" uniform=\"true\"\n           doc=\"" + \
                  xml_escape(doc) + "\"/>\n";                                                      \
    in.params += ", bool " #name;                                                                  \
    in.args += #name ", ";
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
    return in;
}

// rp_pbrlib_defs.mtlx: the nodedef.
std::string materialx_defs(const MaterialxInputs& in) {
    return materialx_header() +
           "  <nodedef name=\"ND_rp_prismatic_retroreflector_bsdf\" "
           "node=\"rp_prismatic_retroreflector_bsdf\" bsdf=\"R\" nodegroup=\"pbr\"\n"
           "           doc=\"" +
           xml_escape(kNodeDoc) + "\">\n" + in.nodedef +
           "    <output name=\"out\" type=\"BSDF\"/>\n  </nodedef>\n</materialx>\n";
}

// rp_pbrlib_genglsl_impl.mtlx: the genglsl implementation's element.
std::string materialx_impl() {
    return materialx_header() +
           "  <implementation name=\"IM_rp_prismatic_retroreflector_bsdf_genglsl\"\n"
           "                  nodedef=\"ND_rp_prismatic_retroreflector_bsdf\"\n"
           "                  file=\"rp_prismatic_retroreflector_bsdf.glsl\"\n"
           "                  function=\"mx_rp_prismatic_retroreflector_bsdf\" "
           "target=\"genglsl\"/>\n"
           "</materialx>\n";
}

// The genglsl closure function mx_rp_prismatic_retroreflector_bsdf, on the full variant's entry
// points.
std::string materialx_closure(const MaterialxInputs& in) {
    return "\n// ---- MaterialX genglsl closure (1.39.3 and later signature) "
           "--------------------------\n"
           "//\n"
           "// REFLECTION: per light, response = f(L, V) (N.L) occlusion, f including `weight`.\n"
           "// INDIRECT: environment light approximated per lobe from the lobe albedo "
           "estimates of\n"
           "// rp_estimates_at (their error against the exact albedo is measured by\n"
           "// tests/nodes/test_physics.cpp): the surface lobe by MaterialX's pre-integrated GGX\n"
           "// environment radiance at roughness alpha (Beckmann and GGX lobes of equal alpha\n"
           "// are alike near their peak), the retro lobe by the environment radiance around V,\n"
           "// the direction the light came from (a GGX lobe about N = V of alpha_o / 2: a\n"
           "// reflected direction spreads twice as wide as the normals), and the diffuse lobe\n"
           "// by the irradiance. Opaque: throughput 0. The normal faces the viewer, as in\n"
           "// MaterialX's other BSDFs.\n"
           "void mx_rp_prismatic_retroreflector_bsdf(ClosureData closureData" +
           in.params +
           ", inout BSDF bsdf)\n"
           "{\n"
           "    bsdf.throughput = vec3(0.0);\n"
           "    vec3 V = closureData.V;\n"
           "    vec3 N = mx_forward_facing_normal(normal, V);\n"
           "    vec3 fN;\n"
           "    vec3 fT;\n"
           "    vec3 fB;\n"
           "    rp_make_frame(N, tangent, fN, fT, fB);\n"
           "    if (closureData.closureType == CLOSURE_TYPE_REFLECTION)\n"
           "    {\n"
           "        vec3 L = closureData.L;\n"
           "        vec3 surface;\n"
           "        vec3 retro;\n"
           "        vec3 diffuse;\n"
           "        float pdf;\n"
           "        rp_prismatic_retroreflector_eval(" +
           in.args.substr(0, in.args.find("normal, ")) +
           "N, tangent, L, V, surface, retro, diffuse, pdf);\n"
           "        float NdotL = max(dot(fN, L), 0.0);\n"
           "        bsdf.response = (surface + retro + diffuse) * NdotL * closureData.occlusion;\n"
           "    }\n"
           "    else if (closureData.closureType == CLOSURE_TYPE_INDIRECT)\n"
           "    {\n"
           "        vec3 albedoSurface;\n"
           "        vec3 albedoRetro;\n"
           "        vec3 albedoDiffuse;\n"
           "        float alphaO;\n"
           "        rp_prismatic_retroreflector_estimates(" +
           in.args.substr(0, in.args.find("normal, ")) +
           "N, tangent, V, albedoSurface, albedoRetro, albedoDiffuse, alphaO);\n"
           "        // MaterialX's environment integrals divide by N.V: a view at or below the\n"
           "        // horizon of the node's frame (where the estimates are zero) gets no\n"
           "        // environment light, and the integrals see the node's frame (a tangent along\n"
           "        // the normal is replaced as in the node).\n"
           "        vec3 vLocal;\n"
           "        if (!rp_to_local(fN, fT, fB, V, vLocal) || !(vLocal.z >= RP_MIN_COS)) {\n"
           "            bsdf.response = vec3(0.0);\n"
           "            return;\n"
           "        }\n"
           "        float ks = " +
           in.sanitized.at("specular") +
           ";\n"
           "        float w = " +
           in.sanitized.at("weight") +
           ";\n"
           "        float alphaS = max(" +
           in.sanitized.at("roughness") +
           ", M_FLOAT_EPS);\n"
           "        float eta = " +
           in.sanitized.at("ior") +
           ";\n"
           "        // mx_environment_radiance applies the dielectric's Fresnel itself.\n"
           "        vec3 Ls = ks > 0.0 ? mx_environment_radiance(fN, V, fT, vec2(alphaS), 0,\n"
           "                                   mx_init_fresnel_dielectric(eta, 0.0, 1.0)) * ks : "
           "vec3(0.0);\n"
           "        vec3 X = abs(V.z) < 0.999 ? normalize(cross(V, vec3(0.0, 0.0, 1.0))) : "
           "vec3(1.0, 0.0, 0.0);\n"
           "        float alphaR = clamp(0.5 * alphaO, M_FLOAT_EPS, 1.0);\n"
           "        vec3 Lr = mx_environment_radiance(V, V, X, vec2(alphaR), 0,\n"
           "                      mx_init_fresnel_schlick(vec3(1.0), vec3(1.0), vec3(1.0), 5.0, "
           "0.0, 1.0));\n"
           "        vec3 Ld = mx_environment_irradiance(fN);\n"
           "        bsdf.response = w * (Ls + Lr * albedoRetro + Ld * albedoDiffuse) * "
           "closureData.occlusion;\n"
           "    }\n"
           "}\n";
}

} // namespace

std::vector<std::pair<std::string, std::string>> generate_materialx(const std::string& sourceDir) {
    const MaterialxInputs in = materialx_inputs();
    const Variant full = standard_variants().front();
    // MaterialX's closure types and its microfacet helpers (Fresnel data, forward-facing
    // normal), included from its standard libraries' folder on the search path.
    const std::string glsl =
        "#include \"libraries/pbrlib/genglsl/lib/mx_closure_type.glsl\"\n"
        "#include \"libraries/pbrlib/genglsl/lib/mx_microfacet_specular.glsl\"\n\n" +
        generate_library(full, sourceDir);
    return {{"materialx/rp_pbrlib/rp_pbrlib_defs.mtlx", materialx_defs(in)},
            {"materialx/rp_pbrlib/genglsl/rp_pbrlib_genglsl_impl.mtlx", materialx_impl()},
            {"materialx/rp_pbrlib/genglsl/rp_prismatic_retroreflector_bsdf.glsl",
             glsl + materialx_closure(in)},
            {"materialx/rp_pbrlib/rp_pbrlib_ng.mtlx", generate_portable_nodegraph()}};
}

} // namespace retroprism::glsl
