#include "fitting.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "linalg.h"
#include "minimize.h"
#include "parallel.h"
#include "stats.h"

namespace retroprism {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kFwhmToSigma = 1.0 / 2.3548200450309493; // 1 / (2 sqrt(2 ln 2))

// Search ranges of the shape parameters (within the node's table ranges; eta = 1 is excluded
// because the retro lobe collapses there).
constexpr double kAlphaMin = 1e-3, kAlphaMax = 1.0;
constexpr double kEtaMin = 1.01, kEtaMax = 3.0;

// The weights and the floor epsilon of the objective (see fitting.h).
struct Weighting {
    std::vector<double> w; // sums to 1
    double epsilon = 0;
};

Weighting weighting(const FitData& d, const FitOptions& o) {
    Weighting wt;
    std::vector<double> all;
    for (const FitSample& s : d.samples)
        all.push_back(s.value);
    wt.epsilon = std::max(o.floor_fraction * median(all), 1e-12);
    const size_t G = d.group_theta.size();
    std::vector<double> groupMedian(G);
    for (size_t g = 0; g < G; ++g) {
        std::vector<double> v;
        for (const FitSample& s : d.samples)
            if (size_t(s.group) == g) v.push_back(s.value);
        groupMedian[g] = median(v);
    }
    std::vector<int> nPeak(G, 0), nFloor(G, 0);
    auto isPeak = [&](const FitSample& s) {
        return s.value > o.peak_factor * groupMedian[size_t(s.group)];
    };
    for (const FitSample& s : d.samples)
        (isPeak(s) ? nPeak : nFloor)[size_t(s.group)]++;
    wt.w.resize(d.samples.size());
    for (size_t i = 0; i < d.samples.size(); ++i) {
        const FitSample& s = d.samples[i];
        const size_t g = size_t(s.group);
        const bool both = nPeak[g] > 0 && nFloor[g] > 0;
        const double classWeight = both ? 0.5 : 1.0;
        wt.w[i] = classWeight / double(G) / double(isPeak(s) ? nPeak[g] : nFloor[g]);
    }
    return wt;
}

double sigma_rad(const FitOptions& o) {
    return std::max(o.resolution_fwhm_deg, 0.0) * kDeg * kFwhmToSigma;
}

// ---------------------------------------------------------------------------------------------
// The node's unit lobes per sample: surface (k_s = 1), retro (c_r = 1), diffuse (k_d = 1),
// each times cos(theta_o), with the instrument's blur.

using Basis3 = std::array<double, 3>;

// The sheeting geometry inputs: cant_angle (degrees), dihedral_error and dihedral_spread
// (arcminutes).
struct Geometry {
    double cant_angle = 0, dihedral_error = 0, dihedral_spread = 0;
};

Params unit_params(double alpha, double eta, int mode, const Geometry& geo) {
    Params p;
    p.cant_angle = geo.cant_angle;
    p.dihedral_error = geo.dihedral_error;
    p.dihedral_spread = geo.dihedral_spread;
    p.roughness = std::clamp(alpha, 0.0, 1.0);
    p.ior = eta;
    p.prism_reflection = mode;
    p.specular = 1.0;
    p.diffuse_color = {1.0, 1.0, 1.0};
    p.retro_color = {1.0, 1.0, 1.0};
    return p;
}

// The node's own core (nodes/prism_core.inc) is called per theta_l group: the incident state
// (refraction, retroreflected fraction E, lobe widths) depends on wi alone, so it is set up once
// per group instead of once per sample as PrismaticRetroreflector::eval would (E of uncoated
// prisms is an exact azimuth integral). The values are eval's: the directions are already in
// the local frame (default normal and tangent).
std::vector<Basis3> node_basis(double alpha, double eta, int mode, const Geometry& geo,
                               const FitData& d, const FitOptions& o) {
    const double sigma = sigma_rad(o);
    // Per group: the material for the surface lobe (alpha_s) and for the retro and diffuse
    // lobes (alpha_r), and their incident states; without blur both are the material itself.
    struct Group {
        f64::rp_material ms, mr;
        f64::rp_incident ss, sr;
    };
    std::vector<Group> groups(d.group_theta.size());
    for (size_t g = 0; g < groups.size(); ++g) {
        const double thetaI = d.group_theta[g];
        const double alphaS = std::sqrt(alpha * alpha + 0.5 * sigma * sigma);
        const double cosI = std::cos(thetaI), sinT = std::sin(thetaI) / eta;
        const double cosT = std::sqrt(std::max(0.0, 1.0 - sinT * sinT));
        const double k = std::sqrt(2.0) * std::abs(eta * cosT - cosI) / std::sqrt(cosI);
        const double alphaR =
            k > 1e-9 ? std::sqrt(alpha * alpha + 2.0 * sigma * sigma / (k * k)) : kAlphaMax;
        Group& gr = groups[g];
        gr.ms = prepare_material(sanitize(unit_params(sigma > 0 ? alphaS : alpha, eta, mode, geo)));
        gr.mr = prepare_material(sanitize(unit_params(sigma > 0 ? alphaR : alpha, eta, mode, geo)));
        const f64::vec3 wi(std::sin(thetaI), 0.0, cosI);
        f64::rp_incident_setup(gr.ms, wi, gr.ss);
        f64::rp_incident_setup(gr.mr, wi, gr.sr);
    }
    std::vector<Basis3> B(d.samples.size());
    parallel_ranges(d.samples.size(), o.threads, 256, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
            const FitSample& s = d.samples[i];
            B[i] = {0.0, 0.0, 0.0};
            if (!(s.wi.z >= f64::RP_MIN_COS && s.wo.z >= f64::RP_MIN_COS)) continue;
            const Group& gr = groups[size_t(s.group)];
            f64::rp_lobes fs, fr;
            f64::rp_eval_lobes(gr.ms, gr.ss, s.wi, s.wo, fs);
            if (sigma > 0)
                f64::rp_eval_lobes(gr.mr, gr.sr, s.wi, s.wo, fr);
            else
                fr = fs;
            const double c = s.wo.z;
            B[i] = {fs.surface.x * c, fr.retro.x * c, fr.diffuse.x * c};
        }
    });
    return B;
}

