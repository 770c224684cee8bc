// prismatic_retroreflector.cpp: parameter handling, material preparation and the closure
// wrapper around the math core (prism_core.inc).
#include "prismatic_retroreflector.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "quadrature.h"

namespace retroprism {

const std::vector<ParamInfo>& param_table() {
    static const std::vector<ParamInfo> table = {
#define RP_FLOAT(name, def, lo, hi, doc)                                                           \
    {#name, ParamType::Float, {def, 0, 0}, lo, hi, "", "", doc},
#define RP_COLOR(name, r, g, b, doc) {#name, ParamType::Color, {r, g, b}, 0.0, 1.0, "", "", doc},
#define RP_ENUM(name, def, values, doc)                                                            \
    {#name, ParamType::Enum, {def, 0, 0}, 0, 0, values, "", doc},
#define RP_VECTOR(name, x, y, z, geomprop, doc)                                                    \
    {#name, ParamType::Vector, {x, y, z}, -1.0, 1.0, "", geomprop, doc},
#define RP_BOOL(name, def, doc)                                                                    \
    {#name, ParamType::Bool, {def ? 1.0 : 0.0, 0, 0}, 0, 1, "", "", doc},
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
    };
    return table;
}

const ParamInfo* find_param(const std::string& name) {
    for (const ParamInfo& info : param_table())
        if (name == info.name) return &info;
    return nullptr;
}

const std::vector<FitInfo>& fit_table() {
    static const std::vector<FitInfo> table = {
#define RP_FLOAT(name, def, lo, hi, doc)
#define RP_COLOR(name, r, g, b, doc)
#define RP_ENUM(name, def, values, doc)
#define RP_VECTOR(name, x, y, z, geomprop, doc)
#define RP_BOOL(name, def, doc)
#define RP_FIT(name, lo, hi, scale) {find_param(#name), lo, hi, FitScale::scale},
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
#undef RP_FIT
    };
    return table;
}

namespace {

template <class T, class U>
T* if_same_type(U* field) {
    if constexpr (std::is_same_v<T, U>)
        return field;
    else
        return nullptr;
}

} // namespace

template <class T>
T* input_field(Params& p, const std::string& name) {
#define RP_FIELD(n)                                                                                \
    if (name == #n) return if_same_type<T>(&p.n);
#define RP_FLOAT(n, def, lo, hi, doc) RP_FIELD(n)
#define RP_COLOR(n, r, g, b, doc) RP_FIELD(n)
#define RP_ENUM(n, def, values, doc) RP_FIELD(n)
#define RP_VECTOR(n, x, y, z, geomprop, doc) RP_FIELD(n)
#define RP_BOOL(n, def, doc) RP_FIELD(n)
#include "prismatic_retroreflector_params.def"
#undef RP_FIELD
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
    return nullptr;
}
template double* input_field<double>(Params&, const std::string&);
template int* input_field<int>(Params&, const std::string&);
template bool* input_field<bool>(Params&, const std::string&);
template Vec3d* input_field<Vec3d>(Params&, const std::string&);

std::vector<std::string> enum_values(const ParamInfo& info) {
    std::vector<std::string> out;
    std::stringstream ss(info.enum_values);
    std::string item;
    while (std::getline(ss, item, ','))
        out.push_back(item);
    return out;
}

int enum_index(const ParamInfo& info, const std::string& value) {
    std::vector<std::string> values = enum_values(info);
    auto it = std::find(values.begin(), values.end(), value);
    return it == values.end() ? -1 : int(it - values.begin());
}

namespace {

double clamp_or_default(double v, double lo, double hi, double def) {
    return f64::rp_sanitize(v, lo, hi, def);
}

} // namespace

Params sanitize(const Params& in) {
    Params p = in;
    for (const ParamInfo& info : param_table()) {
        switch (info.type) {
        case ParamType::Float: {
            double& v = *input_field<double>(p, info.name);
            v = clamp_or_default(v, info.min_value, info.max_value, info.default_value[0]);
            break;
        }
        case ParamType::Color: {
            Color3& v = *input_field<Color3>(p, info.name);
            for (size_t c = 0; c < 3; ++c)
                v[c] = clamp_or_default(v[c], 0.0, 1.0, info.default_value[c]);
            break;
        }
        case ParamType::Enum: {
            int& v = *input_field<int>(p, info.name);
            if (v < 0 || v >= int(enum_values(info).size())) v = int(info.default_value[0]);
            break;
        }
        case ParamType::Vector: // the frame, below
        case ParamType::Bool:
            break;
        }
    }
    // The frame, as every backend makes it (rp_make_frame).
    f64::vec3 n, t, b;
    f64::rp_make_frame(f64::vec3(in.normal[0], in.normal[1], in.normal[2]),
                       f64::vec3(in.tangent[0], in.tangent[1], in.tangent[2]), n, t, b);
    p.normal = {n.x, n.y, n.z};
    p.tangent = {t.x, t.y, t.z};
    return p;
}

double fdr_external(double eta) {
    const double n = eta;
    if (!(n > 1.0)) return 0.0;
    if (n < 1.01) {
        // integral over u = cos^2 in [0, 1] of F(sqrt(u)), with u = v^2 to resolve grazing
        auto f = [&](double v) { return 2.0 * v * f64::rp_fresnel_dielectric(v, n); };
        return integrate_adaptive(f, 0.0, 1.0, 1e-14);
    }
    // Exact integral of the unpolarised Fresnel reflectance (verified against quadrature to
    // 2e-10 relative for eta in [1.01, 3] by tests/nodes/test_physics.cpp).
    const double n2 = n * n, n4 = n2 * n2;
    return 0.5 + (n - 1) * (3 * n + 1) / (6 * (n + 1) * (n + 1)) +
           f64::rp_fdr_log_weight(n) * std::log((n - 1) / (n + 1)) -
           2 * n2 * n * (n2 + 2 * n - 1) / ((n2 + 1) * (n4 - 1)) +
           8 * n4 * (n4 + 1) / ((n2 + 1) * (n4 - 1) * (n4 - 1)) * std::log(n);
}

double fdr_internal(double eta) {
    if (!(eta > 1.0)) return 0.0;
    return 1.0 - (1.0 - fdr_external(eta)) / (eta * eta);
}

namespace {

const f64::vec2 kVertex1 = f64::RP_ERA_V1;
const f64::vec2 kVertex2 = f64::RP_ERA_V2;
const f64::vec2 kVertex3 = f64::RP_ERA_V3;

} // namespace

double era_averaged_direct(double t) {
    return f64::rp_retro_fraction_averaged_exact(t, 1.0, false);
}

double metal_hits_averaged_direct(double t) {
    return f64::rp_metal_hits_paper_direct(t);
}

double retro_fraction_tir_averaged_direct(double t, double eta) {
    f64::rp_material m{};
    m.prism_reflection = f64::RP_PRISM_TIR;
    m.eta = eta;
    m.vertex1 = kVertex1;
    m.vertex2 = kVertex2;
    m.vertex3 = kVertex3;
    const int n = 2000000;
    const double period = 2.0 * f64::RP_PI / 3.0;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        double phi = (i + 0.5) / n * period;
        sum += f64::rp_retro_fraction_oriented(
            m, glm::normalize(f64::vec3(t * std::cos(phi), t * std::sin(phi), -1.0)));
    }
    return sum / n;
}

f64::rp_material prepare_material(const Params& p) {
    return f64::rp_prepare(
        p.weight, f64::vec3(p.diffuse_color[0], p.diffuse_color[1], p.diffuse_color[2]),
        f64::vec3(p.retro_color[0], p.retro_color[1], p.retro_color[2]), p.specular, p.roughness,
        p.ior, p.prism_reflection, p.metal_reflectance, p.era_mode, p.orientation, p.cant_angle,
        p.dihedral_error, p.dihedral_spread, p.prism_pitch, p.abbe_number, p.wavelength,
        p.retro_lobe, p.reciprocal ? 1 : 0, p.fidelity);
}

namespace {

template <class Real>
typename core<Real>::material round_material(const f64::rp_material& m);

template <>
f64::rp_material round_material<double>(const f64::rp_material& m) {
    return m;
}

template <>
f32::rp_material round_material<float>(const f64::rp_material& m) {
    f32::rp_material r{};
    r.weight = float(m.weight);
    r.specular = float(m.specular);
    r.retro_color = f32::vec3(m.retro_color);
    r.diffuse_color = f32::vec3(m.diffuse_color);
    r.alpha = float(m.alpha);
    r.eta = float(m.eta);
    r.inv_alpha = float(m.inv_alpha);
    r.inv_alpha2 = float(m.inv_alpha2);
    r.inv_eta = float(m.inv_eta);
    r.eta2m1 = float(m.eta2m1);
    r.inv_spread = float(m.inv_spread);
    r.prism_reflection = m.prism_reflection;
    r.metal_r = float(m.metal_r);
    r.metal_r3 = float(m.metal_r3);
    r.era_mode = m.era_mode;
    r.vertex1 = f32::vec2(m.vertex1);
    r.vertex2 = f32::vec2(m.vertex2);
    r.vertex3 = f32::vec2(m.vertex3);
    r.canted = m.canted;
    r.face1 = f32::vec3(m.face1);
    r.face2 = f32::vec3(m.face2);
    r.face3 = f32::vec3(m.face3);
    r.face_z = f32::vec3(m.face_z);
    r.face_xy = f32::vec3(m.face_xy);
    r.face_phi = f32::vec3(m.face_phi);
    r.dihedral = m.dihedral;
    r.ring_par = float(m.ring_par);
    r.ring_tilt = float(m.ring_tilt);
    r.spread2 = float(m.spread2);
    r.diffraction = m.diffraction;
    r.diff_scale = f32::vec3(m.diff_scale);
    r.diff_coherence = f32::vec2(m.diff_coherence);
    r.ap_e1 = f32::vec3(m.ap_e1);
    r.ap_e2 = f32::vec3(m.ap_e2);
    r.ap_e3 = f32::vec3(m.ap_e3);
    r.ap_v1 = f32::vec2(m.ap_v1);
    r.ap_v2 = f32::vec2(m.ap_v2);
    r.ap_v3 = f32::vec2(m.ap_v3);
    r.ap_edge = f32::vec3(m.ap_edge);
    r.ap_period = float(m.ap_period);
    r.ap_rot = float(m.ap_rot);
    r.retro_anisotropic = m.retro_anisotropic;
    r.reciprocal = m.reciprocal;
    r.fidelity = m.fidelity;
    r.diffuse_scale = f32::vec3(m.diffuse_scale);
    r.diffuse_albedo = f32::vec3(m.diffuse_albedo);
    return r;
}

// The core's diffraction terms (prism_core.inc) for either precision.
int diffraction_terms(const f32::rp_material& m) {
    return f32::rp_diffraction_terms(m);
}
int diffraction_terms(const f64::rp_material& m) {
    return f64::rp_diffraction_terms(m);
}
f32::vec4 diffraction_term_of(const f32::rp_material& m, const f32::rp_incident& s, int j) {
    return f32::rp_diffraction_term_of(m, s, j);
}
f64::vec4 diffraction_term_of(const f64::rp_material& m, const f64::rp_incident& s, int j) {
    return f64::rp_diffraction_term_of(m, s, j);
}
// A direction of one term (variances var along and across the plane of incidence; its donut
// when `donut`, rp_diffraction_term_of) for either precision.
f32::vec3 diffraction_sample_term(const f32::rp_incident& s, f32::vec3 wi, f32::vec2 var, float u1,
                                  float u2, float u3, bool donut) {
    return donut ? f32::rp_diffraction_sample_donut(s, wi, var.x, u1, u2, u3)
                 : f32::rp_diffraction_sample_term(s, wi, var, u1, u2, u3);
}
f64::vec3 diffraction_sample_term(const f64::rp_incident& s, f64::vec3 wi, f64::vec2 var, double u1,
                                  double u2, double u3, bool donut) {
    return donut ? f64::rp_diffraction_sample_donut(s, wi, var.x, u1, u2, u3)
                 : f64::rp_diffraction_sample_term(s, wi, var, u1, u2, u3);
}

template <class V>
V from_array(const Vec3d& a) {
    using R = typename V::value_type;
    return V(R(a[0]), R(a[1]), R(a[2]));
}

} // namespace

template <class Real>
PrismaticRetroreflector<Real>::PrismaticRetroreflector(const Params& params, Averages averages)
    : params_(sanitize(params)), averages_(averages),
      m_(round_material<Real>(prepare_material(params_))) {
    if (averages == Averages::Tabulated) azimuthSeries_ = attach_azimuth_series(m_);
    n_ = from_array<vec3>(params_.normal);
    t_ = from_array<vec3>(params_.tangent);
    b_ = glm::cross(n_, t_);
}

template <class Real>
bool PrismaticRetroreflector<Real>::to_local(const vec3& w, vec3& local) const {
    return core<Real>::to_local(n_, t_, b_, w, local);
}

template <class Real>
typename PrismaticRetroreflector<Real>::vec3
PrismaticRetroreflector<Real>::to_world(const vec3& l) const {
    return l.x * t_ + l.y * b_ + l.z * n_;
}

template <class Real>
typename PrismaticRetroreflector<Real>::Eval
PrismaticRetroreflector<Real>::eval(const vec3& wiWorld, const vec3& woWorld) const {
    Eval out;
    vec3 wi, wo;
    typename core<Real>::lobes r;
    if (to_local(wiWorld, wi) && to_local(woWorld, wo) && core<Real>::eval(m_, wi, wo, r, out.pdf))
        out.f = {r.surface, r.retro, r.diffuse};
    return out;
}

template <class Real>
typename PrismaticRetroreflector<Real>::Lobes
PrismaticRetroreflector<Real>::f(const vec3& wiWorld, const vec3& woWorld) const {
    vec3 wi, wo;
    typename core<Real>::lobes r;
    if (to_local(wiWorld, wi) && to_local(woWorld, wo) && core<Real>::eval_f(m_, wi, wo, r))
        return {r.surface, r.retro, r.diffuse};
    return Lobes();
}

template <class Real>
typename PrismaticRetroreflector<Real>::Incident
PrismaticRetroreflector<Real>::incident(const vec3& wiWorld) const {
    Incident in;
    // The entry points' condition on wi and the weight; wo's is checked per direction (outgoing).
    if (!to_local(wiWorld, in.wi) || !core<Real>::reflects(m_, in.wi)) return in;
    core<Real>::setup(m_, in.wi, in.s);
    in.valid = true;
    return in;
}

template <class Real>
bool PrismaticRetroreflector<Real>::outgoing(const Incident& in, const vec3& woWorld,
                                             vec3& wo) const {
    return in.valid && to_local(woWorld, wo) && wo.z >= Real(f64::RP_MIN_COS);
}

template <class Real>
typename PrismaticRetroreflector<Real>::Lobes
PrismaticRetroreflector<Real>::f(const Incident& in, const vec3& woWorld) const {
    vec3 wo;
    if (!outgoing(in, woWorld, wo)) return Lobes();
    typename core<Real>::lobes r;
    core<Real>::eval_lobes(m_, in.s, in.wi, wo, r);
    return {r.surface, r.retro, r.diffuse};
}

template <class Real>
Real PrismaticRetroreflector<Real>::pdf(const vec3& wi, const vec3& wo) const {
    return eval(wi, wo).pdf;
}

template <class Real>
typename PrismaticRetroreflector<Real>::Eval
PrismaticRetroreflector<Real>::eval(const Incident& in, const vec3& woWorld) const {
    vec3 wo;
    Eval e;
    if (!outgoing(in, woWorld, wo)) return e;
    typename core<Real>::lobes r;
    core<Real>::eval_lobes_pdf(m_, in.s, in.wi, wo, r, e.pdf);
    e.f = {r.surface, r.retro, r.diffuse};
    return e;
}

template <class Real>
Real PrismaticRetroreflector<Real>::pdf(const Incident& in, const vec3& wo) const {
    return eval(in, wo).pdf;
}

template <class Real>
std::optional<typename PrismaticRetroreflector<Real>::Sample>
PrismaticRetroreflector<Real>::sample(const vec3& wiWorld, const vec3& u) const {
    vec3 wi;
    if (!to_local(wiWorld, wi)) return std::nullopt;
    vec3 wo;
    typename core<Real>::lobes r;
    Real pdf = 0;
    int lobe = -1;
    if (!core<Real>::sample(m_, wi, u, wo, r, pdf, lobe)) return std::nullopt;
    return sampled(wo, r, pdf, lobe);
}

template <class Real>
std::optional<typename PrismaticRetroreflector<Real>::Sample>
PrismaticRetroreflector<Real>::sample(const Incident& in, const vec3& u) const {
    if (!in.valid) return std::nullopt;
    vec3 wo;
    typename core<Real>::lobes r;
    Real pdf = 0;
    int lobe = -1;
    if (!core<Real>::sample_incident(m_, in.s, in.wi, u, wo, r, pdf, lobe)) return std::nullopt;
    return sampled(wo, r, pdf, lobe);
}

template <class Real>
typename PrismaticRetroreflector<Real>::Sample
PrismaticRetroreflector<Real>::sampled(const vec3& wo, const typename core<Real>::lobes& r,
                                       Real pdf, int lobe) const {
    Sample s;
    s.wo = to_world(wo);
    s.f.surface = r.surface;
    s.f.retro = r.retro;
    s.f.diffuse = r.diffuse;
    s.pdf = pdf;
    s.lobe = lobe;
    return s;
}

template <class Real>
PrismaticRetroreflector<Real> PrismaticRetroreflector<Real>::at_wavelength(double nm) const {
    Params p = params_;
    p.wavelength = nm;
    p = sanitize(p);
    if (p.abbe_number > 0.0 && p.wavelength != params_.wavelength)
        return PrismaticRetroreflector(p, averages_);
    // The index does not move: only lambda / pitch of each channel (rp_prepare_diffraction).
    PrismaticRetroreflector out = *this;
    out.params_ = p;
    if (m_.diffraction != 0) {
        const f64::rp_material d = prepare_material(p);
        out.m_.diff_scale = vec3(d.diff_scale);
    }
    return out;
}

template <class Real>
typename PrismaticRetroreflector<Real>::Eval
PrismaticRetroreflector<Real>::eval(const vec3& wi, const vec3& wo, double wavelengthNm) const {
    return at_wavelength(wavelengthNm).eval(wi, wo);
}

template <class Real>
typename PrismaticRetroreflector<Real>::Lobes
PrismaticRetroreflector<Real>::f(const vec3& wi, const vec3& wo, double wavelengthNm) const {
    return at_wavelength(wavelengthNm).f(wi, wo);
}

template <class Real>
Real PrismaticRetroreflector<Real>::pdf(const vec3& wi, const vec3& wo, double wavelengthNm) const {
    return at_wavelength(wavelengthNm).pdf(wi, wo);
}

template <class Real>
std::optional<typename PrismaticRetroreflector<Real>::Sample>
PrismaticRetroreflector<Real>::sample(const vec3& wi, const vec3& u, double wavelengthNm) const {
    return at_wavelength(wavelengthNm).sample(wi, u);
}

template <class Real>
Real PrismaticRetroreflector<Real>::retro_fraction(const vec3& wiWorld) const {
    vec3 wi;
    if (!to_local(wiWorld, wi) || !(wi.z >= Real(f64::RP_MIN_COS))) return 0;
    typename core<Real>::incident s;
    core<Real>::setup(m_, wi, s);
    return s.era;
}

template <class Real>
typename PrismaticRetroreflector<Real>::Albedo
PrismaticRetroreflector<Real>::albedo(const vec3& wiWorld, int grid) const {
    Albedo out;
    vec3 wi;
    if (!to_local(wiWorld, wi) || !core<Real>::reflects(m_, wi)) return out;
    typename core<Real>::incident s;
    core<Real>::setup(m_, wi, s);
    // Diffuse, exactly: T_i (1 - E) k_d (1 - F_dr_ext) / (eta^2 (1 - k_d F_dr)).
    out.diffuse = m_.diffuse_albedo * (m_.weight * s.transI * s.passed);
    // Surface and retro: E[f_k cos_o / pdf_k] over each lobe's sampling map, on a midpoint grid
    // (the map covers the lobe's whole mass; directions below the horizon contribute 0).
    const bool lobeOn[2] = {
        m_.specular > 0,
        s.era > 0 && (m_.retro_color.x > 0 || m_.retro_color.y > 0 || m_.retro_color.z > 0)};
    for (int lobe = 0; lobe < 2; ++lobe) {
        if (!lobeOn[lobe]) continue;
        // The retro lobe with dihedral errors samples a third number, the angle on its ring of
        // spots: a periodic integrand, which the midpoint rule in it integrates to spectral
        // accuracy with few points.
        const int rings = lobe == 1 && s.ringRadius > 0 ? kAlbedoRingPoints : 1;
        double sum[3] = {0, 0, 0};
        for (int k = 0; k < rings; ++k) {
            const Real u3 = (Real(k) + Real(0.5)) / Real(rings);
            for (int i = 0; i < grid; ++i) {
                for (int j = 0; j < grid; ++j) {
                    Real u1 = (Real(i) + Real(0.5)) / Real(grid);
                    Real u2 = (Real(j) + Real(0.5)) / Real(grid);
                    vec3 wo = core<Real>::lobe_sample(m_, s, wi, lobe, u1, u2, u3);
                    if (!(wo.z >= Real(f64::RP_MIN_COS))) continue;
                    Real pdf = core<Real>::lobe_pdf(m_, s, wi, wo, lobe);
                    if (!(pdf > 0)) continue;
                    typename core<Real>::lobes r;
                    core<Real>::eval_lobes(m_, s, wi, wo, r);
                    vec3 f = lobe == 0 ? r.surface : r.retro;
                    for (int c = 0; c < 3; ++c)
                        sum[c] += double(f[c] * wo.z / pdf);
                }
            }
        }
        vec3 a = vec3(Real(sum[0]), Real(sum[1]), Real(sum[2]));
        a /= Real(grid * grid) * Real(rings);
        if (lobe == 0)
            out.surface = a;
        else
            out.retro = a;
    }
    if (lobeOn[1] && m_.diffraction != 0) out.retro = diffraction_albedo(wi, s, grid);
    return out;
}

// The retro lobe's albedo with diffraction: the same estimator over the lobe's sampling map with
// the map's discrete choices (channel, term of the pattern) summed with their probabilities
// instead of drawn: each term's Gaussian on a midpoint grid of about its share of grid^2 points
// (at least one: side ceil(sqrt(weight grid^2))), and its ring (dihedral errors), or the donut's
// component and radius (its third variate), at kAlbedoRingPoints / 4 values, so that the work is
// about that of the geometric lobe's.
template <class Real>
typename PrismaticRetroreflector<Real>::vec3 PrismaticRetroreflector<Real>::diffraction_albedo(
    const vec3& wi, const typename core<Real>::incident& s, int grid) const {
    const bool grey = m_.diff_scale.x == m_.diff_scale.y && m_.diff_scale.y == m_.diff_scale.z;
    const int channels = grey ? 1 : 3;
    const bool ringed = s.ringPar2 + s.ringPerp2 > 0;
    const int terms = diffraction_terms(m_);
    double sum[3] = {0, 0, 0};
    for (int ch = 0; ch < channels; ++ch) {
        const Real scale = m_.diff_scale[ch];
        for (int t = 0; t < terms; ++t) {
            const auto term = diffraction_term_of(m_, s, t);
            if (!(term.x > 0)) continue;
            const bool donut = term.w > 0;
            const int rings = ringed || donut ? kAlbedoRingPoints / 4 : 1;
            const int side =
                std::max(1, int(std::ceil(std::sqrt(double(term.x) * double(grid) * grid))));
            const double weight = double(term.x) / (double(channels) * side * side * rings);
            for (int k = 0; k < rings; ++k)
                for (int i = 0; i < side; ++i)
                    for (int j = 0; j < side; ++j) {
                        const glm::vec<2, Real> var =
                            glm::vec<2, Real>(term.y, term.z) * (scale * scale);
                        const Real u1 = (Real(i) + Real(0.5)) / Real(side);
                        const Real u2 = (Real(j) + Real(0.5)) / Real(side);
                        const Real u3 = (Real(k) + Real(0.5)) / Real(rings);
                        const vec3 wo = diffraction_sample_term(s, wi, var, u1, u2, u3, donut);
                        if (!(wo.z >= Real(f64::RP_MIN_COS))) continue;
                        const Real pdf = core<Real>::lobe_pdf(m_, s, wi, wo, 1);
                        if (!(pdf > 0)) continue;
                        typename core<Real>::lobes r;
                        core<Real>::eval_lobes(m_, s, wi, wo, r);
                        for (int c = 0; c < 3; ++c)
                            sum[c] += weight * double(r.retro[c] * wo.z / pdf);
                    }
        }
    }
    return vec3(Real(sum[0]), Real(sum[1]), Real(sum[2]));
}

double era(double thetaT, double phi, int eraMode, double cantDeg) {
    Params p;
    p.era_mode = eraMode;
    p.cant_angle = cantDeg;
    f64::rp_material m = prepare_material(sanitize(p));
    m.prism_reflection = f64::RP_PRISM_IDEAL; // geometry alone
    const f64::vec3 d(std::sin(thetaT) * std::cos(phi), std::sin(thetaT) * std::sin(phi),
                      -std::cos(thetaT));
    return f64::rp_retro_fraction(m, d);
}

template class PrismaticRetroreflector<float>;
template class PrismaticRetroreflector<double>;

} // namespace retroprism
