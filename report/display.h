// display.h: scene-linear Rec.709 to a display image with OpenColorIO (io/ocio_transforms.h),
// for the PNGs of the night preview: scene-linear Rec.709 -> x 2^exposure -> view transform -> sRGB
// display.
//   view "aces" (default): the ACES 1.0 SDR-video output transform, i.e. Rec.709 -> CIE XYZ
//     (D65) -> ACES2065-1 (inverse of the built-in "UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD"),
//     the built-in "ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 - SDR-VIDEO_1.0" (RRT + ODT tone
//     curve: scene 0.18 -> display 0.36, 1 -> 0.81, 16 -> 1.0) and
//     "DISPLAY - CIE-XYZ-D65_to_sRGB" (sRGB piecewise encoding); the ACES configs' "sRGB -
//     Display / ACES 1.0 - SDR Video" view.
//   view "standard": no tone curve: clipped to [0, 1] and sRGB-encoded (inverse of the sRGB
//     ExponentWithLinearTransform).
#pragma once

#include <string>
#include <vector>

namespace retroprism {

// The display views ("aces", "standard") and a one-line description of one.
const std::vector<std::string>& display_views();
std::string display_description(const std::string& view, double exposureEv);

// Applies exposure and view to interleaved linear Rec.709 RGB (3 floats per pixel) in place;
// the result is display-encoded sRGB in [0, 1].
void apply_display(std::vector<float>& rgb, const std::string& view, double exposureEv);

} // namespace retroprism