// c_d of the diffuse lobe for substrate albedo k_d, and back (F = F_dr internal).
double diffuse_coefficient(double kd, double F) {
    return kd * (1.0 - F) / (1.0 - kd * F);
}
double diffuse_albedo(double c, double F) {
    return c / (1.0 - F + c * F);
}

// ---------------------------------------------------------------------------------------------
// The inner problem: n <= 3 coefficients in [0, 1] minimising sum w (ln(m + eps) - ln(y +
// eps))^2, by projected Levenberg-Marquardt. `model(i, c, m, grad)` gives the model value of
// sample i and its gradient in c.

struct Inner {
    double cost = std::numeric_limits<double>::infinity();
    std::array<double, 3> c{0, 0, 0};
};

template <class Model>
double inner_cost(const Model& model, int n, const std::array<double, 3>& c,
                  const std::vector<double>& logY, const Weighting& wt) {
    double cost = 0;
    double grad[3];
    (void)n;
    for (size_t i = 0; i < logY.size(); ++i) {
        double m;
        model(i, c.data(), m, grad);
        const double r = std::log(std::max(m, 0.0) + wt.epsilon) - logY[i];
        cost += wt.w[i] * r * r;
    }
    return cost;
}

template <class Model>
Inner solve_inner(const Model& model, int n, std::array<double, 3> c,
                  const std::vector<double>& logY, const Weighting& wt) {
    Inner best;
    best.c = c;
    best.cost = inner_cost(model, n, c, logY, wt);
    double lambda = 1e-3;
    for (int it = 0; it < 200; ++it) {
        // Gauss-Newton normal equations of the weighted log residuals.
        double H[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, g[3] = {0, 0, 0};
        for (size_t i = 0; i < logY.size(); ++i) {
            double m, grad[3];
            model(i, best.c.data(), m, grad);
            const double mm = std::max(m, 0.0) + wt.epsilon;
            const double r = std::log(mm) - logY[i];
            double J[3];
            for (int k = 0; k < n; ++k)
                J[k] = grad[k] / mm;
            for (int a = 0; a < n; ++a) {
                g[a] += wt.w[i] * J[a] * r;
                for (int b = 0; b < n; ++b)
                    H[a][b] += wt.w[i] * J[a] * J[b];
            }
        }
        // Active bounds: a coefficient at a bound whose descent direction leaves [0, 1].
        int freeIdx[3], nf = 0;
        for (int k = 0; k < n; ++k) {
            const bool atLo = best.c[size_t(k)] <= 0.0 && g[k] > 0;
            const bool atHi = best.c[size_t(k)] >= 1.0 && g[k] < 0;
            if (!atLo && !atHi) freeIdx[nf++] = k;
        }
        if (nf == 0) break;
        bool improved = false;
        while (lambda < 1e12) {
            double A[9], b[3], x[3];
            for (int a = 0; a < nf; ++a) {
                for (int bb = 0; bb < nf; ++bb)
                    A[a * nf + bb] = H[freeIdx[a]][freeIdx[bb]];
                A[a * nf + a] += lambda * H[freeIdx[a]][freeIdx[a]] + 1e-300;
                b[a] = -g[freeIdx[a]];
            }
            std::array<double, 3> trial = best.c;
            if (solve_linear(nf, 1, A, b, x))
                for (int a = 0; a < nf; ++a)
                    trial[size_t(freeIdx[a])] =
                        std::clamp(trial[size_t(freeIdx[a])] + x[a], 0.0, 1.0);
            const double cost = inner_cost(model, n, trial, logY, wt);
            if (cost < best.cost) {
                const double gain = best.cost - cost;
                best.c = trial;
                best.cost = cost;
                lambda = std::max(lambda / 3.0, 1e-12);
                improved = gain > 1e-13 * (best.cost + 1e-300);
                break;
            }
            lambda *= 4.0;
        }
        if (!improved) break;
    }
    return best;
}

// The searched shape parameters: alpha, then eta unless fixed (fixedEta > 0), then the
// geometry inputs when `geometry` (the node's cant_angle, dihedral_error and dihedral_spread in
// their RP_FIT ranges). ShapeSearch::value maps a point of the search to them.
struct ShapeSearch {
    std::vector<BoxVar> box;
    std::vector<std::vector<double>> starts;
    double fixedEta = 0;
    bool geometry = false;

    double alpha(const std::vector<double>& x) const { return x[0]; }
    double eta(const std::vector<double>& x) const { return fixedEta > 0 ? fixedEta : x[1]; }
    Geometry geo(const std::vector<double>& x) const {
        const size_t k = fixedEta > 0 ? 1 : 2;
        return geometry ? Geometry{x[k], x[k + 1], x[k + 2]} : Geometry{};
    }
};

BoxVar fit_range(const char* name) {
    for (const FitInfo& f : fit_table())
        if (std::string(f.param->name) == name) return {f.lo, f.hi, f.scale == FitScale::Log};
    return {0.0, 0.0, false}; // not reached: the parameter table fits both geometry inputs
}

// The paper's geometry (cant 0, no dihedral errors): alpha, and eta unless fixed, from alpha
// 0.01, 0.05 and 0.2 with eta 1.5. With the geometry: all from the paper geometry's optimum
// `shape` (alpha, eta) with the paper's geometry, with the dihedral error at the centre of its
// range, with that and the cant at 12% and 88% of its range (logistic coordinates -2 and +2),
// and with the dihedral spread at the centre of its range alone, so the search does not hinge
// on leaving the borders dihedral_error = 0 or dihedral_spread = 0.
ShapeSearch shape_search(double fixedEta, const std::vector<double>* shape = nullptr) {
    ShapeSearch s;
    s.fixedEta = fixedEta;
    s.geometry = shape != nullptr;
    s.box.push_back({kAlphaMin, kAlphaMax, false});
    if (!(fixedEta > 0)) s.box.push_back({kEtaMin, kEtaMax, false});
    if (!s.geometry) {
        for (double a0 : {0.01, 0.05, 0.2}) {
            std::vector<double> x = {a0};
            if (!(fixedEta > 0)) x.push_back(1.5);
            s.starts.push_back(x);
        }
        return s;
    }
    const BoxVar cant = fit_range("cant_angle"), dihedral = fit_range("dihedral_error"),
                 spread = fit_range("dihedral_spread");
    s.box.push_back(cant);
    s.box.push_back(dihedral);
    s.box.push_back(spread);
    const double d0 = box_value(dihedral, 0.0), s0 = box_value(spread, 0.0);
    for (const std::vector<double>& g :
         std::vector<std::vector<double>>{{0.0, 0.0, 0.0},
                                          {0.0, d0, 0.0},
                                          {box_value(cant, -2.0), d0, 0.0},
                                          {box_value(cant, 2.0), d0, 0.0},
                                          {0.0, 0.0, s0}}) {
        std::vector<double> x = *shape;
        x.insert(x.end(), g.begin(), g.end());
        s.starts.push_back(x);
    }
    return s;
}

// Evaluations per Nelder-Mead run: 120 for (alpha, eta), 60 more per further dimension.
int shape_evaluations(const ShapeSearch& s) {
    return 120 + 60 * std::max(int(s.box.size()) - 2, 0);
}

std::vector<double> log_values(const FitData& d, const Weighting& wt) {
    std::vector<double> v(d.samples.size());
    for (size_t i = 0; i < v.size(); ++i)
        v[i] = std::log(d.samples[i].value + wt.epsilon);
    return v;
}

// The node's inner model for fixed (alpha, eta, mode): m = k_s B_s + c_r B_r + c_d B_d.
struct NodeInner {
    const std::vector<Basis3>* B;
    void operator()(size_t i, const double* c, double& m, double* grad) const {
        const Basis3& b = (*B)[i];
        m = c[0] * b[0] + c[1] * b[1] + c[2] * b[2];
        grad[0] = b[0];
        grad[1] = b[1];
        grad[2] = b[2];
    }
};

// The baseline's inner model for fixed (alpha, eta): m = k_s s + k_d d (1 - k_s e).
struct MrmUnit {
    double s, d, e;
};
struct MrmInner {
    const std::vector<MrmUnit>* U;
    void operator()(size_t i, const double* c, double& m, double* grad) const {
        const MrmUnit& u = (*U)[i];
        m = c[0] * u.s + c[1] * u.d * (1.0 - c[0] * u.e);
        grad[0] = u.s - c[1] * u.d * u.e;
        grad[1] = u.d * (1.0 - c[0] * u.e);
        grad[2] = 0.0;
    }
};

std::vector<MrmUnit> mrm_basis(double alpha, double eta, const FitData& d, const FitOptions& o) {
    const double sigma = sigma_rad(o);
    baselines::RetroreflectiveGGX blurred, plain;
    blurred.roughness = std::sqrt(alpha * alpha + sigma * sigma);
    plain.roughness = alpha;
    blurred.ior = plain.ior = eta;
    std::vector<MrmUnit> U(d.samples.size());
    parallel_ranges(d.samples.size(), o.threads, 256, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
            const FitSample& s = d.samples[i];
            const double c = std::max(s.wo.z, 0.0);
            const auto ub = blurred.unit(s.wi, s.wo), up = plain.unit(s.wi, s.wo);
            U[i] = {ub.s * c, up.d * c, up.e};
        }
    });
    return U;
}

} // namespace

