// [stability]: the node at the extremes of its inputs. Never NaN, Inf or a negative value;
// invalid parameters clamped as documented; float agrees with double.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <limits>

#include "test_support.h"

using namespace retroprism;
using rptest::dir_deg;
using rptest::dvec3;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// A direction at the given cosine of theta (may be 0 or negative) and azimuth (degrees).
dvec3 dir_cos(double cosTheta, double phiDeg) {
    double c = std::max(-1.0, std::min(1.0, cosTheta));
    double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    double p = phiDeg * M_PI / 180.0;
    return dvec3(s * std::cos(p), s * std::sin(p), c);
}

dvec3 mirror(const dvec3& w) {
    return dvec3(-w.x, -w.y, w.z);
}

// The same direction as float, and that float direction promoted back to double, so that
// both nodes see identical inputs.
glm::vec3 to_float(const dvec3& w) {
    return glm::vec3(w);
}

// The extreme directions of the sweep for one incident direction wi: itself, its mirror, the
// normal, grazing and below-horizon ones, and a ring around wi and the mirror direction.
std::vector<dvec3> outgoing_set(const dvec3& wi) {
    std::vector<dvec3> out = {wi, mirror(wi), dvec3(0, 0, 1)};
    for (double c : {1.0, 1e-7, 0.0, -1e-7, 1e-3, 0.5})
        for (double phi : {0.0, 90.0, 180.0})
            out.push_back(dir_cos(c, phi));
    for (double offset : {1e-6, 1e-4, 1e-3, 1e-2, 0.1})
        for (double phi : {0.0, 120.0, 240.0}) {
            dvec3 d(offset * std::cos(phi * M_PI / 180), offset * std::sin(phi * M_PI / 180), 0);
            out.push_back(glm::normalize(wi + d));
            out.push_back(glm::normalize(mirror(wi) + d));
        }
    return out;
}

std::vector<dvec3> incident_set() {
    std::vector<dvec3> out;
    for (double c : {1.0, 0.9, 0.5, 0.1, 1e-3, 1e-7, 0.0, -1e-7})
        for (double phi : {0.0, 45.0})
            out.push_back(dir_cos(c, phi));
    return out;
}

bool ok_value(double v) {
    return std::isfinite(v) && v >= 0.0;
}

template <class V>
bool ok_rgb(const V& v) {
    return ok_value(double(v.x)) && ok_value(double(v.y)) && ok_value(double(v.z));
}

struct Counts {
    long cases = 0;
    long bad = 0; // NaN, Inf or negative
};

// Evaluates, samples and asks the pdf of one node at every pair; counts bad values.
template <class Real>
void sweep_node(const Params& p, Counts& counts) {
    using Node = PrismaticRetroreflector<Real>;
    using vec3 = typename Node::vec3;
    Node node(p);
    rptest::Rng rng(7);
    for (const dvec3& wiD : incident_set()) {
        vec3 wi(wiD);
        for (const dvec3& woD : outgoing_set(wiD)) {
            vec3 wo(woD);
            typename Node::Eval e = node.eval(wi, wo);
            counts.cases += 1;
            if (!ok_rgb(e.f.surface) || !ok_rgb(e.f.retro) || !ok_rgb(e.f.diffuse) ||
                !ok_value(double(e.pdf))) {
                counts.bad += 1;
                UNSCOPED_INFO("bad eval: wi " << wiD.x << "," << wiD.y << "," << wiD.z << " wo "
                                              << woD.x << "," << woD.y << "," << woD.z);
            }
        }
        for (int i = 0; i < 16; ++i) {
            vec3 u(Real(rng.uniform()), Real(rng.uniform()), Real(rng.uniform()));
            if (i == 0) u = vec3(0);
            if (i == 1) u = vec3(Real(1) - std::numeric_limits<Real>::epsilon());
            if (i == 2) u = vec3(1);
            auto s = node.sample(wi, u);
            counts.cases += 1;
            if (s && (!ok_rgb(s->f.surface) || !ok_rgb(s->f.retro) || !ok_rgb(s->f.diffuse) ||
                      !(s->pdf > 0) || !std::isfinite(double(s->pdf)) ||
                      !std::isfinite(double(s->wo.x + s->wo.y + s->wo.z)))) {
                counts.bad += 1;
                UNSCOPED_INFO("bad sample at wi " << wiD.x << "," << wiD.y << "," << wiD.z);
            }
        }
    }
}

