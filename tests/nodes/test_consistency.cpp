// [consistency]: sample(), eval() and pdf() of the node agree with one another, in float and
// in double, at every parameter corner (rptest::parameter_corners()) and for many incident
// directions, grazing ones included (theta_i up to 89.9 degrees):
//  - a non-empty sample's lobes f and pdf are the node's eval(wi, wo).f and pdf(wi, wo);
//  - its wo is unit and above the horizon, its pdf positive and finite, its f finite and
//    non-negative, its lobe index valid with a non-zero value of that lobe, and the
//    estimator weight f cos(theta_o) / pdf finite;
//  - pdf(wi, wo) is eval(wi, wo).pdf;
//  - a wi below the horizon gives an empty sample and a zero eval.
//
// Why a tolerance at all: sample() and eval() run the same core code (rp_eval_lobes and
// rp_pdf_mixture of nodes/prism_core.inc) on the same local directions, so on this platform
// they agree bit for bit (the MEASURED lines below say so). The tolerance only leaves room
// for a compiler that contracts a * b + c into a fused multiply-add differently in the two
// inlined copies: one rounding, amplified by the sharpest lobe's exponent.
//  - double: relative 1e-12; float: relative 1e-5 (the figures).
// One more difference is not the code's: eval() renormalises its argument (to_local), and a
// sampled wo is unit only to a few roundings (kUnitUlps below), so where its computed length
// is not exactly 1 eval() sees a direction moved by a few ulp, which a lobe 1e-4 wide (the
// roughness floor) turns into a relative change of up to ~1e-2 in float. Where that happens
// the test checks eval() against the core at the renormalised direction instead (the same
// code on the same input) and that the renormalisation moved wo by no more than wo's distance
// from unit length allows, and reports the size of the difference.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"

