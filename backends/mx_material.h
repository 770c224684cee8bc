// mx_material.h: a material of any MaterialX document (layers, mixes, textures, node graphs
// around the node or without it) as real MaterialX 1.39.4 generates it: the GLSL pair, the
// pixel stage's public uniforms with the document's values, and the textures its image nodes
// read, loaded with OpenImageIO.
#pragma once

#include <string>
#include <vector>

#include "mx_runner.h"

namespace retroprism::gl {

// One public uniform of the generated pixel stage (mx.cjs writes them as MATERIAL.glsl.json).
struct MxUniform {
    std::string variable;   // the GLSL uniform, "<node>_<input>"
    std::string type;       // MaterialX's type: float, color3, vector2, integer, filename, ...
    std::string path;       // the element path, "node/input"
    std::string value;      // MaterialX's value string (a filename with fileprefix applied)
    std::string colorspace; // of its input or node ("" = the working space, lin_rec709)
    std::string node, category, nodeType; // the node it belongs to; "" when none
};

struct MxMaterial {
    std::string document; // the file, as given
    std::string material;
    MxShaders shaders;
    std::vector<MxUniform> uniforms;
    std::vector<std::string> categories; // of the nodes the material reaches, sorted

    // The uniform of `path` ("node/input"), or nullptr.
    const MxUniform* find(const std::string& path) const;
};

// Generates with MaterialX (mx.cjs; `dataDir` as util/paths.h finds it) the GLSL of `material`
// of `document` (the first when empty). What MaterialX rejects (an unknown node, inputs that
// match no nodedef, a failed validation, a cycle) is an InputError with MaterialX's messages,
// each naming the document and the element; a missing Node.js or MaterialX tool is a GlError.
MxMaterial generate_mx_material(const std::string& dataDir, const std::string& document,
                                const std::string& material);

// A texture an image node reads, as OpenGL takes it: RGBA float, row 0 at the bottom (MaterialX's
// texture coordinates: v up), 1 channel as grey (v, v, v, 1), 2 as grey and alpha, 3 with alpha
// 1; texels of a colour image node (color3, color4) whose file has a colour space other than
// lin_rec709 converted to it with OpenColorIO (io/color.h), as MaterialX's colour management
// would; other types are used as stored.
struct MxTexture {
    std::string variable; // the sampler uniform
    std::string node;     // the image node
    std::string file;     // the resolved path
    int width = 0, height = 0;
    std::vector<float> rgba;
};

// Loads every texture of `m`: a filename input's value relative to the document's folder
// unless absolute. An image node without a file, or a file that cannot be read, is an
// InputError naming the document, the node, its input and the file.
std::vector<MxTexture> load_mx_textures(const MxMaterial& m);

// MaterialX's value string of a float, vector or colour as numbers; InputError when malformed.
std::vector<double> mx_values(const MxUniform& u);

} // namespace retroprism::gl
