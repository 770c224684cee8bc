// photopic.h: the weighting of wavelengths by which a photometer under the standard
// illuminant sees R_A (CIE 54.2: illuminant A, the CIE 1931 observer's y-bar, i.e. V(lambda)):
// the relative spectral power of illuminant A, the photopic luminous efficiency, and the 15
// wavelengths over which the project integrates them (the wave simulator's `--photopic` and
// the node's photopic R_A, analysis/photometry.h).
#pragma once

#include <vector>

namespace retroprism {

// CIE standard illuminant A, relative spectral power (100 at 560 nm), CIE 15:2004 Eq. 1:
// S_A = 100 (560/lambda)^5 (exp(1.435e7 / (2848 * 560)) - 1) / (exp(1.435e7 / (2848 lambda)) - 1).
double illuminant_a(double lambdaNm);
// CIE 1924 photopic luminous efficiency V(lambda), the CIE's 10-nm table from 380 to 780 nm
// interpolated linearly (0 outside).
double photopic_v(double lambdaNm);
// The photometric wavelengths: 410, 430, ..., 690 nm (midpoints of 20-nm bins over 400-700 nm)
// and their weights S_A V, normalised to sum 1.
const std::vector<double>& photopic_wavelengths_nm();
const std::vector<double>& photopic_weights();

} // namespace retroprism