// ---------------------------------------------------------------------------------------------

void add_sample(FitData& d, double thetaL, const glm::dvec3& wo, double value, int line) {
    int g = -1;
    for (size_t k = 0; k < d.group_theta.size(); ++k)
        if (std::abs(d.group_theta[k] - thetaL) < 1e-9) g = int(k);
    if (g < 0) {
        g = int(d.group_theta.size());
        d.group_theta.push_back(thetaL);
    }
    FitSample s;
    s.wi = glm::dvec3(std::sin(thetaL), 0.0, std::cos(thetaL));
    s.wo = wo;
    s.value = value;
    s.group = g;
    s.line = line;
    d.samples.push_back(s);
}

FitData fit_data(const AltaData& alta) {
    FitData d;
    d.file = alta.file;
    for (const AltaSample& s : alta.samples)
        add_sample(d, s.theta_l, s.wo(), s.value_cos(alta.cosine_factor), s.line);
    return d;
}

Params node_params(const NodeFitParams& p) {
    Params q;
    q.roughness = p.roughness;
    q.ior = p.ior;
    q.specular = p.specular;
    q.retro_color = {p.retro, p.retro, p.retro};
    q.diffuse_color = {p.diffuse, p.diffuse, p.diffuse};
    q.prism_reflection = p.prism_reflection;
    q.cant_angle = p.cant_angle;
    q.dihedral_error = p.dihedral_error;
    q.dihedral_spread = p.dihedral_spread;
    return q;
}

