// color.h: input colours with OpenColorIO. The transforms are built in code from OCIO's own
// transforms on a raw config (io/ocio_transforms.h), so nothing depends on $OCIO.
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
#pragma once

#include <string>
#include <vector>

#include "mtlx_reader.h"

namespace retroprism {

// A colour from a MaterialX colour space (mtlx_colorspaces()) to lin_rec709.
Color3 to_lin_rec709(const std::string& colorspace, const Color3& c);
ColorConverter ocio_color_converter();

// The node's parameters of the material `name` (the first when empty) of a MaterialX
// document, colours converted to lin_rec709. `materialName` receives the material's name. A
// graph (mtlx_reader.h's MtlxOutline::graph()) is an InputError saying what it holds and that
// only the node's chain is read here.
Params document_params(const std::string& path, const std::string& name,
                       std::string* materialName = nullptr);

} // namespace retroprism
