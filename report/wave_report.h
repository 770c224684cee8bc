// wave_report.h: the physical-optics R_A as text (`retroprism simulate --wave`), and the node's
// retro lobe against it (sim/wave_node.h) as text and as a figure (`simulate --wave
// --against-node [--plot FILE.png]`, docs/diffraction.md#against-physical-optics).
#pragma once

#include <cstdio>
#include <vector>

#include <OpenImageIO/imagebuf.h>

#include "plot.h"
#include "wave_node.h"
#include "wave_optics.h"

namespace retroprism {

// A head line naming the material, then per wavelength of `lambdasNm` (0: the photopic
// weighting) a block with a row per observation angle and a column per entrance angle:
// ra[wavelength][entrance][observation], R_A in sr^-1.
void print_wave_table(const sim::wave::WaveMaterial& m, const std::vector<double>& lambdasNm,
                      const std::vector<double>& entranceDeg,
                      const std::vector<double>& observationDeg,
                      const std::vector<std::vector<std::vector<double>>>& ra, std::FILE* out);

// A head line naming the material (the node's parameters of the profiles' cases) and the pitch
// spread, then per profile a block with a row per observation angle (`observationDeg`, the
// profiles' angles): the node's R_A, the wave optics' and their ratio; then the counts over all
// entries (sim::wave::node_wave_counts).
void print_node_wave(const Params& material,
                     const std::vector<sim::wave::NodeWaveProfile>& profiles,
                     const std::vector<double>& observationDeg, double pitchSpread, std::FILE* out);

namespace plot {

// The observation angles of node_wave_figure's curves: 60 log-spaced over [0.05, 3] degrees.
std::vector<double> node_wave_plot_observations();

// R_A against observation angle (log-log, the angles of node_wave_plot_observations), the wave
// optics' curve and the node's, a panel per profile: a row per entrance angle and a column per
// wavelength, in the profiles' first order; above each panel the range of node / wave and the
// entries within 10%. The title names the material's faces and pitch (the first profile's).
OIIO::ImageBuf node_wave_figure(const Params& material,
                                const std::vector<sim::wave::NodeWaveProfile>& profiles,
                                double pitchSpread, Text& text);

} // namespace plot

} // namespace retroprism