std::vector<double> node_values(const NodeFitParams& p, const FitData& d, const FitOptions& o) {
    const std::vector<Basis3> B =
        node_basis(p.roughness, p.ior, p.prism_reflection,
                   {p.cant_angle, p.dihedral_error, p.dihedral_spread}, d, o);
    const double cd = diffuse_coefficient(p.diffuse, fdr_internal(p.ior));
    std::vector<double> v(B.size());
    for (size_t i = 0; i < B.size(); ++i)
        v[i] = p.specular * B[i][0] + p.retro * B[i][1] + cd * B[i][2];
    return v;
}

std::vector<double> mrm_values(const baselines::RetroreflectiveGGX& m, const FitData& d,
                               const FitOptions& o) {
    const std::vector<MrmUnit> U = mrm_basis(m.roughness, m.ior, d, o);
    std::vector<double> v(U.size());
    const double ks = m.specular, kd = m.color.x;
    for (size_t i = 0; i < U.size(); ++i)
        v[i] = ks * m.tint.x * U[i].s + kd * U[i].d * (1.0 - ks * U[i].e);
    return v;
}

FitReport fit_report(const FitData& d, const std::vector<double>& model, const FitOptions& o) {
    const Weighting wt = weighting(d, o);
    FitReport r;
    r.epsilon = wt.epsilon;
    const size_t G = d.group_theta.size();
    std::vector<double> rel2(G, 0), log2(G, 0);
    r.groups.resize(G);
    for (size_t g = 0; g < G; ++g)
        r.groups[g].theta_deg = d.group_theta[g] / kDeg;
    double relAll = 0, logAll = 0;
    for (size_t i = 0; i < d.samples.size(); ++i) {
        const FitSample& s = d.samples[i];
        const double m = std::max(model[i], 0.0), y = s.value;
        const double lr = std::log((m + wt.epsilon) / (y + wt.epsilon));
        const double rr = y > 0 ? (m - y) / y : (m > 0 ? 1.0 : 0.0);
        r.objective += wt.w[i] * lr * lr;
        relAll += rr * rr;
        logAll += lr * lr;
        GroupReport& gr = r.groups[size_t(s.group)];
        gr.samples++;
        rel2[size_t(s.group)] += rr * rr;
        log2[size_t(s.group)] += lr * lr;
        // Peaks: the highest measured sample within 3 degrees of the retro / mirror direction.
        const glm::dvec3 mirror(-s.wi.x, -s.wi.y, s.wi.z);
        const double cap = std::cos(3.0 * kDeg);
        if (glm::dot(s.wo, s.wi) > cap && y > gr.retro_measured) {
            gr.retro_measured = y;
            gr.retro_model = m;
        }
        if (glm::dot(s.wo, mirror) > cap && y > gr.mirror_measured) {
            gr.mirror_measured = y;
            gr.mirror_model = m;
        }
    }
    const double n = double(std::max<size_t>(d.samples.size(), 1));
    r.rel_rms = std::sqrt(relAll / n);
    r.log_rms = std::sqrt(logAll / n);
    for (size_t g = 0; g < G; ++g) {
        const double ng = double(std::max(r.groups[g].samples, 1));
        r.groups[g].rel_rms = std::sqrt(rel2[g] / ng);
        r.groups[g].log_rms = std::sqrt(log2[g] / ng);
    }
    return r;
}

