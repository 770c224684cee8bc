#include "display.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "error.h"
#include "ocio_transforms.h"

namespace retroprism {

using namespace ocio;

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
