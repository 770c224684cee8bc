#include "mx_material.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include <unistd.h>

#include <OpenImageIO/imagebuf.h>
#include <nlohmann/json.hpp>

#include "color.h"
#include "error.h"
#include "mtlx_reader.h"
#include "parse.h"
#include "text_file.h"

namespace retroprism::gl {

namespace fs = std::filesystem;

const MxUniform* MxMaterial::find(const std::string& path) const {
    for (const MxUniform& u : uniforms)
        if (u.path == path) return &u;
    return nullptr;
}

namespace {

// The lines of mx.cjs's output that report an error (each starts with the document's name).
std::string error_lines(const std::string& output) {
    std::istringstream in(output);
    std::string line, out;
    while (std::getline(in, line))
        if (line.find(": error: ") != std::string::npos ||
            line.find("no surfacematerial") != std::string::npos)
            out += (out.empty() ? "" : "\n") + line;
    return out;
}

MxMaterial read_manifest(const fs::path& dir, const std::string& material) {
    MxMaterial m;
    m.material = material;
    m.shaders = read_mx_shaders(dir.string(), material);
    const nlohmann::json j =
        nlohmann::json::parse(read_text_file((dir / (material + ".glsl.json")).string()));
    for (const auto& u : j.at("uniforms")) {
        MxUniform x;
        x.variable = u.at("variable").get<std::string>();
        x.type = u.at("type").get<std::string>();
        x.path = u.at("path").get<std::string>();
        x.value = u.at("value").get<std::string>();
        x.colorspace = u.value("colorspace", "");
        x.node = u.value("node", "");
        x.category = u.value("category", "");
        x.nodeType = u.value("nodetype", "");
        m.uniforms.push_back(std::move(x));
    }
    m.categories = j.at("categories").get<std::vector<std::string>>();
    return m;
}

} // namespace

MxMaterial generate_mx_material(const std::string& dataDir, const std::string& document,
                                const std::string& material) {
    const MtlxOutline outline = outline_mtlx(document);
    if (outline.materials.empty())
        throw InputError(document + ": no <surfacematerial> in the document");
    std::string name = material.empty() ? outline.materials.front() : material;
    if (std::find(outline.materials.begin(), outline.materials.end(), name) ==
        outline.materials.end()) {
        std::string list;
        for (const std::string& n : outline.materials)
            list += (list.empty() ? "" : ", ") + n;
        throw InputError(document + ": no material named \"" + name + "\" (materials: " + list +
                         ")");
    }
    const fs::path dir =
        fs::temp_directory_path() / ("retroprism_mxdoc_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    struct Cleanup {
        fs::path d;
        ~Cleanup() {
            std::error_code ec;
            fs::remove_all(d, ec);
        }
    } cleanup{dir};
    try {
        generate_mx_shaders(dataDir, {document}, dir.string(), {"glsl", false});
    } catch (const GlError& e) {
        const std::string errors = error_lines(e.what());
        if (errors.empty()) throw;
        throw InputError("MaterialX 1.39.4 rejects the document:\n" + errors);
    }
    MxMaterial m = read_manifest(dir, name);
    m.document = document;
    return m;
}

std::vector<double> mx_values(const MxUniform& u) {
    std::vector<double> v;
    std::istringstream in(u.value);
    std::string item;
    while (std::getline(in, item, ','))
        v.push_back(parse_number(trim(item), u.path));
    return v;
}

namespace {

// The texels of `file` as RGBA float, row 0 at the bottom.
MxTexture read_texture(const MxMaterial& m, const MxUniform& u, const fs::path& file) {
    const std::string where =
        m.document + ": <" + u.category + " name=\"" + u.node + "\"> input file: " + u.value;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec))
        throw InputError(where + ": no such file (" + file.string() + ")");
    OIIO::ImageBuf in(file.string());
    if (!in.read(0, 0, true, OIIO::TypeDesc::FLOAT))
        throw InputError(where + ": cannot read " + file.string() + " (" + in.geterror() + ")");
    const OIIO::ImageSpec& spec = in.spec();
    MxTexture t;
    t.variable = u.variable;
    t.node = u.node;
    t.file = file.string();
    t.width = spec.width;
    t.height = spec.height;
    const int nc = spec.nchannels;
    std::vector<float> px(size_t(t.width) * size_t(t.height) * size_t(nc));
    in.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());
    t.rgba.assign(size_t(t.width) * size_t(t.height) * 4, 1.0f);
    const bool convert = (u.nodeType == "color3" || u.nodeType == "color4") &&
                         !u.colorspace.empty() && u.colorspace != kMtlxWorkingSpace;
    for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x) {
            const float* s = &px[(size_t(y) * size_t(t.width) + size_t(x)) * size_t(nc)];
            float* d = &t.rgba[(size_t(t.height - 1 - y) * size_t(t.width) + size_t(x)) * 4];
            for (int c = 0; c < 3; ++c)
                d[c] = nc >= 3 ? s[c] : s[0];
            if (nc == 2 || nc >= 4) d[3] = s[nc == 2 ? 1 : 3];
            if (convert) {
                const Color3 lin = to_lin_rec709(u.colorspace, {d[0], d[1], d[2]});
                for (int c = 0; c < 3; ++c)
                    d[c] = float(lin[size_t(c)]);
            }
        }
    return t;
}

} // namespace

std::vector<MxTexture> load_mx_textures(const MxMaterial& m) {
    std::vector<MxTexture> out;
    const fs::path base = fs::path(m.document).parent_path();
    for (const MxUniform& u : m.uniforms) {
        if (u.type != "filename") continue;
        if (u.value.empty())
            throw InputError(m.document + ": <" + u.category + " name=\"" + u.node +
                             "\"> input file: no file given");
        const fs::path f(u.value);
        out.push_back(read_texture(m, u, f.is_absolute() ? f : base / f));
    }
    return out;
}

} // namespace retroprism::gl
