// night_output.h: the files of a night preview (analysis/night_render.h), written only when
// everything succeeded (temporary names, then renamed; on any failure neither file remains):
//  - the EXR: linear Rec.709 radiance (scene units), float, channels R, G, B, A (combined,
//    A = coverage) and one layer per layer of the image present, in this order:
//    surface.{R,G,B}, retro.{R,G,B}, diffuse.{R,G,B}, other.{R,G,B}; R = the sum of the
//    layers' R; attributes retroprism:* describe the document, the material's inputs (the
//    node's, or the renderer of a MaterialX graph), the quantity, the lights and the display
//    transform;
//  - the display PNG: the combined RGB through OpenColorIO (io/color.h): x 2^exposure and the
//    view transform.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "night_render.h"

namespace retroprism {

struct NightOutput {
    std::string exrPath;
    std::string pngPath;
    std::string view = "aces";
    double exposureEv = -6;
    // What was rendered, for the EXR's attributes.
    std::string document;
    std::string material;
    Params inputs;
    bool fill = false;
    // When not empty, the EXR's retroprism:inputs in place of `inputs` (a MaterialX graph's
    // renderer and shader).
    std::string inputsDescription;
};

// The layers `img` holds, in the EXR's order: ("surface", &img.surface), ... ("other", ...).
std::vector<std::pair<const char*, const std::vector<float>*>> night_layers(const NightImage& img);

// Writes both files; InputError naming the file that could not be written.
void write_night_images(const NightImage& img, const NightOutput& out);

} // namespace retroprism