std::vector<Params> extreme_materials() {
    std::vector<Params> out;
    for (double roughness : {1e-6, 1e-5, 1e-4, 1e-3, 0.005, 0.05, 0.3, 1.0, 1.5, 10.0, -1.0, kNaN})
        for (double ior : {1.0, 1.0001, 1.001, 1.01, 1.1, 1.49, 2.0, 3.0, 5.0, 0.5, kInf})
            for (int prism : {0, 1, 2}) {
                Params p;
                p.roughness = roughness;
                p.ior = ior;
                p.prism_reflection = prism;
                p.era_mode = (prism + int(ior * 7)) % 3;
                p.retro_lobe = prism % 2;
                p.fidelity = (prism + int(ior * 3)) % 2;
                p.reciprocal = (prism + int(roughness * 1e4)) % 2 == 1;
                p.orientation = 33.0;
                out.push_back(p);
            }
    // Colours and weights at and beyond their ends, NaN/Inf parameters, degenerate frames.
    const double colours[] = {0.0, 1.0, -0.5, 2.0, kNaN, kInf};
    for (double c : colours) {
        Params p;
        p.diffuse_color = {c, 1.0, 0.0};
        p.retro_color = {0.0, c, 1.0};
        p.specular = c;
        p.weight = c;
        p.metal_reflectance = c;
        p.prism_reflection = 2;
        out.push_back(p);
    }
    Params frame;
    frame.normal = {0, 0, 0};
    frame.tangent = {0, 0, 1};
    out.push_back(frame);
    frame.normal = {kNaN, 1, 0};
    frame.tangent = {kInf, 0, 0};
    frame.era_mode = 2;
    out.push_back(frame);
    frame.normal = {0, 0, -1};
    frame.tangent = {0, 0, 5};
    out.push_back(frame);
    Params badEnum;
    badEnum.prism_reflection = 7;
    badEnum.era_mode = -3;
    out.push_back(badEnum);
    return out;
}

} // namespace

TEST_CASE("No NaN, Inf or negative value at the extremes, float and double", "[stability]") {
    Counts counts;
    const std::vector<Params> materials = extreme_materials();
    for (const Params& p : materials) {
        sweep_node<double>(p, counts);
        sweep_node<float>(p, counts);
    }
    std::printf("MEASURED: stability sweep: %zu materials, %ld eval/sample cases (float and "
                "double), %ld with NaN, Inf or a negative value\n",
                materials.size(), counts.cases, counts.bad);
    CHECK(counts.cases > 100000);
    CHECK(counts.bad == 0);
}

TEST_CASE("Non-finite and zero directions give zero, never NaN", "[stability]") {
    PrismaticRetroreflector<double> node;
    const dvec3 good = dir_deg(30, 0);
    const dvec3 bad[] = {dvec3(kNaN, 0, 1), dvec3(0, kInf, 1), dvec3(0, 0, 0), dvec3(0, 0, -kInf),
                         dvec3(1e-300, 0, 1e-300)};
    for (const dvec3& b : bad) {
        for (int k = 0; k < 2; ++k) {
            auto e = k == 0 ? node.eval(b, good) : node.eval(good, b);
            CHECK(e.f.total() == dvec3(0));
            CHECK(e.pdf == 0);
        }
        CHECK_FALSE(node.sample(b, dvec3(0.3, 0.4, 0.5)));
        CHECK(node.albedo(b, 8).total() == dvec3(0));
    }
    // NaN random numbers are clamped away, never propagated.
    auto s = node.sample(good, dvec3(kNaN, kNaN, kNaN));
    if (s) CHECK(ok_rgb(s->f.total()));
}