namespace {

using retroprism::core;
using retroprism::Params;
using retroprism::PrismaticRetroreflector;

template <class Real>
struct Tol;
template <>
struct Tol<double> {
    static constexpr double rel = 1e-12;
    static constexpr const char* name = "double";
};
template <>
struct Tol<float> {
    static constexpr double rel = 1e-5;
    static constexpr const char* name = "float";
};

// The core's Fresnel reflectance in the node's precision.
float fresnel(float c, float eta) {
    return retroprism::f32::rp_fresnel_dielectric(c, eta);
}
double fresnel(double c, double eta) {
    return retroprism::f64::rp_fresnel_dielectric(c, eta);
}

// A sampled wo is unit to this many ulp: the surface lobe reflects wi about a normalised
// microfacet normal m, wo = 2 (wi.m) m - wi, whose squared length is 1 + 4 (wi.m)^2 (|m|^2 - 1)
// + (|wi|^2 - 1) plus the reflection's own roundings, so the errors of the two normalisations
// add up (4.5 ulp measured in double and in float).
constexpr double kUnitUlps = 16.0;

double rel_diff(double a, double b) {
    const double m = std::max(std::abs(a), std::abs(b));
    return m > 0 ? std::abs(a - b) / m : 0.0;
}

template <class Lobes>
double max_rel_diff(const Lobes& a, const Lobes& b) {
    double r = 0;
    for (int c = 0; c < 3; ++c) {
        r = std::max(r, rel_diff(a.surface[c], b.surface[c]));
        r = std::max(r, rel_diff(a.retro[c], b.retro[c]));
        r = std::max(r, rel_diff(a.diffuse[c], b.diffuse[c]));
    }
    return r;
}

// The incident directions of one corner: fixed polar angles up to 89.9 degrees, then random
// ones, half uniform in cos(theta) and half in theta within [80, 89.9] degrees (grazing).
std::vector<glm::dvec3> incident_directions(rptest::Rng& rng) {
    std::vector<glm::dvec3> out;
    for (double theta : {0.0, 1e-3, 10.0, 30.0, 45.0, 60.0, 75.0, 80.0, 85.0, 89.0, 89.5, 89.9})
        out.push_back(rptest::dir_deg(theta, 360.0 * rng.uniform()));
    const double cosMax = std::cos(89.9 * M_PI / 180.0);
    for (int i = 0; i < 20; ++i) {
        const double c = cosMax + (1.0 - cosMax) * rng.uniform();
        out.push_back(rptest::dir_deg(std::acos(c) * 180.0 / M_PI, 360.0 * rng.uniform()));
    }
    for (int i = 0; i < 20; ++i)
        out.push_back(rptest::dir_deg(80.0 + 9.9 * rng.uniform(), 360.0 * rng.uniform()));
    return out;
}

// The random numbers of one wi: a few edge values, then uniform ones. All in [0, 1).
template <class Real>
std::vector<glm::vec<3, Real>> random_triples(rptest::Rng& rng, int n) {
    using vec3 = glm::vec<3, Real>;
    // The largest Real below 1: u in [0, 1) (the node's contract).
    const Real below1 = std::nextafter(Real(1), Real(0));
    std::vector<vec3> out = {vec3(0), vec3(Real(0.5)), vec3(below1),
                             vec3(Real(0), below1, Real(0.5)), vec3(below1, Real(0), Real(0.999))};
    auto u = [&]() { return std::min(Real(rng.uniform()), below1); };
    for (int i = 0; i < n; ++i)
        out.push_back(vec3(u(), u(), u()));
    return out;
}

// Per-precision totals over all corners, for the MEASURED lines.
struct Totals {
    long samples = 0, empty = 0, renormalised = 0;
    double worstSame = 0;         // sample vs eval, identical local directions
    double worstRenormalised = 0; // sample vs eval where eval renormalised wo
    double worstCore = 0;         // sample vs core eval at the same bits
    long zeroLobe = 0;            // sampled lobe legitimately zero (T(cos_o) rounds to 0)
    double worstUnitUlps = 0;     // max ||wo| - 1| / epsilon
};

template <class Real>
void check_corner(const rptest::Corner& corner, std::uint64_t seed, Totals& tot) {
    using Node = PrismaticRetroreflector<Real>;
    using vec3 = typename Node::vec3;
    const double tol = Tol<Real>::rel;
    const Real eps = std::numeric_limits<Real>::epsilon();
    const Node node(corner.params);
    rptest::Rng rng(seed);
    // The corners use the default frame (normal +z, tangent +x), in which to_world() returns the
    // local direction bit for bit: s.wo is then the very direction sample() evaluated.
    const retroprism::Vec3d zAxis = {0.0, 0.0, 1.0}, xAxis = {1.0, 0.0, 0.0};
    REQUIRE(node.params().normal == zAxis);
    REQUIRE(node.params().tangent == xAxis);

    // Violations, counted, with the first one described.
    long nonEmpty = 0, badLobe = 0, badWo = 0, badPdf = 0, badF = 0, zeroLobe = 0, badWeight = 0,
         badEval = 0, badCore = 0, badRenorm = 0, badPdfFn = 0;
    std::string first;
    auto note = [&](long& counter, const std::string& what) {
        if (counter++ == 0 && first.empty()) first = what;
    };

    for (const glm::dvec3& wiD : incident_directions(rng)) {
        const vec3 wi(wiD);
        vec3 wiLocal;
        if (!node.to_local(wi, wiLocal)) {
            note(badEval, "to_local(wi) failed for a unit wi");
            continue;
        }
        for (const vec3& u : random_triples<Real>(rng, 48)) {
            const auto s = node.sample(wi, u);
            ++tot.samples;
            if (!s) {
                ++tot.empty;
                continue;
            }
            ++nonEmpty;
            std::ostringstream where;
            where.precision(17);
            where << "wi = (" << wi.x << ", " << wi.y << ", " << wi.z << "), u = (" << u.x << ", "
                  << u.y << ", " << u.z << "), wo = (" << s->wo.x << ", " << s->wo.y << ", "
                  << s->wo.z << "), lobe " << s->lobe << ", pdf " << s->pdf;
            const std::string at = where.str();

            if (s->lobe < 0 || s->lobe > 2) note(badLobe, "lobe index out of range at " + at);
            // Unit to kUnitUlps; above the horizon by the node's own
            // threshold (RP_MIN_COS: below it sample() returns nothing).
            const double len = std::sqrt(double(glm::dot(s->wo, s->wo)));
            tot.worstUnitUlps = std::max(tot.worstUnitUlps, std::abs(len - 1.0) / double(eps));
            if (!(std::abs(len - 1.0) <= kUnitUlps * double(eps)) ||
                !(s->wo.z >= Real(retroprism::f64::RP_MIN_COS)))
                note(badWo, "wo not unit or below the horizon at " + at);
            if (!(s->pdf > 0) || !std::isfinite(s->pdf))
                note(badPdf, "pdf not positive and finite at " + at);
            bool fOk = true;
            for (int c = 0; c < 3; ++c)
                for (Real v : {s->f.surface[c], s->f.retro[c], s->f.diffuse[c]})
                    fOk = fOk && std::isfinite(v) && v >= 0;
            if (!fOk) note(badF, "f not finite and non-negative at " + at);
            // The sampled lobe has a value there, unless it is legitimately zero: the retro and
            // diffuse lobes carry T(cos_o) = 1 - F(cos_o), which rounds to 0 at grazing wo.
            if (s->lobe >= 0 && s->lobe <= 2) {
                const vec3 lobeF = s->lobe == 0   ? s->f.surface
                                   : s->lobe == 1 ? s->f.retro
                                                  : s->f.diffuse;
                if (!(lobeF.x > 0 || lobeF.y > 0 || lobeF.z > 0)) {
                    const Real t = Real(1) - fresnel(s->wo.z, node.core_material().eta);
                    if (s->lobe != 0 && t == Real(0))
                        ++zeroLobe;
                    else
                        note(badLobe, "the sampled lobe is zero at " + at);
                }
            }
            const vec3 fTotal = s->f.total();
            for (int c = 0; c < 3; ++c) {
                const Real w = fTotal[c] * s->wo.z / s->pdf;
                if (!std::isfinite(w)) note(badWeight, "estimator weight not finite at " + at);
            }

            // sample() against the core's eval at the very same local directions.
            typename core<Real>::lobes r;
            Real corePdf = 0;
            core<Real>::eval(node.core_material(), wiLocal, s->wo, r, corePdf);
            typename Node::Lobes coreF;
            coreF.surface = r.surface;
            coreF.retro = r.retro;
            coreF.diffuse = r.diffuse;
            const double dCore = std::max(max_rel_diff(s->f, coreF), rel_diff(s->pdf, corePdf));
            tot.worstCore = std::max(tot.worstCore, dCore);
            if (!(dCore <= tol)) note(badCore, "sample() differs from the core eval at " + at);

            // sample() against the node's eval() and pdf() at s.wo.
            const auto e = node.eval(wi, s->wo);
            const Real p = node.pdf(wi, s->wo);
            if (!(p == e.pdf)) note(badPdfFn, "pdf() != eval().pdf at " + at);
            vec3 woLocal;
            if (!node.to_local(s->wo, woLocal)) {
                note(badEval, "to_local(wo) failed at " + at);
                continue;
            }
            const double d = std::max(max_rel_diff(s->f, e.f), rel_diff(s->pdf, e.pdf));
            if (woLocal == s->wo) {
                tot.worstSame = std::max(tot.worstSame, d);
                if (!(d <= tol)) note(badEval, "sample() differs from eval()/pdf() at " + at);
            } else {
                // eval() renormalised wo: compare it with the core at that direction, and bound
                // the move.
                ++tot.renormalised;
                tot.worstRenormalised = std::max(tot.worstRenormalised, d);
                core<Real>::eval(node.core_material(), wiLocal, woLocal, r, corePdf);
                coreF.surface = r.surface;
                coreF.retro = r.retro;
                coreF.diffuse = r.diffuse;
                const double dr = std::max(max_rel_diff(e.f, coreF), rel_diff(e.pdf, corePdf));
                const vec3 move = glm::abs(woLocal - s->wo);
                if (!(dr <= tol) ||
                    !(std::max(move.x, std::max(move.y, move.z)) <= Real(kUnitUlps + 1) * eps))
                    note(badRenorm, "eval() of a renormalised wo is off at " + at);
            }
        }
        // pdf() is eval().pdf at arbitrary directions too, above and below the horizon.
        for (int k = 0; k < 4; ++k) {
            const vec3 wo(rptest::dir_deg(180.0 * rng.uniform(), 360.0 * rng.uniform()));
            const auto e = node.eval(wi, wo);
            if (!(node.pdf(wi, wo) == e.pdf)) note(badPdfFn, "pdf() != eval().pdf at a random wo");
        }
    }
    tot.zeroLobe += zeroLobe;
    INFO(Tol<Real>::name << " node, " << corner.name << ": first problem: " << first);
    CHECK(nonEmpty > 0);
    CHECK(badLobe == 0);
    CHECK(badWo == 0);
    CHECK(badPdf == 0);
    CHECK(badF == 0);
    CHECK(badWeight == 0);
    CHECK(badCore == 0);
    CHECK(badEval == 0);
    CHECK(badRenorm == 0);
    CHECK(badPdfFn == 0);
}

template <class Real>
void check_all_corners() {
    Totals tot;
    const auto corners = rptest::parameter_corners();
    for (size_t i = 0; i < corners.size(); ++i)
        check_corner<Real>(corners[i], 0xc0ffee00u + i, tot);
    std::printf("MEASURED: consistency (%s): %zu corners, %ld samples (%ld empty); max relative "
                "difference sample() vs eval()/pdf() = %.3g (identical directions), vs the core "
                "at the same bits = %.3g; %ld samples renormalised by eval() (max relative "
                "difference there %.3g); %ld sampled lobes legitimately zero (T(cos_o) = 0); max "
                "||wo| - 1| = "
                "%.2g ulp\n",
                Tol<Real>::name, corners.size(), tot.samples, tot.empty, tot.worstSame,
                tot.worstCore, tot.renormalised, tot.worstRenormalised, tot.zeroLobe,
                tot.worstUnitUlps);
}

// Below the horizon: wi.z < RP_MIN_COS (including -0 and 0) gives nothing.
template <class Real>
void check_below_horizon() {
    using Node = PrismaticRetroreflector<Real>;
    using vec3 = typename Node::vec3;
    rptest::Rng rng(0xbe10u);
    long checked = 0, badTotal = 0;
    for (const rptest::Corner& corner : rptest::parameter_corners()) {
        const Node node(corner.params);
        long bad = 0;
        std::string first;
        for (double wiZ : {-1.0, -0.5, -1e-3, -1e-12, -0.0, 0.0, 1e-12, 5e-10}) {
            const double r = std::sqrt(1.0 - wiZ * wiZ);
            const double phi = 2.0 * M_PI * rng.uniform();
            const vec3 wi(glm::dvec3(r * std::cos(phi), r * std::sin(phi), wiZ));
            for (int k = 0; k < 8; ++k) {
                const vec3 u(Real(rng.uniform()), Real(rng.uniform()), Real(rng.uniform()));
                const vec3 wo(rptest::dir_deg(90.0 * rng.uniform(), 360.0 * rng.uniform()));
                const auto s = node.sample(wi, u);
                const auto e = node.eval(wi, wo);
                const bool zero = e.f.total() == vec3(0) && e.pdf == 0 && node.pdf(wi, wo) == 0;
                ++checked;
                if (s || !zero) {
                    if (bad++ == 0) {
                        std::ostringstream os;
                        os << "wi.z = " << wiZ << ": sample " << (s ? "not empty" : "empty")
                           << ", eval total (" << e.f.total().x << ", ...), pdf " << e.pdf;
                        first = os.str();
                    }
                }
                // And a wo below the horizon with wi above it: zero as well.
                const vec3 wiUp(rptest::dir_deg(89.0 * rng.uniform(), 360.0 * rng.uniform()));
                const vec3 woDown(glm::dvec3(wo.x, wo.y, -double(wo.z)));
                const auto e2 = node.eval(wiUp, woDown);
                if (!(e2.f.total() == vec3(0) && e2.pdf == 0)) {
                    if (bad++ == 0) first = "wo below the horizon evaluates to non-zero";
                }
            }
        }
        INFO(Tol<Real>::name << " node, " << corner.name << ": " << first);
        CHECK(bad == 0);
        badTotal += bad;
    }
    std::printf(
        "MEASURED: consistency (%s): %ld queries with wi.z < RP_MIN_COS (each also with a wo below "
        "the horizon), %ld not empty or not zero\n",
        Tol<Real>::name, checked, badTotal);
}

} // namespace