NodeFit fit_node(const FitData& d, const FitOptions& o) {
    const Weighting wt = weighting(d, o);
    const std::vector<double> logY = log_values(d, wt);
    NodeFit best;
    best.report.objective = std::numeric_limits<double>::infinity();
    double bestCost = std::numeric_limits<double>::infinity();
    for (int mode = 0; mode < 3; ++mode) {
        std::array<double, 3> warm = {0.5, 0.5, 0.5};
        std::array<double, 3> lastC = warm;
        auto cost = [&](double alpha, double eta, const Geometry& geo) {
            const std::vector<Basis3> B = node_basis(alpha, eta, mode, geo, d, o);
            const NodeInner model{&B};
            Inner in = solve_inner(model, 3, {0.5, 0.5, 0.5}, logY, wt);
            const Inner in2 = solve_inner(model, 3, warm, logY, wt);
            if (in2.cost < in.cost) in = in2;
            warm = in.c;
            lastC = in.c;
            return in.cost;
        };
        auto run = [&](const ShapeSearch& s) {
            const NmResult r = search_box(
                [&](const std::vector<double>& x) { return cost(s.alpha(x), s.eta(x), s.geo(x)); },
                s.box, s.starts, shape_evaluations(s));
            best.evaluations += r.evaluations;
            return r;
        };
        // The paper's geometry first, then the geometry from its optimum; the border point
        // (the paper's geometry) is kept when the search inside the box does not beat it.
        const ShapeSearch paper = shape_search(o.fixed_ior);
        const NmResult rp = run(paper);
        NmResult r = rp;
        const ShapeSearch* s = &paper;
        best.paper_objective[mode] = rp.f;
        ShapeSearch full;
        if (!o.paper_geometry) {
            full = shape_search(o.fixed_ior, &rp.x);
            const NmResult rg = run(full);
            if (rg.f < rp.f) {
                r = rg;
                s = &full;
            }
        }
        // The coefficients at the optimum (re-solved there: the last evaluation may be
        // elsewhere).
        cost(s->alpha(r.x), s->eta(r.x), s->geo(r.x));
        best.evaluations++;
        best.mode_objective[mode] = r.f;
        if (r.f < bestCost) {
            bestCost = r.f;
            NodeFitParams p;
            p.roughness = s->alpha(r.x);
            p.ior = s->eta(r.x);
            p.cant_angle = s->geo(r.x).cant_angle;
            p.dihedral_error = s->geo(r.x).dihedral_error;
            p.dihedral_spread = s->geo(r.x).dihedral_spread;
            p.prism_reflection = mode;
            p.specular = lastC[0];
            p.retro = lastC[1];
            p.diffuse = diffuse_albedo(lastC[2], fdr_internal(p.ior));
            best.params = p;
        }
    }
    best.report = fit_report(d, node_values(best.params, d, o), o);
    return best;
}