TEST_CASE("Invalid parameters are clamped into their documented ranges", "[stability]") {
    for (const ParamInfo& info : param_table()) {
        if (info.type != ParamType::Float) continue;
        INFO(info.name);
        // Each float parameter below, above and NaN.
        auto with = [&](double v) {
            Params p;
            *input_field<double>(p, info.name) = v;
            return sanitize(p);
        };
        auto get = [&](const Params& p) { return *input_field<double>(p, info.name); };
        CHECK(get(with(info.min_value - 10.0)) == info.min_value);
        CHECK(get(with(info.max_value + 10.0)) == info.max_value);
        CHECK(get(with(-kInf)) == info.min_value);
        CHECK(get(with(kInf)) == info.max_value);
        CHECK(get(with(kNaN)) == info.default_value[0]);
        const double mid = 0.5 * (info.min_value + info.max_value);
        CHECK(get(with(mid)) == mid);
    }
    Params p;
    p.diffuse_color = {-1.0, 2.0, kNaN};
    p.prism_reflection = 9;
    p.normal = {0, 0, 0};
    p.tangent = {0, 0, 3};
    Params s = sanitize(p);
    CHECK(s.diffuse_color[0] == 0.0);
    CHECK(s.diffuse_color[1] == 1.0);
    CHECK(s.diffuse_color[2] == Params().diffuse_color[2]);
    CHECK(s.prism_reflection == Params().prism_reflection);
    CHECK(s.normal == Vec3d{0, 0, 1});
    // A tangent parallel to the normal is replaced by a unit one orthogonal to it.
    const Vec3d& t = s.tangent;
    CHECK(std::abs(t[0] * t[0] + t[1] * t[1] + t[2] * t[2] - 1.0) < 1e-12);
    CHECK(std::abs(t[2]) < 1e-12);
}

TEST_CASE("Roughness below the floor evaluates as the floor; the eta = 1 sheet", "[stability]") {
    // Roughness 0 and 1e-6 both mean the delta limit, evaluated at RP_MIN_ALPHA (1e-4).
    Params a, b;
    a.roughness = 0.0;
    b.roughness = 1e-6;
    PrismaticRetroreflector<double> na(a), nb(b);
    const dvec3 wi = dir_deg(30, 0);
    for (double off : {0.0, 5e-5, 2e-4}) {
        dvec3 wo = glm::normalize(wi + dvec3(0, off, 0));
        CHECK(na.eval(wi, wo).f.retro == nb.eval(wi, wo).f.retro);
        dvec3 wm = glm::normalize(mirror(wi) + dvec3(0, off, 0));
        CHECK(na.eval(wi, wm).f.surface == nb.eval(wi, wm).f.surface);
    }
    // At eta = 1 there is no interface: no surface reflection, full transmission.
    Params one;
    one.ior = 1.0;
    PrismaticRetroreflector<double> n1(one);
    CHECK(n1.eval(wi, mirror(wi)).f.surface == dvec3(0));
    CHECK(n1.eval(wi, wi).f.retro.x > 0);
}