TEMPLATE_TEST_CASE("consistency: sample() agrees with eval() and pdf() at every corner",
                   "[consistency]", double, float) {
    check_all_corners<TestType>();
}

TEMPLATE_TEST_CASE("consistency: below the horizon, sample() is empty and eval() zero",
                   "[consistency]", double, float) {
    check_below_horizon<TestType>();
}

// f() is eval().f without the pdf: the same lobe arithmetic, so the same bits.
TEMPLATE_TEST_CASE("consistency: f() equals eval().f", "[consistency]", double, float) {
    using Node = PrismaticRetroreflector<TestType>;
    using vec3 = typename Node::vec3;
    rptest::Rng rng(0xf00du);
    long checked = 0, differ = 0;
    for (const rptest::Corner& corner : rptest::parameter_corners()) {
        const Node node(corner.params);
        for (int k = 0; k < 64; ++k) {
            const vec3 wi(rptest::dir_deg(89.9 * rng.uniform(), 360.0 * rng.uniform()));
            // Near the retro peak, near the mirror direction, or anywhere.
            vec3 wo(rptest::dir_deg(89.9 * rng.uniform(), 360.0 * rng.uniform()));
            if (k % 3 == 0) wo = glm::normalize(wi + vec3(TestType(0.01) * vec3(rng.uniform())));
            if (k % 3 == 1) wo = vec3(-wi.x, -wi.y, wi.z);
            const auto e = node.eval(wi, wo);
            const auto f = node.f(wi, wo);
            ++checked;
            differ +=
                !(f.surface == e.f.surface && f.retro == e.f.retro && f.diffuse == e.f.diffuse);
        }
    }
    std::printf("MEASURED: consistency (%s): f() vs eval().f at %ld pairs, %ld differ\n",
                Tol<TestType>::name, checked, differ);
    CHECK(checked > 1000);
    CHECK(differ == 0);
}