MrmFit fit_mrm(const FitData& d, const FitOptions& o) {
    const Weighting wt = weighting(d, o);
    const std::vector<double> logY = log_values(d, wt);
    std::array<double, 3> warm = {0.5, 0.5, 0.0}, lastC = warm;
    auto cost = [&](double alpha, double eta) {
        const std::vector<MrmUnit> U = mrm_basis(alpha, eta, d, o);
        const MrmInner model{&U};
        Inner in = solve_inner(model, 2, {0.5, 0.5, 0.0}, logY, wt);
        const Inner in2 = solve_inner(model, 2, warm, logY, wt);
        if (in2.cost < in.cost) in = in2;
        warm = in.c;
        lastC = in.c;
        return in.cost;
    };
    const ShapeSearch s = shape_search(o.fixed_ior);
    const NmResult r =
        search_box([&](const std::vector<double>& x) { return cost(s.alpha(x), s.eta(x)); }, s.box,
                   s.starts, shape_evaluations(s));
    cost(s.alpha(r.x), s.eta(r.x));
    MrmFit fit;
    fit.evaluations = r.evaluations + 1;
    fit.model.roughness = s.alpha(r.x);
    fit.model.ior = s.eta(r.x);
    fit.model.specular = lastC[0];
    fit.model.tint = glm::dvec3(1.0);
    fit.model.color = glm::dvec3(lastC[1]);
    fit.report = fit_report(d, mrm_values(fit.model, d, o), o);
    return fit;
}

} // namespace retroprism
