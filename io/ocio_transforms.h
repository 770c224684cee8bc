// ocio_transforms.h: the OpenColorIO transforms the colour code is built from, on a raw config
// (Debian 12's OCIO 2.1 has no built-in config): RGB primaries to CIE XYZ, matrices, the sRGB
// and pure-power curves, OCIO's built-in transforms, and a CPU processor of a transform. Used by
// the input side (io/color.h) and the display side (report/display.h).
#pragma once

#include <array>

#include <OpenColorIO/OpenColorIO.h>

namespace retroprism::ocio {

namespace OCIO = OCIO_NAMESPACE;

using Mat3 = std::array<std::array<double, 3>, 3>;

// CIE xy chromaticities: the D65 white and the primaries of Rec.709, Display P3 and Adobe RGB.
inline constexpr double kD65[2] = {0.3127, 0.3290};
inline constexpr double kRec709[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
inline constexpr double kP3[3][2] = {{0.680, 0.320}, {0.265, 0.690}, {0.150, 0.060}};
inline constexpr double kAdobe[3][2] = {{0.64, 0.33}, {0.21, 0.71}, {0.15, 0.06}};

Mat3 mul(const Mat3& a, const Mat3& b);
Mat3 inverse(const Mat3& m);
// RGB -> CIE XYZ for primaries and white given as CIE xy chromaticities (SMPTE RP 177).
Mat3 rgb_to_xyz(const double xy[3][2], const double white[2]);

OCIO::MatrixTransformRcPtr matrix(const Mat3& m);
// The sRGB piecewise curve (gamma 2.4, offset 0.055); forward: encoded -> linear.
OCIO::TransformRcPtr srgb_curve(OCIO::TransformDirection dir);
// A pure power curve; forward: encoded -> linear.
OCIO::TransformRcPtr power(double gamma);
// One of OCIO's built-in transforms by its style name.
OCIO::TransformRcPtr builtin(const char* style,
                             OCIO::TransformDirection dir = OCIO::TRANSFORM_DIR_FORWARD);
// Linear `primaries` (D65) -> linear Rec.709.
OCIO::TransformRcPtr to_rec709(const double primaries[3][2]);
// The CPU processor of a transform; std::runtime_error with OCIO's message when it fails.
OCIO::ConstCPUProcessorRcPtr cpu(const OCIO::ConstTransformRcPtr& t);

} // namespace retroprism::ocio
