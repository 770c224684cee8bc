// openmaterial_export.h: the node as ASAM OpenMATERIAL 3D files (io/openmaterial.h: what the
// fields mean): `retroprism export --format openmaterial`.
//
//  - The BRDF table NAME_brdf.xompt: f in 1/sr (no cosine) of the node at each wavelength
//    (its evaluation at a wavelength: diffraction of prism_pitch, the index with abbe_number), one
//    colour channel (red by default: the node's colours are not spectral). The format has one
//    incident azimuth, so the node is averaged over its orientation about the normal (the
//    rotation angle): exactly isotropic for era_mode averaged, a midpoint rule of
//    kTableRotations over one period (180 degrees matched pairs, 120 oriented) otherwise.
//    Grid (degrees): theta_i 0-85 every 5; per theta_i, theta_o every 4 from 0 to 88 and at
//    theta_i +- kRetroOffsetsDeg; per (theta_i, theta_o), phi_o every 15, and where theta_o is
//    within 5 degrees of theta_i also at angular offsets kRetroOffsetsDeg from the retro
//    (phi_o 0) and mirror (phi_o 180) azimuths (offset / sin(theta_o) in azimuth), both sides.
//    The values are the BRDF at the points (no receiver solid angle: receiverSolidAngles left out).
//  - The material file NAME.xomp: the coefficient of retroreflection R_A (luminance Y, the
//    node's colour channels: the visible) at observation 0.2 and entrance -4 degrees, rotation 0
//    (the first entry of ASTM D4956's tables), and the table's URI.
#pragma once

#include <string>
#include <vector>

#include "openmaterial.h"
#include "prismatic_retroreflector.h"

namespace retroprism {

constexpr int kTableRotations = 12;
// Offsets from the retro direction at which the table samples (degrees).
inline const std::vector<double> kRetroOffsetsDeg = {0.02, 0.05, 0.1, 0.2, 0.35, 0.5,
                                                     0.75, 1.0,  1.5, 2.5, 4.0};

// The node's f averaged over its rotation about the normal, at one wavelength and channel, in
// the table's coordinates (radians).
class IsotropicNode {
  public:
    IsotropicNode(const Params& material, double wavelengthNm, int channel);
    double f(double thetaI, double thetaO, double phiO) const;

  private:
    PrismaticRetroreflector<double> node_;
    int channel_;
    int rotations_;
    double period_;
};

struct OpenMaterialExport {
    std::string name; // the material's name and the files' stem
    std::vector<double> wavelengths_nm = {905.0, 1550.0};
    int channel = 0; // 0 red, 1 green, 2 blue
    std::string description;
};

// The table (metadata filled: name, a UUID from the inputs, sources saying what computed it).
BrdfTable node_brdf_table(const Params& material, const OpenMaterialExport& e);

// R_A (Y) at observation 0.2, entrance -4 degrees; InputError above the schema's 5000.
double openmaterial_ra(const Params& material);

// Writes DIR/NAME.xomp and DIR/NAME_brdf.xompt; returns the table written.
BrdfTable write_openmaterial(const Params& material, const OpenMaterialExport& e,
                             const std::string& dir);

// A table read back against the node: at every row (relative to the row's f, over rows whose f
// is above 1e-6 of the wavelength's largest), and at the centres between neighbouring rows in
// theta_o and phi_o near the retro direction (where the lobe is), the table's linear
// interpolation against the node: its relative error's median, 90th percentile and largest.
struct TableCheck {
    std::size_t rows = 0;
    double max_row_error = 0;
    std::size_t centres = 0;
    double median_centre_error = 0, p90_centre_error = 0, max_centre_error = 0;
};
TableCheck check_brdf_table(const BrdfTable& t, const Params& material, int channel);

} // namespace retroprism
