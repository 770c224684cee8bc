#include "color.h"

#include <stdexcept>

#include "ocio_transforms.h"
#include "query.h"

namespace retroprism {

using namespace ocio;

namespace {

OCIO::GroupTransformRcPtr input_transform(const std::string& cs) {
    OCIO::GroupTransformRcPtr g = OCIO::GroupTransform::Create();
    const char* ap1 = "UTILITY - ACES-AP1_to_LINEAR-REC709_BFD";
    if (cs == "lin_rec709") {
    } else if (cs == "srgb_texture") {
        g->appendTransform(srgb_curve(OCIO::TRANSFORM_DIR_FORWARD));
    } else if (cs == "g22_rec709") {
        g->appendTransform(power(2.2));
    } else if (cs == "g18_rec709") {
        g->appendTransform(power(1.8));
    } else if (cs == "acescg" || cs == "lin_ap1") {
        g->appendTransform(builtin(ap1));
    } else if (cs == "g22_ap1") {
        g->appendTransform(power(2.2));
        g->appendTransform(builtin(ap1));
    } else if (cs == "g18_ap1") {
        g->appendTransform(power(1.8));
        g->appendTransform(builtin(ap1));
    } else if (cs == "lin_displayp3") {
        g->appendTransform(to_rec709(kP3));
    } else if (cs == "srgb_displayp3") {
        g->appendTransform(srgb_curve(OCIO::TRANSFORM_DIR_FORWARD));
        g->appendTransform(to_rec709(kP3));
    } else if (cs == "lin_adobergb") {
        g->appendTransform(to_rec709(kAdobe));
    } else if (cs == "adobergb") {
        g->appendTransform(power(563.0 / 256.0));
        g->appendTransform(to_rec709(kAdobe));
    } else {
        throw InputError("colour space \"" + cs + "\" is not supported");
    }
    return g;
}

} // namespace

Color3 to_lin_rec709(const std::string& colorspace, const Color3& c) {
    if (colorspace == "lin_rec709") return c;
    float px[3] = {float(c[0]), float(c[1]), float(c[2])};
    cpu(input_transform(colorspace))->applyRGB(px);
    return {double(px[0]), double(px[1]), double(px[2])};
}

ColorConverter ocio_color_converter() {
    return [](const std::string& cs, const Color3& c) { return to_lin_rec709(cs, c); };
}

Params document_params(const std::string& path, const std::string& name,
                       std::string* materialName) {
    const MtlxOutline outline = outline_mtlx(path);
    if (outline.graph())
        throw InputError(
            path + ": a MaterialX graph (" + outline.graph_description() +
            "): the node's inputs, R_A tables and fits are computed for the chain surfacematerial "
            "-> surface -> " +
            kMtlxNodeCategory +
            " with constant inputs alone; a graph's response depends on the surface point and "
            "on its other BSDFs, which only MaterialX's shader evaluates (retroprism render "
            "renders it)");
    const MtlxDocument doc = read_mtlx(path);
    const MtlxMaterial& m = select_material(doc, name);
    if (materialName) *materialName = m.name;
    return to_working_space(doc, m, ocio_color_converter());
}

} // namespace retroprism
