// luminaire.h: luminous intensity distributions of lamps (headlamps), read from IES LM-63
// files (.ies), EULUMDAT files (.ldt) and candela matrices (CSV): `retroprism approach
// --headlamps`.
//
// The lamp's frame (metres, as analysis/approach.h's road): +z is the lamp's reference axis,
// straight ahead along the road the vehicle drives; +y is up; +x is to the right as the driver
// sees it (toward the right shoulder). Directions point away from the lamp.
//
// Photometric angles (degrees) of a direction d = (x, y, z) in that frame:
//  - Type A (automotive; LM-63 photometric type 3): polar axis vertical. The horizontal angle H
//    is the turn about the vertical axis from straight ahead, positive to the right; the
//    vertical angle V is the elevation above the horizontal plane, positive up:
//    d = (cos V sin H, sin V, cos V cos H).
//  - Type B (floodlights; type 2): polar axis horizontal, along x. V is the turn about the
//    x axis, positive up; H is the angle out of the vertical plane y-z, positive to the right:
//    d = (sin H, cos H sin V, cos H cos V).
//  - Type C (C-gamma; type 1, and every EULUMDAT file): polar axis vertical. gamma (the file's
//    vertical angle) is measured from straight down (0) to straight up (180); the C angle (the
//    file's horizontal angle) turns counter-clockwise seen from above, from straight ahead (C 0)
//    to the left (C 90): d = (-sin gamma sin C, -cos gamma, sin gamma cos C). A headlamp's
//    beam, straight ahead, is at gamma 90, C 0.
// Near straight ahead, types A and B differ by second-order terms (at H = V = 10 degrees, by
// 0.21 degrees in direction).
//
// Symmetry: the horizontal angles a file lists say which part of the distribution it holds,
// the rest follows by symmetry (LM-63):
//  - types A and B: from -90 .. 90 (or a part: the distribution is 0 outside), or starting at
//    0: symmetric about the vertical plane (H and -H the same);
//  - type C: starting at 0 and ending at 0 (symmetric about the vertical axis), 90 (about the
//    planes C 0-180 and C 90-270), 180 (about the plane C 0-180) or above 180 up to 360 (no
//    symmetry; between the last angle and 360 interpolated toward C 0).
// Outside the vertical angles listed, the intensity is 0. Between listed angles it is
// interpolated bilinearly in (horizontal, vertical) angle.
//
// CSV form (candela matrix): lines whose first non-blank character is '#' are comments, blank
// lines are skipped, fields are separated by commas. The first row is a header: its first
// field the photometric type (A, B or C), then the horizontal angles; every other row holds a
// vertical angle and then the intensity in cd at each horizontal angle. Angles ascending (rows
// too), candela finite and >= 0. Example (type A, 3 x 2):
//   A, -10, 0, 10
//   -2, 500, 8000, 6000
//   2, 200, 400, 300
#pragma once

#include <istream>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace retroprism {

enum class PhotometricType { A, B, C };

// A luminous intensity distribution: intensities in cd on a grid of photometric angles.
struct LuminousIntensityDistribution {
    std::string file; // the name used in messages
    PhotometricType type = PhotometricType::C;
    std::vector<double> horizontal_deg; // ascending (type C: C angles)
    std::vector<double> vertical_deg;   // ascending (type C: gamma)
    // candela[h * vertical_deg.size() + v], in cd, every multiplier of the file applied
    // (LM-63: the candela multiplier times the ballast factor; the value after the ballast
    // factor, 2002's "future use" and 2019's file generation type, is read and not applied.
    // EULUMDAT: the file's cd/klm times the lamps' total flux / 1000 lm).
    std::vector<double> candela;
    double multiplier = 1; // the factor applied to the file's values to give candela

    // The intensity (cd) toward `direction` (the lamp's frame above; need not be unit length;
    // 0 for the zero vector or a non-finite one).
    double intensity(const glm::dvec3& direction) const;
    // The intensity at the file's angles (degrees), after the symmetry above.
    double intensity_at(double horizontalDeg, double verticalDeg) const;
};

// "A", "B" or "C".
const char* photometric_type_name(PhotometricType t);

// The photometric angles (degrees) of a direction in the lamp's frame: {horizontal, vertical}
// by the type's convention above (type C: {C in [0, 360), gamma}).
glm::dvec2 photometric_angles(PhotometricType t, const glm::dvec3& direction);

// The readers. Every error is an InputError "FILE:LINE: ..." naming what is wrong and the
// allowed form or range: a missing or unknown header or TILT line (LM-63's TILT=INCLUDE and
// TILT=FILENAME are not read: a headlamp is measured in its mounting position), a field that is
// not a finite number, a count out of range (angles 1 to 2000 each, at most 1,000,000 values),
// an unknown photometric type or symmetry, angles out of range or not ascending, a negative
// candela value or multiplier, a file that ends before its values do, values after them.
LuminousIntensityDistribution parse_ies(std::istream& in, const std::string& name);
LuminousIntensityDistribution parse_eulumdat(std::istream& in, const std::string& name);
LuminousIntensityDistribution parse_candela_csv(std::istream& in, const std::string& name);

// Reads the file at `path` by its extension: .ies, .ldt or .csv (any case); InputError naming
// the allowed extensions for any other.
LuminousIntensityDistribution read_luminaire(const std::string& path);

// "LEFT[,RIGHT]": the left and right headlamps' distributions (one file: both lamps);
// InputError for an empty list or more than two files.
std::pair<LuminousIntensityDistribution, LuminousIntensityDistribution>
read_headlamp_pair(const std::string& files);

} // namespace retroprism
