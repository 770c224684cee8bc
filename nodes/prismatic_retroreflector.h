// prismatic_retroreflector.h: the closure-like node of retroreflective prismatic sheeting
// (Guo, Guo & Pan, Graphical Models 96 (2018) 38-46,
// "A retroreflective BRDF model based on prismatic sheeting and microfacet theory"), as
// specified by MODEL.md.
//
// Conventions (the same in every backend of the library):
//  - Frame: the node's `normal` is the local +z and its `tangent` (made orthogonal to the
//    normal) the local +x. Directions passed to eval / pdf / sample are expressed in the frame
//    in which normal and tangent are given; they are normalised here (a direction whose
//    squared length is within 1e-6 of 1 is used as given). With the default
//    normal (0,0,1) and tangent (1,0,0) that frame is the local shading frame.
//  - wi points toward the light, wo toward the viewer; both point away from the surface.
//  - f is the BRDF in 1/sr WITHOUT the cosine factor. Lobes: surface (k_s f_s, the rough top
//    surface), retro (f_r, the cube-corner prisms), diffuse (f_d, the substrate); `weight`
//    multiplies all three. A lobe whose weight or colour is zero contributes exactly 0.
//  - sample() returns the sampled direction wo, the lobes' values f at wo (not divided by the
//    pdf, no cosine), the one-sample-mixture pdf of wo in 1/sr, and the lobe that produced it;
//    it returns an empty optional when wi is below the horizon, nothing reflects, or the
//    sampled direction falls below the horizon. pdf() is the same mixture pdf.
//  - albedo(wi) = integral of f cos(theta_o) over the hemisphere, per lobe.
//  - Directions with cos(theta) < 1e-9 (RP_MIN_COS), and zero, tiny (length below 1e-15),
//    overflowing (length 1.7e19 or more) and non-finite directions, give zero values, a zero
//    pdf and an empty sample: never NaN or Inf.
//  - Parameters outside their range (the table in prismatic_retroreflector_params.def) are
//    clamped into it; NaN parameters take their default; a zero, tiny or non-finite normal takes
//    (0,0,1) and a tangent parallel to the normal (or zero, tiny, non-finite) is replaced by an
//    arbitrary orthogonal one.
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "prism_core.h"

