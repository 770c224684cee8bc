// photometry.h: the coefficient of retroreflection R_A of a material (MODEL.md section 5).
//
// R_A = f(wi, wo) cos(theta_i) cos(theta_o), in cd lx^-1 m^-2 (numerically 1/sr): the luminous
// intensity sent toward the observer per unit illuminance on a plane perpendicular to the
// illumination axis, per unit sample area.
//
// Angle conventions (ASTM E808 / E810, CIE 54.2), coplanar geometry: presentation angle
// gamma = 0 and the second entrance-angle component beta_2 = 0, so the illumination axis, the
// observation axis and the reference axis (the sample's normal) lie in one plane.
//  - Sample frame: reference axis n = +z; the datum mark is the node's tangent, +x.
//  - Entrance angle beta: from the reference axis to the illumination axis, signed, in the
//    x-z plane: wi = (sin beta, 0, cos beta). A negative entrance angle puts the source on the
//    other side of the normal (the -4 degree column of sign specifications).
//  - Observation angle alpha: between the illumination axis and the observation axis, in the
//    same plane. The instruments are fixed and the sample turns (a goniometer), so the observer
//    keeps its side of the source: wo = (sin(beta - alpha), 0, cos(beta - alpha)). For
//    beta > alpha the observer is between the source and the normal; for beta < 0 it is on the
//    far side. (At the table's alpha <= 1.5 degrees this choice changes R_A by < 0.1% for
//    the node: its retro lobe is symmetric about wi.)
//  - Presentation angle gamma (0 in the coplanar geometry above): the observation axis turned
//    about the illumination axis by gamma, counter-clockwise seen from the source.
//  - Rotation angle epsilon: the sample (with its prisms and datum mark) turned about its
//    normal by epsilon, counter-clockwise seen from the source's side (+z). Evaluated by turning
//    wi and wo by -epsilon about z in the sample frame; it matters for era_mode oriented
//    (period 120 degrees) and matched_pair (period 180), not for averaged.
// The material's normal and tangent inputs are not used: R_A is a property of the flat sample.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "prismatic_retroreflector.h"
#include "ra_table.h"

namespace retroprism {

// Rec. 709 luminance Y of linear RGB.
double luminance_709(const glm::dvec3& rgb);

// How R_A's luminance is taken over wavelengths. Channels: luminance Y of the node's three
// channels (at the material's `wavelength`, or at 610, 550 and 465 nm). Photopic: as a
// photometer under illuminant A sees it (CIE 54.2), the sum over util/photopic.h's 15
// wavelengths (410-690 nm) of their weights S_A V times Y of the node at that wavelength (every
// channel there, so a coloured retro_color enters by its luminance), the material's own
// `wavelength` replaced: the diffraction of prism_pitch, and the index with abbe_number, per
// wavelength across the band instead of at three.
enum class RaSpectrum { Channels, Photopic };

// f(node at a wavelength, its weight) over the spectrum's wavelengths: Channels, the node itself
// with weight 1; Photopic, node.at_wavelength(lambda) with its weight for each of
// photopic_wavelengths_nm() (util/photopic.h).
void for_each_wavelength(
    const PrismaticRetroreflector<double>& node, RaSpectrum spectrum,
    const std::function<void(const PrismaticRetroreflector<double>&, double)>& f);

// The standard table's angles (degrees).
const std::vector<double>& ra_observation_angles(); // 0.2, 0.33, 0.5, 1.0, 1.5
const std::vector<double>& ra_entrance_angles();    // -4, 15, 30, 40, 45

// wi and wo in the node's local frame for entrance beta, observation alpha, rotation epsilon
// and presentation gamma (degrees), by the conventions above.
void ra_directions(double entranceDeg, double observationDeg, double rotationDeg, glm::dvec3& wi,
                   glm::dvec3& wo, double presentationDeg = 0.0);

// The angles (degrees) of a pair of directions in the sample frame, the inverse of
// ra_directions: entrance beta in [0, 90] (unsigned: a negative entrance angle is the same
// geometry with the rotation turned by 180 degrees), observation alpha, rotation epsilon and
// presentation gamma in (-180, 180]; rotation 0 at normal incidence, presentation 0 at zero
// observation.
struct RaGeometry {
    double entrance = 0, observation = 0, rotation = 0, presentation = 0;
};
RaGeometry ra_geometry(const glm::dvec3& wi, const glm::dvec3& wo);

// The node's parameters for R_A: the material with the default frame (normal +z, tangent +x).
Params ra_params(const Params& material);

// R_A per RGB channel (cd lx^-1 m^-2) of a node built from ra_params(material).
glm::dvec3 ra_value(const PrismaticRetroreflector<double>& node, double entranceDeg,
                    double observationDeg, double rotationDeg);

// R_A (luminance Y) of a measured entry's geometry (io/ra_table.h): at its rotation, or the
// mean over rotations 0 and 90 degrees when it has none, at its presentation angle; `ra` is
// the R_A in RGB of a material at (entrance, observation, rotation, presentation) in degrees.
double ra_at_entry(const RaEntry& e,
                   const std::function<glm::dvec3(double, double, double, double)>& ra);
// The same for the node built from ra_params(material).
double ra_at_entry(const PrismaticRetroreflector<double>& node, const RaEntry& e);

struct RaTable {
    std::vector<double> observation;          // rows, degrees
    std::vector<double> entrance;             // columns, degrees
    double rotation = 0;                      // degrees
    std::vector<std::vector<glm::dvec3>> rgb; // [row][column]
};

// Photopic: every channel of the table holds the photopic R_A.
RaTable ra_table(const Params& material, double rotationDeg,
                 const std::vector<double>& observation = ra_observation_angles(),
                 const std::vector<double>& entrance = ra_entrance_angles(),
                 RaSpectrum spectrum = RaSpectrum::Channels);

// A BRDF evaluated in batches (a backend): f(wi, wo) in RGB (1/sr, without the cosine) at each
// (wi, wo) pair, directions in the node's local frame (normal +z, tangent +x).
using BrdfBatch =
    std::function<std::vector<glm::dvec3>(const std::vector<std::array<glm::dvec3, 2>>&)>;

// The R_A table of a BRDF given as a batch, by the angle conventions above.
RaTable ra_table(const BrdfBatch& f, double rotationDeg,
                 const std::vector<double>& observation = ra_observation_angles(),
                 const std::vector<double>& entrance = ra_entrance_angles());

// A table's deviation from a reference table of the same angles, in luminance Y: per entry
// (y - y_ref) / y_ref, and the largest magnitude and its angles.
struct RaDeviation {
    std::vector<std::vector<double>> relative; // [row][column]
    double max_abs = 0;
    double observation = 0; // degrees, where max_abs is
    double entrance = 0;
};
RaDeviation ra_deviation(const RaTable& reference, const RaTable& t);

} // namespace retroprism
