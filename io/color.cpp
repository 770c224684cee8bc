#include "color.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <OpenColorIO/OpenColorIO.h>

#include "query.h"

namespace OCIO = OCIO_NAMESPACE;

namespace retroprism {

namespace {

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 mul(const Mat3& a, const Mat3& b) {
    Mat3 c{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                c[size_t(i)][size_t(j)] += a[size_t(i)][size_t(k)] * b[size_t(k)][size_t(j)];
    return c;
}

Mat3 inverse(const Mat3& m) {
    const double a = m[0][0], b = m[0][1], c = m[0][2], d = m[1][0], e = m[1][1], f = m[1][2],
                 g = m[2][0], h = m[2][1], i = m[2][2];
    const double A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
    const double det = a * A + b * B + c * C;
    return {{{A / det, -(b * i - c * h) / det, (b * f - c * e) / det},
             {B / det, (a * i - c * g) / det, -(a * f - c * d) / det},
             {C / det, -(a * h - b * g) / det, (a * e - b * d) / det}}};
}

// RGB -> CIE XYZ for primaries and white given as CIE xy chromaticities (SMPTE RP 177).
Mat3 rgb_to_xyz(const double xy[3][2], const double white[2]) {
    Mat3 P;
    for (int k = 0; k < 3; ++k) {
        const double x = xy[k][0], y = xy[k][1];
        P[0][size_t(k)] = x / y;
        P[1][size_t(k)] = 1.0;
        P[2][size_t(k)] = (1.0 - x - y) / y;
    }
    const double W[3] = {white[0] / white[1], 1.0, (1.0 - white[0] - white[1]) / white[1]};
    const Mat3 Pi = inverse(P);
    double S[3];
    for (int k = 0; k < 3; ++k)
        S[k] = Pi[size_t(k)][0] * W[0] + Pi[size_t(k)][1] * W[1] + Pi[size_t(k)][2] * W[2];
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            P[size_t(i)][size_t(k)] *= S[k];
    return P;
}

const double kD65[2] = {0.3127, 0.3290};
const double kRec709[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
const double kP3[3][2] = {{0.680, 0.320}, {0.265, 0.690}, {0.150, 0.060}};
const double kAdobe[3][2] = {{0.64, 0.33}, {0.21, 0.71}, {0.15, 0.06}};

OCIO::MatrixTransformRcPtr matrix(const Mat3& m) {
    double M[16] = {m[0][0], m[0][1], m[0][2], 0, m[1][0], m[1][1], m[1][2], 0,
                    m[2][0], m[2][1], m[2][2], 0, 0,       0,       0,       1};
    OCIO::MatrixTransformRcPtr t = OCIO::MatrixTransform::Create();
    t->setMatrix(M);
    return t;
}

OCIO::TransformRcPtr srgb_curve(OCIO::TransformDirection dir) {
    OCIO::ExponentWithLinearTransformRcPtr t = OCIO::ExponentWithLinearTransform::Create();
    const double g[4] = {2.4, 2.4, 2.4, 1.0}, o[4] = {0.055, 0.055, 0.055, 0.0};
    t->setGamma(g);
    t->setOffset(o);
    t->setDirection(dir); // forward: encoded -> linear
    return t;
}

OCIO::TransformRcPtr power(double gamma) {
    OCIO::ExponentTransformRcPtr t = OCIO::ExponentTransform::Create();
    const double g[4] = {gamma, gamma, gamma, 1.0};
    t->setValue(g); // forward: encoded -> linear
    return t;
}

OCIO::TransformRcPtr builtin(const char* style,
                             OCIO::TransformDirection dir = OCIO::TRANSFORM_DIR_FORWARD) {
    OCIO::BuiltinTransformRcPtr t = OCIO::BuiltinTransform::Create();
    t->setStyle(style);
    t->setDirection(dir);
    return t;
}

// Linear `primaries` (D65) -> linear Rec.709.
OCIO::TransformRcPtr to_rec709(const double primaries[3][2]) {
    return matrix(mul(inverse(rgb_to_xyz(kRec709, kD65)), rgb_to_xyz(primaries, kD65)));
}

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

OCIO::ConstCPUProcessorRcPtr cpu(const OCIO::ConstTransformRcPtr& t) {
    try {
        static const OCIO::ConstConfigRcPtr config = OCIO::Config::CreateRaw();
        return config->getProcessor(t)->getDefaultCPUProcessor();
    } catch (const OCIO::Exception& e) {
        throw std::runtime_error(std::string("OpenColorIO: ") + e.what());
    }
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
    const MtlxDocument doc = read_mtlx(path);
    const MtlxMaterial& m = select_material(doc, name);
    if (materialName) *materialName = m.name;
    return to_working_space(doc, m, ocio_color_converter());
}

const std::vector<std::string>& display_views() {
    static const std::vector<std::string> v = {"aces", "standard"};
    return v;
}

std::string display_description(const std::string& view, double exposureEv) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "exposure %+.2f EV, ", exposureEv);
    if (view == "aces")
        return std::string(buf) +
               "ACES 1.0 SDR-video output transform (OpenColorIO built-ins), sRGB display";
    return std::string(buf) + "no tone curve (clipped), sRGB display encoding";
}

void apply_display(std::vector<float>& rgb, const std::string& view, double exposureEv) {
    OCIO::GroupTransformRcPtr g = OCIO::GroupTransform::Create();
    const double s = std::pow(2.0, exposureEv);
    g->appendTransform(matrix({{{s, 0, 0}, {0, s, 0}, {0, 0, s}}}));
    if (view == "aces") {
        g->appendTransform(matrix(rgb_to_xyz(kRec709, kD65)));
        g->appendTransform(
            builtin("UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD", OCIO::TRANSFORM_DIR_INVERSE));
        g->appendTransform(builtin("ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 - SDR-VIDEO_1.0"));
        g->appendTransform(builtin("DISPLAY - CIE-XYZ-D65_to_sRGB"));
    } else if (view == "standard") {
        OCIO::RangeTransformRcPtr clip = OCIO::RangeTransform::Create();
        clip->setMinInValue(0.0);
        clip->setMinOutValue(0.0);
        clip->setMaxInValue(1.0);
        clip->setMaxOutValue(1.0);
        g->appendTransform(clip);
        g->appendTransform(srgb_curve(OCIO::TRANSFORM_DIR_INVERSE));
    } else {
        throw InputError("--view " + view + ": expected aces or standard");
    }
    const OCIO::ConstCPUProcessorRcPtr p = cpu(g);
    OCIO::PackedImageDesc desc(rgb.data(), long(rgb.size() / 3), 1, 3);
    p->apply(desc);
    for (float& v : rgb)
        v = std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f);
}

} // namespace retroprism