namespace retroprism {

using Color3 = std::array<double, 3>;
using Vec3d = std::array<double, 3>;

// The node's inputs, generated from the parameter table. Enums are indices into their
// `enum_values` list.
struct Params {
#define RP_FLOAT(name, def, lo, hi, doc) double name = def;
#define RP_COLOR(name, r, g, b, doc) Color3 name = {r, g, b};
#define RP_ENUM(name, def, values, doc) int name = def;
#define RP_VECTOR(name, x, y, z, geomprop, doc) Vec3d name = {x, y, z};
#define RP_BOOL(name, def, doc) bool name = def;
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
};

// One row of the parameter table, for readers, help texts and generators.
enum class ParamType { Float, Color, Enum, Vector, Bool };
struct ParamInfo {
    const char* name;
    ParamType type;
    double default_value[3];
    double min_value;
    double max_value;
    const char* enum_values; // comma-separated, for ParamType::Enum
    const char* geomprop;    // default geometric property, for ParamType::Vector
    const char* doc;
};
const std::vector<ParamInfo>& param_table();
const ParamInfo* find_param(const std::string& name);

// The inputs `retroprism fit --ra` fits (the RP_FIT lines of the parameter table), in table
// order: floats and colours (one grey value) searched in [lo, hi] on a linear or logarithmic
// scale; enums and booleans (Choice) fitted by trying every value.
enum class FitScale { Linear, Log, Choice };
struct FitInfo {
    const ParamInfo* param;
    double lo;
    double hi;
    FitScale scale;
};
const std::vector<FitInfo>& fit_table();
// The input called `name` of `p`, by name, when it has the C++ type T (double for floats, int
// for enums, bool, Color3 = Vec3d for colours and vectors); nullptr otherwise.
template <class T>
T* input_field(Params& p, const std::string& name);
template <class T>
const T* input_field(const Params& p, const std::string& name) {
    return input_field<T>(const_cast<Params&>(p), name);
}
// Calls f(info, field) for every input of p in table order, with the input's C++ field:
// double& (floats), Color3& (colours and vectors: info.type tells them apart), int& (enums),
// bool&; const references for a const p. One walk over the parameter table for the code that
// treats every input alike (serialisation, descriptions, range checks).
template <class P, class F>
void for_each_input(P& p, F&& f) {
    for (const ParamInfo& info : param_table()) {
        switch (info.type) {
        case ParamType::Float:
            f(info, *input_field<double>(p, info.name));
            break;
        case ParamType::Color:
        case ParamType::Vector:
            f(info, *input_field<Color3>(p, info.name));
            break;
        case ParamType::Enum:
            f(info, *input_field<int>(p, info.name));
            break;
        case ParamType::Bool:
            f(info, *input_field<bool>(p, info.name));
            break;
        }
    }
}
// The enum's values as a list, and the index of `value` in it (-1 when absent).
std::vector<std::string> enum_values(const ParamInfo& info);
int enum_index(const ParamInfo& info, const std::string& value);

// Values clamped into the table's ranges, NaN replaced by defaults, vectors made unit
// (see the conventions above).
Params sanitize(const Params& p);

// Hemispherical-diffuse reflectance of the sheet's top surface for light from outside
// (2 * integral of F(cos, eta) cos sin over [0, pi/2]; closed form of the exact integral,
// with adaptive quadrature below eta = 1.01 where the closed form cancels) and from inside
// the sheet (F_dr of MODEL.md section 3, by eta^2 (1 - F_dr_int) = 1 - F_dr_ext).
double fdr_external(double eta);
double fdr_internal(double eta);

// ERA A of MODEL.md section 2 (the geometry alone, no face reflectance) of the inner direction
// at polar angle thetaT in [0, pi/2) and azimuth phi from one aperture vertex (radians), for
// the era_mode index eraMode of the parameter table (averaged, matched_pair, oriented), for
// cube corners of cant cantDeg (the cant_angle input, MODEL.md section 8).
double era(double thetaT, double phi, int eraMode, double cantDeg = 0.0);

// Azimuth-averaged ERA computed exactly (piecewise Gauss-Legendre between the azimuths where
// the overlap polygon changes form) instead of read from the table; for the table generator.
double era_averaged_direct(double tanThetaT);
// Azimuth average over the paper's cube's orientations of the number of faces a ray meets in
// the prism (sum_k H_k of prism_core.inc, the metallized prisms' substrate term), by piecewise
// Gauss-Legendre between its kinks; for the table generator.
double metal_hits_averaged_direct(double tanThetaT);
// Azimuth average of A R1 R2 R3 for uncoated (TIR) prisms by brute force: a midpoint rule of
// 2e6 azimuths over one period (slow, ~0.1 s; an independent reference for tests).
double retro_fraction_tir_averaged_direct(double tanThetaT, double eta);

// An azimuth average of a prism's retroreflection (rp_azimuth_average, prism_core.inc): the
// faces and range of rp_average_faces, the ior, whether faces are uncoated (tir) and whether the
// metallised prisms' face hits are averaged too (hits), over t = tan(theta_t) in [0, t_end].
struct AzimuthAverage {
    glm::dvec3 face_z{0.0}, face_xy{0.0}, face_phi{0.0};
    double phi_end = 0.0;
    double eta = 1.0;
    double t_end = 0.0;
    bool tir = false;
    bool hits = false;
};
// That average as the piecewise Chebyshev series rp_material::azimuth_series points to (layout:
// rp_azimuth_series, prism_core.inc), interpolating rp_azimuth_average at the points between
// each interval's nodes to within 1e-8 of the interval's largest value or 1e-11 of the
// function's largest, whichever is more, but where an interval reached the narrowest width
// allowed (nodes/azimuth_series.cpp; 0.3-50 ms to make). The last kSeriesCacheEntries series
// made are kept, most recently used first: another node of the same material (the same
// AzimuthAverage, bit for bit) copies its series instead of making it again. Thread-safe.
std::vector<double> azimuth_series(const AzimuthAverage& average);

// The series kept, and the lookups of azimuth_series that found theirs (hits) or made it
// (misses), since the process started.
constexpr int kSeriesCacheEntries = 32;
struct SeriesCacheStats {
    long long hits = 0;
    long long misses = 0;
    int entries = 0;
};
SeriesCacheStats azimuth_series_cache_stats();

// The indices of refraction below which canted prisms keep integrating: t_end =
// 1 / sqrt(eta^2 - 1), the largest tan(theta_t) of light refracted from outside, grows without
// bound as eta approaches 1 (3.1 at 1.05). Uncoated prisms of the paper's cube keep integrating
// below it too: their critical angle goes to 0 with eta - 1, and the series' refinement about it
// with it (at ior 1 + 2e-16 it does not end in minutes).
constexpr double kSeriesMinEtaCanted = 1.05;

// Points m.azimuth_series at the series of m's azimuth averages where the core would integrate
// them at every evaluation: the averaged ERA with canted prisms (ior at least
// kSeriesMinEtaCanted), or the paper's cube with uncoated prisms in the exact tier (the same ior
// bound); as the node does for its own material (any precision or generated variant of the core).
// Returns the series, null when m does not use one; it must outlive every use of m.
template <class Material>
auto attach_azimuth_series(Material& m) {
    using R = std::remove_cv_t<decltype(m.eta)>;
    std::shared_ptr<const std::vector<R>> series;
    if (m.era_mode != f64::RP_ERA_AVERAGED) return series;
    AzimuthAverage a;
    a.eta = double(m.eta);
    a.tir = m.prism_reflection == f64::RP_PRISM_TIR;
    a.hits = m.prism_reflection == f64::RP_PRISM_METALLIZED;
    if (m.canted != 0 && a.eta >= kSeriesMinEtaCanted) {
        a.t_end = 1.0 / std::sqrt((a.eta - 1.0) * (a.eta + 1.0));
    } else if (m.canted == 0 && a.tir && m.fidelity == f64::RP_FIDELITY_EXACT &&
               a.eta >= kSeriesMinEtaCanted) {
        a.t_end = f64::RP_ERA_TAN_MAX;
    } else {
        return series;
    }
    f64::rp_material faces{};
    faces.canted = m.canted;
    faces.face_z = glm::dvec3(m.face_z);
    faces.face_xy = glm::dvec3(m.face_xy);
    faces.face_phi = glm::dvec3(m.face_phi);
    f64::rp_average_faces(faces, a.face_z, a.face_xy, a.face_phi, a.phi_end);
    const std::vector<double> s = azimuth_series(a);
    series = std::make_shared<const std::vector<R>>(s.begin(), s.end());
    m.azimuth_series = series->data();
    return series;
}

template <class Real>
class PrismaticRetroreflector {
  public:
    using real = Real;
    using vec3 = typename core<Real>::vec3;
    using material = typename core<Real>::material;

