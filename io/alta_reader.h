// alta_reader.h: measured BRDF samples in the text format of the ALTA library (Belcour et al.),
// as distributed with the CEA retroreflection measurements (shared data, belcour2014/README.md).
//
// Header lines start with '#': `#DIM 3 1` (three input coordinates, one output value),
// `#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI`, `#PARAM_OUT INV_STERADIAN_COSINE_FACTOR` (the value is
// BRDF x cos(theta_v), 1/sr) or `INV_STERADIAN` (the BRDF itself; see read_alta for a file
// without #PARAM_OUT); other '#' lines (#SAMPLE,
// #ORIGIN, #URL, #VS, ...) are kept as header text. Each data line is `theta_l x y value`:
// theta_l the light's polar angle (radians) at azimuth 0; (x, y) = (theta_v cos dphi,
// theta_v sin dphi) the view direction's polar angle and its azimuth relative to the light.
// Directions in the local frame (normal +z): wi = (sin theta_l, 0, cos theta_l),
// wo = (x / theta_v sin theta_v, y / theta_v sin theta_v, cos theta_v), theta_v = |(x, y)|
// (the normal when theta_v = 0).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace retroprism {

struct AltaSample {
    double theta_l = 0; // radians
    double x = 0, y = 0;
    double value = 0; // as in the file (see AltaData::cosine_factor)
    int line = 0;     // 1-based line in the file

    glm::dvec3 wi() const;
    glm::dvec3 wo() const;
    // BRDF x cos(theta_v), whatever the file's PARAM_OUT.
    double value_cos(bool cosine_factor) const;
};

struct AltaData {
    std::string file;                                        // the name used in messages
    std::vector<std::pair<std::string, std::string>> header; // keyword (without '#'), rest
    std::string param_in;                                    // ISOTROPIC_TL_TV_PROJ_DPHI
    std::string param_out;                                   // INV_STERADIAN[_COSINE_FACTOR]
    bool cosine_factor = true;                               // the values include cos(theta_v)
    std::string warning; // set when the file has no #PARAM_OUT and the output was assumed
    std::vector<AltaSample> samples;
    // The value of a header keyword (e.g. "SAMPLE"), unquoted, or "" when absent.
    std::string header_value(const std::string& keyword) const;
};

// Reads and checks a file; every error is an InputError naming FILE:LINE and what is expected:
// a missing or unsupported #DIM / #PARAM_IN, an unsupported #PARAM_OUT or one after the data,
// data before #DIM and #PARAM_IN, a line without exactly 4 numbers, a non-finite or negative
// value, theta_l outside [0, 90) degrees or theta_v beyond 90 degrees, a file without data.
// A file without #PARAM_OUT (ALTA reads it as an unknown output) is read as `paramOut` says
// (INV_STERADIAN_COSINE_FACTOR or INV_STERADIAN); when that is empty, as
// INV_STERADIAN_COSINE_FACTOR (BRDF x cos(theta_v), as in the CEA campaign's files) with
// AltaData::warning naming the assumption. A file whose #PARAM_OUT differs from a non-empty
// `paramOut` is an error.
AltaData read_alta(const std::string& path, const std::string& paramOut = "");
// The same from text in memory; `name` stands for the file in messages.
AltaData parse_alta(const std::string& text, const std::string& name,
                    const std::string& paramOut = "");

} // namespace retroprism
