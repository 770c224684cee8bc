// color.h: colour management with OpenColorIO (Debian 12 ships OCIO 2.1, which has no built-in
// config: `ocio://default` arrived in 2.2). The transforms are built in code from OCIO's own
// transforms on a raw config (OCIO::Config::CreateRaw), so nothing depends on $OCIO.
//
// Input colours (MaterialX colour spaces -> lin_rec709, MaterialX's default working space):
//   lin_rec709                      identity
//   srgb_texture                    sRGB piecewise curve (ExponentWithLinearTransform, gamma
//                                   2.4, offset 0.055), Rec.709 primaries
//   g22_rec709, g18_rec709          pure power 2.2 / 1.8 (ExponentTransform), Rec.709 primaries
//   acescg = lin_ap1                BuiltinTransform "UTILITY - ACES-AP1_to_LINEAR-REC709_BFD"
//   g22_ap1, g18_ap1                power 2.2 / 1.8, then the same
//   lin_displayp3, srgb_displayp3   P3 primaries, D65 (MatrixTransform from the primaries),
//                                   linear / sRGB curve
//   lin_adobergb, adobergb          Adobe RGB (1998) primaries, D65; linear / power 563/256
//
// Display (the PNG): scene-linear Rec.709 -> x 2^exposure -> view transform -> sRGB display.
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

#include "mtlx_reader.h"

namespace retroprism {

// A colour from a MaterialX colour space (mtlx_colorspaces()) to lin_rec709.
Color3 to_lin_rec709(const std::string& colorspace, const Color3& c);
ColorConverter ocio_color_converter();

// The node's parameters of the material `name` (the first when empty) of a MaterialX
// document, colours converted to lin_rec709. `materialName` receives the material's name.
Params document_params(const std::string& path, const std::string& name,
                       std::string* materialName = nullptr);

// The display views ("aces", "standard") and a one-line description of one.
const std::vector<std::string>& display_views();
std::string display_description(const std::string& view, double exposureEv);

// Applies exposure and view to interleaved linear Rec.709 RGB (3 floats per pixel) in place;
// the result is display-encoded sRGB in [0, 1].
void apply_display(std::vector<float>& rgb, const std::string& view, double exposureEv);

} // namespace retroprism