// f, eval, pdf and sample from incident(wi) are those from wi: the incident state made once,
// the same lobe arithmetic, so the same bits; with several outgoing directions and samples per
// incident direction (as the LiDAR aperture integrals and a shading point's light and BSDF
// samples use it), directions below the horizon on either side, u at its range ends, and the
// corners' diffracting materials.
TEMPLATE_TEST_CASE("consistency: f, eval, pdf and sample from incident(wi) equal those from wi",
                   "[consistency]", double, float) {
    using Node = PrismaticRetroreflector<TestType>;
    using vec3 = typename Node::vec3;
    const auto same = [](const typename Node::Lobes& a, const typename Node::Lobes& b) {
        return a.surface == b.surface && a.retro == b.retro && a.diffuse == b.diffuse;
    };
    rptest::Rng rng(0x1c1du);
    long checked = 0, differ = 0, invalid = 0, samples = 0, empty = 0, sampleDiffer = 0;
    for (const rptest::Corner& corner : rptest::parameter_corners()) {
        const Node node(corner.params);
        for (int k = 0; k < 16; ++k) {
            // Every eighth wi below the horizon: its state is invalid and everything is 0.
            vec3 wi(rptest::dir_deg(89.9 * rng.uniform(), 360.0 * rng.uniform()));
            if (k % 8 == 7) wi.z = -wi.z;
            const typename Node::Incident in = node.incident(wi);
            invalid += !in.valid;
            for (int j = 0; j < 8; ++j) {
                vec3 wo(rptest::dir_deg(89.9 * rng.uniform(), 360.0 * rng.uniform()));
                if (j % 4 == 0)
                    wo = glm::normalize(wi + vec3(TestType(0.01) * vec3(rng.uniform())));
                if (j % 4 == 1) wo = vec3(-wi.x, -wi.y, wi.z);
                if (j % 4 == 2) wo.z = -wo.z;
                const auto ea = node.eval(in, wo), eb = node.eval(wi, wo);
                ++checked;
                differ += !same(node.f(in, wo), node.f(wi, wo)) || !same(ea.f, eb.f) ||
                          !(ea.pdf == eb.pdf) || !(node.pdf(in, wo) == node.pdf(wi, wo));
                // u random, then at its range ends (0 and the largest below 1).
                const TestType top = std::nextafter(TestType(1), TestType(0));
                const vec3 u = j < 6 ? vec3(TestType(rng.uniform()), TestType(rng.uniform()),
                                            TestType(rng.uniform()))
                                     : vec3(j == 6 ? TestType(0) : top);
                const auto sa = node.sample(in, u), sb = node.sample(wi, u);
                ++samples;
                empty += !sb;
                sampleDiffer += sa.has_value() != sb.has_value() ||
                                (sa && !(sa->wo == sb->wo && same(sa->f, sb->f) &&
                                         sa->pdf == sb->pdf && sa->lobe == sb->lobe));
            }
        }
    }
    std::printf("MEASURED: consistency (%s): f, eval and pdf from incident(wi) vs from wi at %ld "
                "pairs (%ld incident directions below the horizon), %ld differ; sample at %ld "
                "(%ld empty), %ld differ\n",
                Tol<TestType>::name, checked, invalid, differ, samples, empty, sampleDiffer);
    CHECK(checked > 1000);
    CHECK(invalid > 0);
    CHECK(samples - empty > 1000);
    CHECK(differ == 0);
    CHECK(sampleDiffer == 0);
}