TEST_CASE("float agrees with double to 1e-4 above 1e-6 of each lobe's peak", "[stability]") {
    // A lobe's peak is its largest value for the material over the incident directions: where
    // a lobe has all but vanished (uncoated prisms beyond their cut-off, E ~ 1e-10), its values
    // are below a millionth of it and do not show.
    // Inputs are float directions and float-representable parameters given to both nodes, so
    // what is compared is the arithmetic: a float direction's own rounding (6e-8) would move
    // the tails of an alpha = 1e-4 lobe by ~1e-3, and rounding ior = 1.0001 to float changes
    // eta - 1, which every Fresnel term near eta = 1 scales with, by 6e-4; that is the
    // inputs' uncertainty, not the node's error.
    auto f = [](double v) { return double(float(v)); };
    double worst = 0.0;
    std::string worstWhere;
    long compared = 0;
    for (double roughness : {1e-4, 1e-3, 0.005, 0.05, 0.3, 1.0})
        for (double ior : {1.0001, 1.1, 1.49, 1.586, 3.0})
            for (int prism : {0, 1, 2})
                for (int era : {0, 1, 2}) {
                    Params p;
                    p.roughness = f(roughness);
                    p.ior = f(ior);
                    p.prism_reflection = prism;
                    p.era_mode = era;
                    p.orientation = 20.0;
                    p.diffuse_color = {f(0.9), f(0.5), f(0.1)};
                    p.retro_lobe = era % 2;
                    p.fidelity = (era + prism) % 2;
                    p.reciprocal = prism == 1;
                    p.retro_color = {1.0, f(0.8), f(0.2)};
                    p.metal_reflectance = f(p.metal_reflectance);
                    PrismaticRetroreflector<double> nd(p);
                    PrismaticRetroreflector<float> nf(p);
                    const double thetas[] = {0.0, 10.0, 30.0, 60.0, 80.0, 89.0, 89.99};
                    // Each lobe's peak for the material, in double, over the incident directions:
                    // retro at wi, surface at the mirror direction, diffuse at the normal.
                    dvec3 peaks(0.0);
                    for (double thetaI : thetas) {
                        const dvec3 wi(to_float(dir_deg(thetaI, 10.0)));
                        peaks = glm::max(peaks, dvec3(nd.eval(wi, mirror(wi)).f.surface.x,
                                                      nd.eval(wi, wi).f.retro.x,
                                                      nd.eval(wi, dvec3(0, 0, 1)).f.diffuse.x));
                    }
                    for (double thetaI : thetas) {
                        const glm::vec3 wiF = to_float(dir_deg(thetaI, 10.0));
                        const dvec3 wi(wiF);
                        // Directions: around the two peaks on the lobe's own scale and a grid.
                        std::vector<glm::vec3> wos;
                        for (int i = 0; i < 24; ++i) {
                            double r = roughness * 0.4 * i, phi = 0.7 * i;
                            dvec3 d(r * std::cos(phi), r * std::sin(phi), 0);
                            wos.push_back(to_float(glm::normalize(wi + d)));
                            wos.push_back(to_float(glm::normalize(mirror(wi) + d)));
                        }
                        for (double t : {0.0, 20.0, 45.0, 70.0, 85.0, 89.9})
                            for (double phi : {0.0, 100.0, 190.0})
                                wos.push_back(to_float(dir_deg(t, phi)));
                        for (const glm::vec3& woF : wos) {
                            const dvec3 wo(woF);
                            auto ed = nd.eval(wi, wo);
                            auto ef = nf.eval(wiF, woF);
                            const dvec3 lobesD[3] = {ed.f.surface, ed.f.retro, ed.f.diffuse};
                            const glm::vec3 lobesF[3] = {ef.f.surface, ef.f.retro, ef.f.diffuse};
                            for (int k = 0; k < 3; ++k)
                                for (int c = 0; c < 3; ++c) {
                                    double d = lobesD[k][c], v = double(lobesF[k][c]);
                                    if (!(d > 1e-6 * peaks[k])) continue;
                                    double rel = std::abs(v - d) / d;
                                    compared += 1;
                                    if (rel > worst) {
                                        worst = rel;
                                        char buf[256];
                                        std::snprintf(buf, sizeof buf,
                                                      "lobe %d roughness %g ior %g prism %d era "
                                                      "%d theta_i %g value %.6g",
                                                      k, roughness, ior, prism, era, thetaI, d);
                                        worstWhere = buf;
                                    }
                                }
                        }
                    }
                }
    std::printf("MEASURED: float vs double: %ld lobe values above 1e-6 of their peak compared, "
                "worst relative difference %.3g (%s)\n",
                compared, worst, worstWhere.c_str());
    INFO(worstWhere);
    CHECK(compared > 50000);
    CHECK(worst <= 1e-4);
}
