// brdf_plots.h: the pictures of `retroprism demo`: in-plane slices of a material's BRDF (log10 of
// the luminance of f cos theta_o per lobe against the signed outgoing angle) and false-colour
// hemisphere maps of the total, one panel per incidence angle.
#pragma once

#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

#include "brdf_maps.h"
#include "figure.h"
#include "plot.h"
#include "prismatic_retroreflector.h"

namespace retroprism::plot {

using BrdfSlice = retroprism::BrdfSlice;

// The figure and panel layout of in-plane slices: one wide panel per incidence angle, the signed
// outgoing angle [-90, 90] deg on x (ticks every 30), a log axis [yLo, yHi] decades on y, the
// expected retro (+theta) and mirror (-theta) peaks marked. angle: "theta_i" or "theta_l" (the
// heading), outgoing: "theta_o" or "theta_v" (the axis label).
void slice_layout(Figure& fig);
Panel slice_panel(double thetaDeg, double yLo, double yHi, const std::string& angle,
                  const std::string& outgoing);

// The slices of one material, one panel per incidence angle on a shared log axis (6 decades
// below the highest value). inputsLine: the caption's line naming the material's inputs.
OIIO::ImageBuf slice_figure(const std::string& name, const std::string& inputsLine,
                            const std::vector<BrdfSlice>& slices, Text& text);

// log10 of the luminance of the total f cos theta_o over the hemisphere (orthographic view from
// +z, `panel` pixels per side), one panel per theta_i (phi_i = 0), with a colour bar from the
// highest value down to the 5th percentile (2 to 6 whole decades).
OIIO::ImageBuf hemisphere_figure(const std::string& name,
                                 const PrismaticRetroreflector<double>& node,
                                 const std::vector<double>& thetaIDeg, int panel, Text& text);

} // namespace retroprism::plot
