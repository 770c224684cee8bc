#include "alta_reader.h"
#include "parse.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "query.h"
#include "text_file.h"

namespace retroprism {

namespace {

constexpr double kHalfPi = 1.5707963267948966;
// theta_v may exceed pi/2 by rounding in the file (the CEA files write 1.5707963267948966 as
// 1.57079632679489655799...): allowed up to this much, then treated as grazing.
constexpr double kAngleSlack = 1e-9;

std::vector<std::string> split_ws(const std::string& s) {
    std::istringstream ss(s);
    std::vector<std::string> out;
    std::string w;
    while (ss >> w)
        out.push_back(w);
    return out;
}

// Overflow gives an infinity (rejected); underflow to a tiny number or zero is fine.
bool parse_double(const std::string& s, double& v) {
    const std::optional<double> x = try_parse_number(s);
    if (x) v = *x;
    return x.has_value();
}

} // namespace

glm::dvec3 AltaSample::wi() const {
    return glm::dvec3(std::sin(theta_l), 0.0, std::cos(theta_l));
}

glm::dvec3 AltaSample::wo() const {
    const double thetaV = std::min(std::hypot(x, y), kHalfPi);
    if (thetaV <= 0.0) return glm::dvec3(0.0, 0.0, 1.0);
    const double s = std::sin(thetaV) / std::hypot(x, y);
    return glm::dvec3(x * s, y * s, std::cos(thetaV));
}

double AltaSample::value_cos(bool cosine_factor) const {
    return cosine_factor ? value : value * std::max(wo().z, 0.0);
}

std::string AltaData::header_value(const std::string& keyword) const {
    for (const auto& kv : header)
        if (kv.first == keyword) {
            std::string v = kv.second;
            if (v.size() >= 2 && v.front() == '"' && v.back() == '"') v = v.substr(1, v.size() - 2);
            return v;
        }
    return "";
}

namespace {

// The output quantity a #PARAM_OUT value names: true for BRDF x cos(theta_v); InputError
// (through `fail`) for an unsupported one.
template <class Fail>
bool cosine_factor_of(const std::string& paramOut, const std::string& what, const Fail& fail) {
    if (paramOut == "INV_STERADIAN_COSINE_FACTOR") return true;
    if (paramOut != "INV_STERADIAN")
        fail(what + " " + paramOut +
             ": unsupported output; expected INV_STERADIAN_COSINE_FACTOR (BRDF x cos theta_v) or "
             "INV_STERADIAN (BRDF)");
    return false;
}

} // namespace

AltaData parse_alta(const std::string& text, const std::string& name, const std::string& paramOut) {
    if (!paramOut.empty() && paramOut != "INV_STERADIAN_COSINE_FACTOR" &&
        paramOut != "INV_STERADIAN")
        throw InputError("--param-out " + paramOut +
                         ": expected INV_STERADIAN_COSINE_FACTOR (BRDF x cos theta_v) or "
                         "INV_STERADIAN (BRDF)");
    AltaData d;
    d.file = name;
    bool haveDim = false;
    std::istringstream in(text);
    std::string raw;
    int lineNo = 0;
    auto fail = [&](const std::string& msg) {
        throw InputError(name + ":" + std::to_string(lineNo) + ": " + msg);
    };
    while (std::getline(in, raw)) {
        ++lineNo;
        const std::string line = trim(raw);
        if (line.empty()) continue;
        if (line[0] == '#') {
            const std::string body = line.substr(1);
            const size_t sp = body.find_first_of(" \t");
            const std::string key = body.substr(0, sp);
            const std::string rest = sp == std::string::npos ? "" : trim(body.substr(sp));
            d.header.emplace_back(key, rest);
            if (key == "DIM") {
                const std::vector<std::string> w = split_ws(rest);
                if (w.size() != 2 || w[0] != "3" || w[1] != "1")
                    fail("#DIM " + rest +
                         ": expected \"#DIM 3 1\" (three input coordinates, one output value; "
                         "RGB data is not supported)");
                haveDim = true;
            } else if (key == "PARAM_IN") {
                if (rest != "ISOTROPIC_TL_TV_PROJ_DPHI")
                    fail("#PARAM_IN " + rest +
                         ": unsupported parametrisation; expected ISOTROPIC_TL_TV_PROJ_DPHI "
                         "(theta_l, theta_v cos dphi, theta_v sin dphi)");
                d.param_in = rest;
            } else if (key == "PARAM_OUT") {
                if (!d.samples.empty())
                    fail("#PARAM_OUT after data lines; it must come before the first data line");
                d.cosine_factor = cosine_factor_of(rest, "#PARAM_OUT", fail);
                if (!paramOut.empty() && paramOut != rest)
                    fail("#PARAM_OUT " + rest + " contradicts --param-out " + paramOut +
                         " (which is for files without #PARAM_OUT)");
                d.param_out = rest;
            }
            continue;
        }
        if (!haveDim || d.param_in.empty())
            fail("data line before the header is complete: the file must declare #DIM 3 1 and "
                 "#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI before its data");
        if (d.param_out.empty()) {
            // ALTA reads a missing #PARAM_OUT as an unknown output; take the stated one.
            d.param_out = paramOut.empty() ? "INV_STERADIAN_COSINE_FACTOR" : paramOut;
            d.cosine_factor = cosine_factor_of(d.param_out, "--param-out", fail);
            if (paramOut.empty())
                d.warning = name + ": no #PARAM_OUT before the data (line " +
                            std::to_string(lineNo) +
                            "); the values are taken as BRDF x cos(theta_v) "
                            "(INV_STERADIAN_COSINE_FACTOR, as in the CEA campaign's files); give "
                            "--param-out INV_STERADIAN if they are the BRDF itself";
        }
        const std::vector<std::string> w = split_ws(line);
        if (w.size() != 4)
            fail("expected 4 numbers (theta_l x y value), found " + std::to_string(w.size()) +
                 " fields");
        double v[4];
        static const char* kField[4] = {"theta_l", "x", "y", "value"};
        for (int k = 0; k < 4; ++k)
            if (!parse_double(w[size_t(k)], v[k]))
                fail(std::string(kField[k]) + " \"" + w[size_t(k)] + "\" is not a finite number");
        AltaSample s;
        s.theta_l = v[0];
        s.x = v[1];
        s.y = v[2];
        s.value = v[3];
        s.line = lineNo;
        if (s.theta_l < 0.0 || s.theta_l >= kHalfPi)
            fail("theta_l = " + w[0] + " rad is outside [0, pi/2) (the light must be above the " +
                 "surface)");
        if (std::hypot(s.x, s.y) > kHalfPi + kAngleSlack)
            fail("theta_v = |(x, y)| = " + std::to_string(std::hypot(s.x, s.y)) +
                 " rad is beyond pi/2 (the view must be above the surface)");
        if (s.value < 0.0) fail("value " + w[3] + " is negative; a BRDF cannot be negative");
        d.samples.push_back(s);
    }
    if (d.samples.empty()) {
        lineNo = std::max(lineNo, 1);
        fail("no data lines (expected lines of \"theta_l x y value\" after the header)");
    }
    return d;
}

AltaData read_alta(const std::string& path, const std::string& paramOut) {
    return parse_alta(read_text_file(path), path, paramOut);
}

} // namespace retroprism