    struct Lobes {
        vec3 surface{0};
        vec3 retro{0};
        vec3 diffuse{0};
        vec3 total() const { return surface + retro + diffuse; }
    };
    struct Eval {
        Lobes f;
        Real pdf = 0;
    };
    struct Sample {
        vec3 wo{0};
        Lobes f;
        Real pdf = 0;
        int lobe = -1; // RP_LOBE_SURFACE, RP_LOBE_RETRO or RP_LOBE_DIFFUSE
    };
    struct Albedo {
        vec3 surface{0};
        vec3 retro{0};
        vec3 diffuse{0};
        vec3 total() const { return surface + retro + diffuse; }
    };

    // How the node evaluates the azimuth averages the core would integrate at every evaluation
    // (canted prisms; uncoated prisms in the exact tier): Tabulated makes their series once
    // (attach_azimuth_series: 1-50 ms) for evaluations of ~100 ns; Integrated integrates at each
    // evaluation (0.3-5 us), for a node evaluated at a few hundred directions or fewer, such as
    // an R_A table's. Their values agree within 1e-6 relative.
    enum class Averages { Tabulated, Integrated };

    // Prepares the per-shading-point constants (sanitised parameters, F_dr, frame).
    explicit PrismaticRetroreflector(const Params& params = Params(),
                                     Averages averages = Averages::Tabulated);

    Eval eval(const vec3& wi, const vec3& wo) const;
    // f alone: eval() without the pdf, cheaper (no mixture weights), for light loops that do not
    // weight by the sampling pdf; the same values as eval().f.
    Lobes f(const vec3& wi, const vec3& wo) const;
    // The state of one incident direction (its lobes' widths and mixture weights, the ERA and,
    // with a prism pitch, the diffraction pattern of the prisms' apertures), made once for many
    // outgoing directions or samples: f, eval, pdf and sample from incident(wi) are those from
    // wi, bit for bit, at the cost of the lobes alone. For a receiver's aperture integrated
    // against one source (analysis/lidar.h), a shading point's light and BSDF samples (eval
    // and sample at one wi), or any loop with the incident direction fixed. A state belongs to
    // the node that made it (it holds that material's widths and pattern); pass it to no other.
    struct Incident {
        vec3 wi{0};                        // local frame
        typename core<Real>::incident s{}; // rp_incident_setup's
        bool valid = false;                // false: wi below the horizon or weight 0 (all 0)
    };
    Incident incident(const vec3& wi) const;
    Lobes f(const Incident& in, const vec3& wo) const;
    Eval eval(const Incident& in, const vec3& wo) const;
    Real pdf(const Incident& in, const vec3& wo) const;
    std::optional<Sample> sample(const Incident& in, const vec3& u) const;
    Real pdf(const vec3& wi, const vec3& wo) const;
    // u in [0, 1)^3: u.z chooses the lobe, u.x and u.y sample it.
    std::optional<Sample> sample(const vec3& wi, const vec3& u) const;
    // Surface and retro lobes by deterministic quadrature over each lobe's own sampling map
    // (grid x grid midpoints; times kAlbedoRingPoints angles on the ring of a retro lobe with
    // dihedral errors); the diffuse lobe in closed form.
    Albedo albedo(const vec3& wi, int grid = 128) const;
    static constexpr int kAlbedoRingPoints = 16;
    // Retroreflected fraction E and ERA A (geometry alone) of the mean refracted direction.
    Real retro_fraction(const vec3& wi) const;

    // The node at one wavelength in nm: every channel evaluated there (the `wavelength` input
    // set: the diffraction of prism_pitch and, with abbe_number, the sheet's index there).
    // Wavelengths are sanitised as that input is (clamped into [0, 2000] nm, NaN taking 0, the
    // colour channels). Without an Abbe number the result shares this node's material but for
    // lambda / pitch; with one it is prepared anew (the azimuth series of the new index from the
    // series cache, or made: 0.3-50 ms). Per-query forms below: a node made once per wavelength
    // is the cheap way to evaluate many directions at one wavelength.
    PrismaticRetroreflector at_wavelength(double wavelengthNm) const;
    Eval eval(const vec3& wi, const vec3& wo, double wavelengthNm) const;
    Lobes f(const vec3& wi, const vec3& wo, double wavelengthNm) const;
    Real pdf(const vec3& wi, const vec3& wo, double wavelengthNm) const;
    std::optional<Sample> sample(const vec3& wi, const vec3& u, double wavelengthNm) const;

    // The core's material; it may point to series the node owns (azimuth_series), so a copy is
    // valid while the node, or a copy of the node, lives.
    const material& core_material() const { return m_; }
    const Params& params() const { return params_; }
    // World (parameter frame) to local shading frame; returns false for a zero, tiny,
    // overflowing or non-finite direction.
    bool to_local(const vec3& w, vec3& local) const;
    vec3 to_world(const vec3& local) const;

  private:
    // wo in the local frame, true when the state is valid and wo above the horizon (what f, eval
    // and pdf from a state evaluate).
    bool outgoing(const Incident& in, const vec3& woWorld, vec3& wo) const;
    // The sample at local direction wo, its lobes' values, pdf and lobe, in the world frame.
    Sample sampled(const vec3& wo, const typename core<Real>::lobes& r, Real pdf, int lobe) const;
    vec3 diffraction_albedo(const vec3& wi, const typename core<Real>::incident& s, int grid) const;

    Params params_;
    Averages averages_ = Averages::Tabulated;
    material m_;
    vec3 n_, t_, b_;
    // The series m_.azimuth_series points to (shared by copies), or null.
    std::shared_ptr<const std::vector<Real>> azimuthSeries_;
};

extern template class PrismaticRetroreflector<float>;
extern template class PrismaticRetroreflector<double>;

// The core material (local-frame constants) for given sanitised parameters, in double;
// the float node rounds it.
f64::rp_material prepare_material(const Params& sanitized);

} // namespace retroprism
