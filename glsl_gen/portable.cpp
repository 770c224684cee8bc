#include "portable.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>

#include "minimize.h"
#include "prismatic_retroreflector.h"

namespace retroprism::glsl {

namespace {

// Degrees of the fits: enough that the fit error is far below the graph's other approximations
// (the figures are printed in the generated file and docs/portable.md).
constexpr int kEraDegreeSin = 14;
constexpr int kEraDegreeCant = 6;
constexpr int kFdrDegree = 10;
constexpr double kCantRange = 30.0; // cant_angle's range, degrees (the parameter table's)
// Uncoated prisms: the fit of Q = E_tir / A in (z, eta) (fit_tir_ratio). Its residual is largest
// near eta = 1.22, where total internal reflection at normal incidence sets in and Q falls from
// 1 to the faces' Fresnel reflectances within a few hundredths of eta; the weight kTirWeight on
// eta in [kTirWeightLo, kTirWeightHi] (the sheeting plastics, acrylic to polycarbonate) keeps the
// fit's relative error there at about 1% (docs/portable.md).
constexpr int kTirDegreeY = 10;
constexpr int kTirDegreeEta = 8;
constexpr double kTirWeight = 10.0;
constexpr double kTirWeightLo = 1.45;
constexpr double kTirWeightHi = 1.65;
// Tikhonov weight on the coefficients: keeps the largest below 1e3 (as the ideal ERA's fit)
// for 0.0005 more RMS error.
constexpr double kTirRidge = 1e-4;
constexpr int kHitsDegree = 10;
// The ERA below which the diffraction lobes' growth A(0) / A stops (grazing incidence): by then
// the lobes' widths are at their clamp of 1.
constexpr double kMinGrowthArea = 1e-3;

// Least squares min |A x - b| by Householder QR (rows >= columns, A of full column rank).
std::vector<double> least_squares(std::vector<std::vector<double>> a, std::vector<double> b) {
    const size_t m = a.size(), n = a.at(0).size();
    for (size_t k = 0; k < n; ++k) {
        double norm = 0;
        for (size_t i = k; i < m; ++i)
            norm += a[i][k] * a[i][k];
        norm = std::sqrt(norm);
        if (norm == 0) throw std::runtime_error("portable fit: rank-deficient design matrix");
        const double alpha = a[k][k] > 0 ? -norm : norm;
        std::vector<double> v(m, 0.0);
        for (size_t i = k; i < m; ++i)
            v[i] = a[i][k];
        v[k] -= alpha;
        double vv = 0;
        for (size_t i = k; i < m; ++i)
            vv += v[i] * v[i];
        auto reflect = [&](auto&& get) {
            double d = 0;
            for (size_t i = k; i < m; ++i)
                d += v[i] * get(i);
            return 2 * d / vv;
        };
        for (size_t j = k; j < n; ++j) {
            const double f = reflect([&](size_t i) { return a[i][j]; });
            for (size_t i = k; i < m; ++i)
                a[i][j] -= f * v[i];
        }
        const double f = reflect([&](size_t i) { return b[i]; });
        for (size_t i = k; i < m; ++i)
            b[i] -= f * v[i];
    }
    std::vector<double> x(n);
    for (size_t k = n; k-- > 0;) {
        double s = b[k];
        for (size_t j = k + 1; j < n; ++j)
            s -= a[k][j] * x[j];
        x[k] = s / a[k][k];
    }
    return x;
}

// Least squares of the design rows (one per point, already weighted) onto `values`, into a
// PolyFit's coefficient layout of degrees (du, dv).
std::vector<std::vector<double>> solve_coefficients(const std::vector<std::vector<double>>& rows,
                                                    const std::vector<double>& values, int du,
                                                    int dv) {
    const std::vector<double> x = least_squares(rows, values);
    std::vector<std::vector<double>> coef(size_t(du + 1), std::vector<double>(size_t(dv + 1)));
    for (int i = 0; i <= du; ++i)
        for (int j = 0; j <= dv; ++j)
            coef[size_t(i)][size_t(j)] = x[size_t(i * (dv + 1) + j)];
    return coef;
}

std::vector<double> monomials(double u, double v, int du, int dv, double weight) {
    std::vector<double> row;
    for (int i = 0; i <= du; ++i)
        for (int j = 0; j <= dv; ++j)
            row.push_back(weight * std::pow(u, i) * std::pow(v, j));
    return row;
}

// sum_ij c[i][j] u^i v^j by Horner's rule in Real: float evaluates it as a shader does (the
// graph's nodes are single precision in GLSL), so that a fit's error includes its rounding.
template <class Real = double>
double poly2(const std::vector<std::vector<double>>& c, double u, double v) {
    Real sum = 0;
    for (size_t i = c.size(); i-- > 0;) {
        Real q = 0;
        for (size_t j = c[i].size(); j-- > 0;)
            q = q * Real(v) + Real(c[i][j]);
        sum = sum * Real(u) + q;
    }
    return double(sum);
}

// Fits f(u, v) on the grid us x vs with degrees (du, dv).
PolyFit fit2(const std::vector<double>& us, const std::vector<double>& vs, int du, int dv,
             const std::function<double(double, double)>& f) {
    std::vector<std::vector<double>> rows;
    std::vector<double> values;
    for (double u : us)
        for (double v : vs) {
            rows.push_back(monomials(u, v, du, dv, 1.0));
            values.push_back(f(u, v));
        }
    PolyFit fit;
    fit.coef = solve_coefficients(rows, values, du, dv);
    double sum2 = 0;
    size_t k = 0;
    for (double u : us)
        for (double v : vs) {
            const double e = std::abs(poly2(fit.coef, u, v) - values[k++]);
            fit.max_error = std::max(fit.max_error, e);
            sum2 += e * e;
        }
    fit.rms_error = std::sqrt(sum2 / double(values.size()));
    return fit;
}

std::vector<double> grid(double lo, double hi, int n) {
    std::vector<double> g;
    for (int i = 0; i < n; ++i)
        g.push_back(lo + (hi - lo) * i / (n - 1));
    return g;
}

} // namespace

const std::vector<PortableException>& portable_exceptions() {
    static const std::vector<PortableException> list = {
        {"fidelity", "the graph is one approximation tier: its fits stand for the exact and the "
                     "fast formulas alike"},
        {"dihedral_error",
         "the ring of spots of cube corners with dihedral-angle errors (a ring convolved with the "
         "retro lobe) has no standard-node form: one microfacet lobe about the view direction "
         "cannot hold a ring, so the graph keeps the perfect cube's lobe"},
        {"reciprocal",
         "the reciprocal form differs from the paper's only where wi != wo, and the graph "
         "evaluates every factor at the view direction, where the two forms agree"},
    };
    return list;
}

const PolyFit& fit_era() {
    static const PolyFit fit = [] {
        // E of ideal prisms is the ERA A of the refracted direction: with ior 1 the refracted
        // direction is wi itself, so sin(theta_t) = sin(theta_i) covers [0, 1).
        std::map<double, PrismaticRetroreflector<double>> nodes;
        auto era = [&](double u, double v) {
            const double cant = v * kCantRange;
            auto it = nodes.find(cant);
            if (it == nodes.end()) {
                Params p;
                p.ior = 1.0;
                p.cant_angle = cant;
                it = nodes.emplace(cant, PrismaticRetroreflector<double>(p)).first;
            }
            const double s = std::min(0.5 * (u + 1), 0.9999);
            return it->second.retro_fraction({s, 0.0, std::sqrt(1 - s * s)});
        };
        return fit2(grid(-1, 1, 201), grid(-1, 1, 25), kEraDegreeSin, kEraDegreeCant, era);
    }();
    return fit;
}

const PolyFit& fit_fdr() {
    static const PolyFit fit = fit2(grid(-1, 1, 201), {0.0}, kFdrDegree, 0,
                                    [](double u, double) { return fdr_internal(u + 2); });
    return fit;
}

namespace {

// E of the node for the refracted direction of sin(theta_t) (refracted from sin(theta_i) = eta
// sin(theta_t) in the plane phi = 0; the averaged ERA does not depend on phi).
double node_era(const PrismaticRetroreflector<double>& node, double eta, double sinT) {
    const double s = std::min(eta * sinT, 0.9999);
    return node.retro_fraction({s, 0.0, std::sqrt(1 - s * s)});
}

// Integrating its azimuth averages: a fit reads each node at a few hundred directions.
PrismaticRetroreflector<double> prism_node(double eta, int prismReflection) {
    Params p;
    p.ior = eta;
    p.prism_reflection = prismReflection;
    return PrismaticRetroreflector<double>(p,
                                           PrismaticRetroreflector<double>::Averages::Integrated);
}

} // namespace

double tir_onset(double sinT, double eta) {
    const double critical = std::asin(1 / eta);
    const double tilt = std::max(std::asin(std::min(sinT, 1.0)) + critical - kCubeFaceAngle, 0.0);
    return std::min(tilt / std::max(2 * critical - kCubeFaceAngle, kTirMinSpan), 1.0);
}

const PolyFit& fit_tir_ratio() {
    static const PolyFit fit = [] {
        // The uncanted cube's ERA A of the refracted direction (ior 1: wi is that direction).
        const PrismaticRetroreflector<double> ideal = prism_node(1.0, 0);
        struct Point {
            double sinT, eta, area, era;
        };
        std::vector<Point> points;
        std::vector<std::vector<double>> rows;
        std::vector<double> values;
        for (double eta : grid(1, 3, 81)) {
            const PrismaticRetroreflector<double> tir = prism_node(eta, 1);
            for (double sinT : grid(0, 1, 201)) {
                const double area = node_era(ideal, 1.0, sinT);
                if (sinT > 1 / eta || area < 1e-3) continue; // no refracted direction; no ERA
                const Point pt{sinT, eta, area, node_era(tir, eta, sinT)};
                const double w =
                    eta >= kTirWeightLo - 1e-9 && eta <= kTirWeightHi + 1e-9 ? kTirWeight : 1.0;
                rows.push_back(monomials(2 * tir_onset(sinT, eta) - 1, eta - 2, kTirDegreeY,
                                         kTirDegreeEta, w));
                values.push_back(w * pt.era / pt.area);
                points.push_back(pt);
            }
        }
        // Ridge rows: the least-squares solution alone has coefficients of up to 4e5 (the fall
        // of Q near eta 1.22 drives them), which cancel beyond single precision in a shader.
        const size_t count = rows.at(0).size();
        for (size_t k = 0; k < count; ++k) {
            rows.emplace_back(count, 0.0);
            rows.back()[k] = kTirRidge;
            values.push_back(0.0);
        }
        PolyFit f;
        f.coef = solve_coefficients(rows, values, kTirDegreeY, kTirDegreeEta);
        auto era = [&](const Point& pt) {
            const double q = poly2<float>(f.coef, 2 * tir_onset(pt.sinT, pt.eta) - 1, pt.eta - 2);
            return std::clamp(q, 0.0, 1.0) * pt.area;
        };
        double sum2 = 0;
        for (const Point& pt : points) {
            const double e = std::abs(era(pt) - pt.era);
            f.max_error = std::max(f.max_error, e);
            sum2 += e * e;
            if (pt.eta >= kTirWeightLo - 1e-9 && pt.eta <= kTirWeightHi + 1e-9 &&
                pt.eta * pt.sinT <= std::sqrt(0.5) && pt.era > 0)
                f.max_rel_error = std::max(f.max_rel_error, e / pt.era);
        }
        f.rms_error = std::sqrt(sum2 / double(points.size()));
        return f;
    }();
    return fit;
}

const PolyFit& fit_metal_hits() {
    static const PolyFit fit = fit2(grid(-1, 1, 201), {0.0}, kHitsDegree, 0, [](double u, double) {
        const double s = std::min(0.5 * (u + 1), 0.9999);
        return metal_hits_averaged_direct(s / std::sqrt(1 - s * s));
    });
    return fit;
}

namespace {

// The search of fit_retro_lobe, a plain function: GCC takes a lambda that initialises a
// static const for a constant expression and runs its 2e7 pow/exp steps in the constant
// evaluator before giving up (17 s of this file's compile).
RetroLobeFit search_retro_lobe() {
    // GGX about V with roughness s alpha_o / 2 at tan(theta_h) = tan(theta' / 2) ~ tan
    // theta' / 2, over the Beckmann lobe's peak value: (1 / s^2) (1 + x / s^2)^-2, x =
    // tan^2 theta' / alpha_o^2; the best scale for width s makes the largest and smallest
    // ratios to exp(-x) equally far from 1.
    RetroLobeFit best;
    best.max_error = 1e300;
    for (int k = 0; k <= 20000; ++k) {
        const double s = 0.5 + 2.0 * k / 20000;
        double lo = 1e300, hi = 0;
        for (int i = 0; i <= 1000; ++i) {
            const double x = kRetroFitRange * i / 1000;
            const double r = std::pow(1 + x / (s * s), -2) / (s * s) / std::exp(-x);
            lo = std::min(lo, r);
            hi = std::max(hi, r);
        }
        const double scale = 2 / (lo + hi);
        const double err = std::max(scale * hi - 1, 1 - scale * lo);
        if (err < best.max_error) best = {s, scale, err};
    }
    return best;
}

} // namespace

const RetroLobeFit& fit_retro_lobe() {
    static const RetroLobeFit fit = search_retro_lobe();
    return fit;
}

namespace {

// The node's diffraction density of nu at normal incidence, azimuth-averaged (48 azimuths), for
// prisms with faces `prismReflection`: lambda / pitch = 1e-3 rad, the geometric lobe of a
// roughness 1e-6 (its width 1e-4 of the pattern's).
std::vector<double> node_diffraction_profile(int prismReflection, const std::vector<double>& nu) {
    Params p;
    p.roughness = 1e-6;
    p.prism_reflection = prismReflection;
    p.prism_pitch = 1000.0;
    p.wavelength = 1000.0;
    const f64::rp_material m = prepare_material(sanitize(p));
    f64::rp_incident s;
    f64::rp_incident_setup(m, f64::vec3(0, 0, 1), s);
    const double scale = m.diff_scale.x;
    std::vector<double> density;
    for (double x : nu) {
        double sum = 0;
        const int n = 48;
        for (int j = 0; j < n; ++j) {
            const double phi = 2 * M_PI * (j + 0.5) / n;
            sum += f64::rp_diffraction_channel(m, s, scale, x * scale * std::cos(phi),
                                               x * scale * std::sin(phi));
        }
        density.push_back(sum / n * scale * scale);
    }
    return density;
}

// The density of nu of a GGX lobe about V of width b (in nu) as fit_retro_lobe maps widths:
// b^2 / (pi (b^2 + nu^2)^2).
double ggx_density(double b, double nu) {
    const double q = b * b + nu * nu;
    return b * b / (M_PI * q * q);
}

DiffractionLobesFit search_diffraction_lobes(int prismReflection) {
    std::vector<double> nu;
    const int points = 61;
    for (int i = 0; i < points; ++i)
        nu.push_back(kDiffractionFitLo *
                     std::pow(kDiffractionFitHi / kDiffractionFitLo, double(i) / (points - 1)));
    const std::vector<double> target = node_diffraction_profile(prismReflection, nu);
    // Coordinates: ln of the two weights (fit_retro_lobe's scale included) and of the two
    // widths in nu; the objective is the largest |ln(fit / node)|.
    auto worst = [&](const std::vector<double>& x) {
        double e = 0;
        for (size_t i = 0; i < nu.size(); ++i) {
            double f = 0;
            for (int k = 0; k < kDiffractionLobes; ++k)
                f += std::exp(x[k]) * ggx_density(std::exp(x[kDiffractionLobes + k]), nu[i]);
            e = std::max(e, std::abs(std::log(f / target[i])));
        }
        return e;
    };
    // Starts: the core near the node's, the tail ten times wider and a tenth as strong.
    NmResult best;
    for (double tail : {0.03, 0.1, 0.3})
        for (double wide : {5.0, 12.0, 30.0}) {
            NmResult r = nelder_mead(
                worst, {std::log(1 - tail), std::log(tail), 0.0, std::log(wide)}, 0.3, 4000);
            for (int restart = 0; restart < 4; ++restart) {
                const NmResult again = nelder_mead(worst, r.x, 0.1, 4000);
                if (!(again.f < r.f)) break;
                r = again;
            }
            if (r.f < best.f) best = r;
        }
    DiffractionLobesFit fit;
    const RetroLobeFit& lobe = fit_retro_lobe();
    for (int k = 0; k < kDiffractionLobes; ++k) {
        fit.weight[k] = std::exp(best.x[k]) / lobe.scale;
        fit.sigma[k] = std::exp(best.x[kDiffractionLobes + k]) / lobe.width;
    }
    fit.max_error = best.f;
    return fit;
}

} // namespace

const DiffractionLobesFit& fit_diffraction_lobes(int prismReflection) {
    static const DiffractionLobesFit fits[3] = {
        search_diffraction_lobes(0), search_diffraction_lobes(1), search_diffraction_lobes(2)};
    return fits[std::clamp(prismReflection, 0, 2)];
}

namespace {

std::string num(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", x);
    return buf;
}

// A value in the graph: a node's output, an input of the node's interface or a constant.
struct Val {
    std::string type;
    std::string attr; // "nodename", "interfacename" or "value"
    std::string text;
};

// Writes the graph's nodes, one per operation, named n1, n2, ... in order of creation.
class Graph {
  public:
    Val node(const std::string& category, const std::string& type,
             const std::vector<std::pair<std::string, Val>>& inputs) {
        const std::string name = "n" + std::to_string(++count_);
        xml_ += "    <" + category + " name=\"" + name + "\" type=\"" + type + "\">\n";
        for (const auto& [input, v] : inputs) {
            xml_ += "      <input name=\"" + input + "\" type=\"" + v.type + "\" " + v.attr +
                    "=\"" + v.text + "\"/>\n";
            if (v.attr == "interfacename") used_.insert(v.text);
        }
        xml_ += "    </" + category + ">\n";
        return {type, "nodename", name};
    }
    void comment(const std::string& text) { xml_ += "    <!-- " + text + " -->\n"; }
    Val input(const std::string& name, const std::string& type) {
        return {type, "interfacename", name};
    }
    static Val f(double x) { return {"float", "value", num(x)}; }
    static Val grey(double x) {
        return {"color3", "value", num(x) + ", " + num(x) + ", " + num(x)};
    }
    Val op(const std::string& category, const Val& a, const Val& b) {
        return node(category, a.type, {{"in1", a}, {"in2", b}});
    }
    Val add(const Val& a, const Val& b) { return op("add", a, b); }
    Val sub(const Val& a, const Val& b) { return op("subtract", a, b); }
    // A colour or vector first: times a float, MaterialX's FA variant (in2 a float).
    Val mul(const Val& a, const Val& b) { return op("multiply", a, b); }
    Val div(const Val& a, const Val& b) { return op("divide", a, b); }
    Val max(const Val& a, const Val& b) { return op("max", a, b); }
    Val min(const Val& a, const Val& b) { return op("min", a, b); }
    Val sqrt(const Val& a) { return node("sqrt", a.type, {{"in", a}}); }
    Val fn(const std::string& category, const Val& a) {
        return node(category, a.type, {{"in", a}});
    }
    Val dot(const Val& a, const Val& b) {
        return node("dotproduct", "float", {{"in1", a}, {"in2", b}});
    }
    // in1 where value1 >= value2, else in2.
    Val if_ge(const Val& value1, const Val& value2, const Val& in1, const Val& in2) {
        return node("ifgreatereq", in1.type,
                    {{"value1", value1}, {"value2", value2}, {"in1", in1}, {"in2", in2}});
    }
    Val extract(const Val& a, int index) {
        return node("extract", "float",
                    {{"in", a}, {"index", {"integer", "value", std::to_string(index)}}});
    }
    Val clamp(const Val& a, double lo, double hi) {
        return node("clamp", a.type, {{"in", a}, {"low", f(lo)}, {"high", f(hi)}});
    }
    // sum_ij c[i][j] u^i v^j by Horner's rule (in v for each power of u, then in u).
    Val poly(const std::vector<std::vector<double>>& c, const Val& u, const Val& v) {
        Val sum = f(0);
        for (size_t i = c.size(); i-- > 0;) {
            Val q = f(c[i].back());
            for (size_t j = c[i].size() - 1; j-- > 0;)
                q = add(mul(q, v), f(c[i][j]));
            sum = i + 1 == c.size() ? q : add(mul(sum, u), q);
        }
        return sum;
    }
    const std::string& xml() const { return xml_; }
    const std::set<std::string>& used() const { return used_; }

  private:
    int count_ = 0;
    std::string xml_;
    std::set<std::string> used_;
};

const ParamInfo& param(const std::string& name) {
    const ParamInfo* info = find_param(name);
    if (!info) throw std::runtime_error("portable graph: no input '" + name + "' in the table");
    return *info;
}

// A float input clamped into its range, as the node sanitises it (NaN is not detectable with
// standard nodes: the graph's clamp is what MaterialX's clamp does with it).
Val float_input(Graph& g, const std::string& name) {
    const ParamInfo& info = param(name);
    return g.clamp(g.input(name, "float"), info.min_value, info.max_value);
}

Val color_input(Graph& g, const std::string& name) {
    return g.node("clamp", "color3",
                  {{"in", g.input(name, "color3")},
                   {"low", {"color3", "value", "0, 0, 0"}},
                   {"high", {"color3", "value", "1, 1, 1"}}});
}

// Exact unpolarised Fresnel transmittance 1 - F for light from outside (eta >= 1: no total
// internal reflection), with g = eta cos(theta_t) (Walter et al. 2007, Eq. 22).
Val transmittance(Graph& g, const Val& c, const Val& gEta) {
    Val gmc = g.sub(gEta, c);
    Val gpc = g.add(gEta, c);
    Val r1 = g.div(gmc, gpc);
    Val num1 = g.sub(g.mul(c, gpc), Graph::f(1));
    Val den1 = g.add(g.mul(c, gmc), Graph::f(1));
    Val r2 = g.div(num1, den1);
    Val fr = g.mul(g.mul(Graph::f(0.5), g.mul(r1, r1)), g.add(Graph::f(1), g.mul(r2, r2)));
    return g.sub(Graph::f(1), g.clamp(fr, 0, 1));
}

// Declares which inputs reach the graph; throws when one of the table does not and is not a
// listed exception, or when an exception does reach it.
void check_coverage(const Graph& g) {
    std::set<std::string> excepted;
    for (const PortableException& e : portable_exceptions())
        excepted.insert(e.input);
    for (const ParamInfo& info : param_table()) {
        const bool used = g.used().count(info.name) > 0;
        const bool listed = excepted.count(info.name) > 0;
        if (used == listed)
            throw std::runtime_error(std::string("portable graph: input '") + info.name + "' " +
                                     (used ? "is used and listed as an exception"
                                           : "neither reaches the graph nor is a listed "
                                             "exception (portable_exceptions)"));
        excepted.erase(info.name);
    }
    if (!excepted.empty())
        throw std::runtime_error("portable graph: exception '" + *excepted.begin() +
                                 "' is not an input of the parameter table");
}

// in1 of an integer enum input equal to value, else in2 (the standard node ifequal).
Val choose_enum(Graph& g, const Val& input, int value, const Val& yes, const Val& no) {
    return g.node("ifequal", "float",
                  {{"value1", input},
                   {"value2", {"integer", "value", std::to_string(value)}},
                   {"in1", yes},
                   {"in2", no}});
}

// What the prisms return (E) and what passes on to the substrate.
struct PrismShare {
    Val era, passed;
};

// The shading point's values the prisms' closed forms read.
struct Sheet {
    Val n, v, ft, eta, eta2, eta2m1, gEta, cantDeg, metal, metal2, prism;
};

// Internal Fresnel reflectance of an uncoated prism face at `cosine` (rp_fresnel_internal): 1
// beyond the critical angle.
Val fresnel_internal(Graph& g, const Val& cosine, const Sheet& s) {
    const Val& eta = s.eta;
    const Val& eta2 = s.eta2;
    const Val& eta2m1 = s.eta2m1;
    Val ck = g.clamp(cosine, 0, 1);
    Val ck2 = g.mul(ck, ck);
    Val sin2T = g.mul(g.sub(Graph::f(1), ck2), eta2);
    Val cosT = g.sqrt(g.max(g.sub(Graph::f(1), sin2T), Graph::f(0)));
    Val ds = g.add(g.mul(eta, ck), cosT);
    Val dp = g.add(ck, g.mul(eta, cosT));
    Val rs = g.div(eta2m1, g.max(g.mul(ds, ds), Graph::f(1e-30)));
    Val rp = g.div(g.mul(eta2m1, g.sub(eta2, g.mul(ck2, g.add(eta2, Graph::f(1))))),
                   g.max(g.mul(dp, dp), Graph::f(1e-30)));
    Val fr = g.clamp(g.mul(Graph::f(0.5), g.add(g.mul(rs, rs), g.mul(rp, rp))), 0, 1);
    return g.if_ge(sin2T, Graph::f(1), Graph::f(1), fr);
}

// The shading frame's tangent (rp_make_frame): the tangent input made orthogonal to the normal;
// a tangent along the normal, or zero, replaced by the orthogonal unit vector of Duff et al.
// 2017.
Val shading_tangent(Graph& g, const Val& n) {
    Val tangent = g.input("tangent", "vector3");
    Val tp = g.sub(tangent, g.mul(n, g.dot(tangent, n)));
    Val nx = g.extract(n, 0);
    Val ny = g.extract(n, 1);
    Val nz = g.extract(n, 2);
    Val sgn = g.if_ge(nz, Graph::f(0), Graph::f(1), Graph::f(-1));
    Val duffA = g.div(Graph::f(-1), g.add(sgn, nz));
    Val duff = g.node("combine3", "vector3",
                      {{"in1", g.add(Graph::f(1), g.mul(g.mul(sgn, g.mul(nx, nx)), duffA))},
                       {"in2", g.mul(sgn, g.mul(g.mul(nx, ny), duffA))},
                       {"in3", g.mul(g.mul(sgn, nx), Graph::f(-1))}});
    Val ft = g.if_ge(g.mul(g.dot(tangent, tangent), Graph::f(1e-12)), g.dot(tp, tp), duff,
                     g.node("normalize", "vector3", {{"in", tp}}));
    return ft;
}

// era_mode oriented and matched_pair: E of the prisms at their azimuth in closed form, and the
// substrate's share; {oriented, matched pair}.
std::pair<PrismShare, PrismShare> prisms_at_azimuth(Graph& g, const Sheet& s) {
    const Val& n = s.n;
    const Val& v = s.v;
    const Val& eta = s.eta;
    const Val& metal = s.metal;
    const Val& metal2 = s.metal2;
    g.comment("era_mode matched_pair and oriented: E of the prisms at their orientation in closed "
              "form (MODEL.md sections 2 and 8, prism_core.inc's rp_era_canted, "
              "rp_face_reflectances_tir and rp_metal_passed_oriented), for the direction refracted "
              "from V, in the frame of the normal and the tangent");
    const Val& ft = s.ft;
    Val fb = g.node("crossproduct", "vector3", {{"in1", n}, {"in2", ft}});
    Val minusInvEta = g.div(Graph::f(-1), eta);
    Val dx = g.mul(g.dot(v, ft), minusInvEta);
    Val dy = g.mul(g.dot(v, fb), minusInvEta);
    Val dz = g.mul(s.gEta, minusInvEta);
    g.comment("Face normals e_k of the cube at cant_angle, turned by orientation: e_1.xy along the "
              "orientation's vertex, e_2 and e_3 at +-phi2 from it (rp_prepare)");
    const double degree = f64::RP_PI / 180;
    Val rot = g.mul(float_input(g, "orientation"), Graph::f(degree));
    Val cantRad = g.mul(s.cantDeg, Graph::f(degree));
    Val cosCant = g.fn("cos", cantRad);
    Val sinCant = g.fn("sin", cantRad);
    Val z1 = g.add(g.mul(cosCant, Graph::f(f64::RP_INV_SQRT3)),
                   g.mul(sinCant, Graph::f(2 * f64::RP_INV_SQRT6)));
    Val z2 = g.sub(g.mul(cosCant, Graph::f(f64::RP_INV_SQRT3)),
                   g.mul(sinCant, Graph::f(f64::RP_INV_SQRT6)));
    Val xy1 = g.sqrt(g.max(g.sub(Graph::f(1), g.mul(z1, z1)), Graph::f(0)));
    Val xy2 = g.sqrt(g.max(g.sub(Graph::f(1), g.mul(z2, z2)), Graph::f(0)));
    Val cosPhi2 = g.clamp(g.div(g.mul(g.mul(z1, z2), Graph::f(-1)), g.mul(xy1, xy2)), -1.0, 1.0);
    Val phi2Acos = g.fn("acos", cosPhi2);
    g.comment("One Newton step on cos(phi2) after acos, as rp_prepare (a shader's acos may be a "
              "polynomial good to 1e-4)");
    Val phi2 = g.add(phi2Acos, g.div(g.sub(g.fn("cos", phi2Acos), cosPhi2), g.fn("sin", phi2Acos)));
    struct Face {
        Val z, normalPart, along; // e_k.z, e_k.z d.z and e_k.xy . d.xy: d.e_k = normalPart + along
    };
    auto face = [&](const Val& xy, const Val& z, const Val& angle) {
        return Face{z, g.mul(dz, z),
                    g.mul(xy, g.add(g.mul(dx, g.fn("cos", angle)), g.mul(dy, g.fn("sin", angle))))};
    };
    const Face faces[3] = {face(xy1, z1, rot), face(xy2, z2, g.add(rot, phi2)),
                           face(xy2, z2, g.sub(rot, phi2))};
    Val metal3 = g.mul(metal2, metal);
    // One orientation: the prism itself (sign 1) or its matched partner turned by 180 degrees
    // (sign -1: d.xy reversed). m_k = 2 e_k.z (d.e_k) / d.z, l_k = 1 - m_k; A = 1 - sum_k l_k
    // |l_k| when every l_k < 1, else 0.
    auto prismAt = [&](double sign) {
        Val m[3], l[3], r = Graph::f(1), sum = Graph::f(0), lmax = Graph::f(-1e30);
        for (int k = 0; k < 3; ++k) {
            Val de = sign > 0 ? g.add(faces[k].normalPart, faces[k].along)
                              : g.sub(faces[k].normalPart, faces[k].along);
            m[k] = g.div(g.mul(g.mul(faces[k].z, Graph::f(2)), de), dz);
            l[k] = g.sub(Graph::f(1), m[k]);
            sum = g.add(sum, g.mul(l[k], g.fn("absval", l[k])));
            lmax = g.max(lmax, l[k]);
            r = g.mul(r, fresnel_internal(g, g.fn("absval", de), s));
        }
        Val a = g.if_ge(lmax, Graph::f(1), Graph::f(0), g.clamp(g.sub(Graph::f(1), sum), 0, 1));
        Val faceHits = Graph::f(0);
        for (int k = 0; k < 3; ++k) {
            Val sk = g.add(g.max(l[(k + 1) % 3], Graph::f(0)), g.max(l[(k + 2) % 3], Graph::f(0)));
            Val gk = g.if_ge(Graph::f(1), sk, g.sub(Graph::f(1), g.mul(sk, Graph::f(0.5))),
                             g.div(Graph::f(0.5), sk));
            faceHits = g.add(faceHits, g.if_ge(Graph::f(0), m[k], Graph::f(0),
                                               g.mul(g.mul(m[k], Graph::f(2)), gk)));
        }
        Val p2k = g.sub(g.sub(faceHits, Graph::f(1)), g.mul(a, Graph::f(2)));
        Val p1k = g.sub(g.sub(Graph::f(1), a), p2k);
        Val passedMetalK = g.max(g.add(g.mul(metal, p1k), g.mul(metal2, p2k)), Graph::f(0));
        Val e = choose_enum(g, s.prism, 1, g.mul(a, r),
                            choose_enum(g, s.prism, 2, g.mul(a, metal3), a));
        return PrismShare{e, choose_enum(g, s.prism, 2, passedMetalK, g.sub(Graph::f(1), e))};
    };
    const PrismShare oriented = prismAt(1);
    const PrismShare partner = prismAt(-1);
    Val eraPair = g.mul(g.add(oriented.era, partner.era), Graph::f(0.5));
    Val passedPair = g.mul(g.add(oriented.passed, partner.passed), Graph::f(0.5));
    return {oriented, {eraPair, passedPair}};
}

// The sheet's index at the `wavelength` input by abbe_number (prism_core.inc's
// rp_dispersed_ior: the Cauchy law through n_d), ior itself without either.
Val dispersed_ior(Graph& g) {
    Val nD = float_input(g, "ior");
    Val abbe = float_input(g, "abbe_number");
    Val nm = float_input(g, "wavelength");
    g.comment("ior at the wavelength (nm) by the Cauchy law through n_d with n_F - n_C = (n_d - "
              "1) / abbe_number; ior itself when either is 0");
    const double lineD = f64::RP_LINE_D, lineF = f64::RP_LINE_F, lineC = f64::RP_LINE_C;
    const double k = 1.0 / (lineF * lineF) - 1.0 / (lineC * lineC);
    Val b = g.div(g.sub(nD, Graph::f(1)), g.mul(g.max(abbe, Graph::f(1e-6)), Graph::f(k)));
    Val nmFloor = g.max(nm, Graph::f(f64::RP_MIN_WAVELENGTH_NM));
    Val invLam2 = g.div(Graph::f(1e6), g.mul(nmFloor, nmFloor));
    Val n = g.clamp(g.add(nD, g.mul(b, g.sub(invLam2, Graph::f(1.0 / (lineD * lineD))))), 1, 3);
    return g.if_ge(Graph::f(0), abbe, nD, g.if_ge(Graph::f(0), nm, nD, n));
}

// The retro lobe: GGX about V of the model's widths at V (MODEL.md section 3; isotropic
// alpha_o, or alpha_par along the plane of incidence and alpha_perp across it for retro_lobe
// anisotropic), widened by the random dihedral errors, each mapped to GGX by fit_retro_lobe, of
// colour retro_color `weight` scale; with a prism pitch, kDiffractionLobes such lobes, each
// widened by its share of the diffraction pattern (fit_diffraction_lobes), the pattern's widths
// grown by `growth` = A(0) / A.
Val retro_lobe(Graph& g, const Sheet& s, const Val& alpha, const Val& c, const Val& weight,
               const Val& growth) {
    const double minAlpha = f64::RP_MIN_ALPHA;
    g.comment(
        "Retro lobe: GGX about V; alpha_perp = sqrt2 alpha (eta^2 - 1) / (eta cos_t + cos_v), "
        "alpha_par = alpha_perp / cos_v, isotropic alpha_o = alpha_perp / sqrt(cos_v)");
    Val perp = g.div(g.mul(g.mul(alpha, Graph::f(std::sqrt(2.0))), s.eta2m1), g.add(s.gEta, c));
    Val par = g.div(perp, c);
    Val iso = g.div(perp, g.sqrt(c));
    g.comment(
        "Random dihedral errors (dihedral_spread, sigma) add 8 sigma^2 to each width's square "
        "times its magnification squared, (eta cos_t / cos_v)^2 along and eta^2 across; the "
        "isotropic width takes their product, eta^2 cos_t / cos_v (docs/dihedral.md)");
    Val sigma = g.mul(float_input(g, "dihedral_spread"), Graph::f(f64::RP_ARCMIN));
    Val var8 = g.mul(g.mul(sigma, sigma), Graph::f(8));
    Val magPar = g.div(s.gEta, c);
    g.comment(
        "Diffraction at the prisms (prism_pitch in um, 0: none): lobe k adds sigma_k^2 (lambda / "
        "pitch)^2 A(0) / A at `wavelength` (550 nm when 0) to each width's square, divided by "
        "cos_v^2 along the plane of incidence and by cos_v for the isotropic width, and has "
        "weight w_k, both fitted per prism_reflection to the node's pattern at normal incidence "
        "(docs/portable.md); without a pitch one lobe of weight 1");
    Val pitch = float_input(g, "prism_pitch");
    Val nm = float_input(g, "wavelength");
    Val lam = g.if_ge(Graph::f(0), nm, Graph::f(0.55),
                      g.mul(g.max(nm, Graph::f(f64::RP_MIN_WAVELENGTH_NM)), Graph::f(0.001)));
    Val ratio = g.if_ge(Graph::f(0), pitch, Graph::f(0),
                        g.div(lam, g.max(pitch, Graph::f(f64::RP_DIFF_MIN_PITCH_UM))));
    Val ratio2 = g.mul(g.mul(ratio, ratio), growth);
    auto widenAll = [&](const Val& width, const Val& mag2, const Val& diff2) {
        return g.sqrt(g.add(g.add(g.mul(width, width), g.mul(var8, mag2)), diff2));
    };
    Val lobe = g.input("retro_lobe", "integer");
    auto ggx = [&](const Val& width, const Val& isotropic) {
        Val w = choose_enum(g, lobe, 1, width, isotropic);
        return g.clamp(g.mul(g.max(w, Graph::f(minAlpha)), Graph::f(0.5 * fit_retro_lobe().width)),
                       minAlpha, 1.0);
    };
    g.comment("The lobe's tangent along the plane of incidence, N less its part along V (at normal "
              "incidence, where the widths agree, the shading tangent)");
    Val inPlane = g.sub(s.n, g.mul(s.v, g.dot(s.n, s.v)));
    Val tangent = g.if_ge(Graph::f(1e-12), g.dot(inPlane, inPlane), s.ft,
                          g.node("normalize", "vector3", {{"in", inPlane}}));
    Val tint =
        g.mul(color_input(g, "retro_color"), g.mul(weight, Graph::f(fit_retro_lobe().scale)));
    auto perPrism = [&](auto value) {
        return choose_enum(g, s.prism, 1, Graph::f(value(fit_diffraction_lobes(1))),
                           choose_enum(g, s.prism, 2, Graph::f(value(fit_diffraction_lobes(2))),
                                       Graph::f(value(fit_diffraction_lobes(0)))));
    };
    Val sum;
    for (int k = 0; k < kDiffractionLobes; ++k) {
        Val sigma2 =
            perPrism([k](const DiffractionLobesFit& f) { return f.sigma[k] * f.sigma[k]; });
        Val var2 = g.mul(ratio2, sigma2);
        Val isoW = widenAll(iso, g.div(g.mul(s.eta, s.gEta), c), g.div(var2, c));
        Val parW = widenAll(par, g.mul(magPar, magPar), g.div(var2, g.mul(c, c)));
        Val perpW = widenAll(perp, s.eta2, var2);
        Val share = g.if_ge(Graph::f(0), pitch, Graph::f(k == 0 ? 1.0 : 0.0),
                            perPrism([k](const DiffractionLobesFit& f) { return f.weight[k]; }));
        Val bsdf =
            g.node("generalized_schlick_bsdf", "BSDF",
                   {{"weight", share},
                    {"color0", tint},
                    {"color82", tint},
                    {"color90", tint},
                    {"roughness", g.node("combine2", "vector2",
                                         {{"in1", ggx(parW, isoW)}, {"in2", ggx(perpW, isoW)}})},
                    {"normal", s.v},
                    {"tangent", tangent},
                    {"scatter_mode", {"string", "value", "R"}}});
        sum = k == 0 ? bsdf : g.add(sum, bsdf);
    }
    return sum;
}

// The diffraction lobes' fits for the graph's header comment.
std::string diffraction_fits_text() {
    const char* names[3] = {"ideal", "tir", "metallized"};
    std::string text;
    for (int prism = 0; prism < 3; ++prism) {
        const DiffractionLobesFit& f = fit_diffraction_lobes(prism);
        text += std::string(prism ? ";\n       " : "") + names[prism] +
                " prisms: GGX lobes of weights " + num(f.weight[0]) + ", " + num(f.weight[1]) +
                " and widths " + num(f.sigma[0]) + ", " + num(f.sigma[1]) +
                " lambda / pitch, largest error in ln " + num(f.max_error) + " over nu " +
                num(kDiffractionFitLo) + "-" + num(kDiffractionFitHi);
    }
    return text;
}

} // namespace

std::string generate_portable_nodegraph() {
    Graph g;
    const double minCos = f64::RP_MIN_COS;
    const double minAlpha = f64::RP_MIN_ALPHA;
    g.comment("The view direction V (toward the viewer) and cos(theta_v) = |N.V|");
    Val view = g.node("viewdirection", "vector3", {{"space", {"string", "value", "world"}}});
    Val v = g.mul(view, Graph::f(-1));
    Val n = g.node("normalize", "vector3", {{"in", g.input("normal", "vector3")}});
    Val c = g.clamp(g.node("absval", "float",
                           {{"in", g.node("dotproduct", "float", {{"in1", n}, {"in2", v}})}}),
                    minCos, 1.0);
    g.comment("Sheet: eta, eta cos(theta_t), sin(theta_t), T(cos_v)");
    Val weight = float_input(g, "weight");
    Val eta = dispersed_ior(g);
    Val eta2 = g.mul(eta, eta);
    Val c2 = g.mul(c, c);
    Val eta2m1 = g.sub(eta2, Graph::f(1));
    Val gEta = g.sqrt(g.max(g.add(eta2m1, c2), Graph::f(0)));
    Val sinT = g.div(g.sqrt(g.max(g.sub(Graph::f(1), c2), Graph::f(0))), eta);
    Val trans = transmittance(g, c, gEta);
    Val trans2 = g.mul(trans, trans);
    g.comment("A: the averaged ERA of ideal prisms, fitted in (sin theta_t, cant_angle)");
    Val u = g.sub(g.mul(sinT, Graph::f(2)), Graph::f(1));
    Val cantDeg = float_input(g, "cant_angle");
    Val cant = g.div(cantDeg, Graph::f(kCantRange));
    Val area = g.clamp(g.poly(fit_era().coef, u, cant), 0, 1);
    g.comment("Uncoated prisms: E = A Q, Q fitted in eta and the tilt beyond the onset of partial "
              "reflection, asin(sin theta_t) + asin(1 / eta) - acos(1 / sqrt3), as a fraction of "
              "its span 2 asin(1 / eta) - acos(1 / sqrt3)");
    Val critical = g.node("asin", "float", {{"in", g.div(Graph::f(1), eta)}});
    Val tilt =
        g.max(g.sub(g.add(g.node("asin", "float", {{"in", g.min(sinT, Graph::f(1))}}), critical),
                    Graph::f(kCubeFaceAngle)),
              Graph::f(0));
    Val span =
        g.max(g.sub(g.mul(critical, Graph::f(2)), Graph::f(kCubeFaceAngle)), Graph::f(kTirMinSpan));
    Val uTir = g.sub(g.mul(g.min(g.div(tilt, span), Graph::f(1)), Graph::f(2)), Graph::f(1));
    Val eraTir =
        g.mul(area, g.clamp(g.poly(fit_tir_ratio().coef, uTir, g.sub(eta, Graph::f(2))), 0, 1));
    g.comment(
        "Metallized prisms: E = A R^3; the substrate receives R P1 + R^2 P2, P2 = H - 1 - 2A, "
        "P1 = 1 - A - P2, H the faces a ray meets (fitted for the uncanted cube)");
    Val metal = float_input(g, "metal_reflectance");
    Val metal2 = g.mul(metal, metal);
    Val eraMetal = g.mul(area, g.mul(metal2, metal));
    Val hits = g.poly(fit_metal_hits().coef, u, Graph::f(0));
    Val p2 = g.max(g.sub(g.sub(hits, Graph::f(1)), g.mul(area, Graph::f(2))), Graph::f(0));
    Val p1 = g.max(g.sub(g.sub(Graph::f(1), area), p2), Graph::f(0));
    Val passedMetal = g.add(g.mul(metal, p1), g.mul(metal2, p2));
    g.comment("prism_reflection (an integer enum: 0 ideal, 1 tir, 2 metallized) chooses E and the "
              "fraction that reaches the substrate");
    Val prism = g.input("prism_reflection", "integer");
    auto choose = [&](int value, const Val& yes, const Val& no) {
        return choose_enum(g, prism, value, yes, no);
    };
    Val eraAveraged = choose(1, eraTir, choose(2, eraMetal, area));
    Val passedAveraged = choose(2, passedMetal, g.sub(Graph::f(1), eraAveraged));
    const Sheet sheet{n,      v,    shading_tangent(g, n), eta, eta2, eta2m1, gEta, cantDeg, metal,
                      metal2, prism};
    const auto [oriented, pair] = prisms_at_azimuth(g, sheet);
    g.comment("era_mode (an integer enum: 0 averaged, 1 matched_pair, 2 oriented; another value "
              "counts as averaged, the node's default) chooses E and the substrate's fraction");
    Val eraMode = g.input("era_mode", "integer");
    auto chooseMode = [&](int value, const Val& yes, const Val& no) {
        return choose_enum(g, eraMode, value, yes, no);
    };
    Val era = chooseMode(1, pair.era, chooseMode(2, oriented.era, eraAveraged));
    Val passed = chooseMode(1, pair.passed, chooseMode(2, oriented.passed, passedAveraged));
    g.comment("Surface lobe: dielectric_bsdf, GGX of the Beckmann roughness");
    Val alpha = g.max(float_input(g, "roughness"), Graph::f(minAlpha));
    Val alpha2 = g.node("combine2", "vector2", {{"in1", alpha}, {"in2", alpha}});
    Val surface = g.node("dielectric_bsdf", "BSDF",
                         {{"weight", g.mul(weight, float_input(g, "specular"))},
                          {"ior", eta},
                          {"roughness", alpha2},
                          {"normal", n},
                          {"scatter_mode", {"string", "value", "R"}}});
    g.comment(
        "The diffraction pattern's growth off normal incidence: A(0) / A, A the ideal prisms' "
        "averaged ERA (the aperture's area)");
    Val area0 = g.clamp(g.poly(fit_era().coef, Graph::f(-1), cant), 0, 1);
    Val growth = g.div(area0, g.max(area, Graph::f(kMinGrowthArea)));
    Val retro = retro_lobe(g, sheet, alpha, c, g.mul(weight, g.mul(era, trans2)), growth);
    g.comment("Diffuse lobe: Lambert of k_d T^2 passed / (eta^2 (1 - k_d F_dr(eta))), passed = 1 - "
              "E (metallized: R P1 + R^2 P2)");
    Val kd = color_input(g, "diffuse_color");
    Val fdr = g.clamp(g.poly(fit_fdr().coef, g.sub(eta, Graph::f(2)), Graph::f(0)), 0, 1);
    Val denom = g.mul(g.sub(Graph::grey(1), g.mul(kd, fdr)), eta2);
    Val diffuseColor = g.mul(g.div(kd, denom), g.mul(weight, g.mul(trans2, passed)));
    Val diffuse = g.node("oren_nayar_diffuse_bsdf", "BSDF",
                         {{"color", diffuseColor}, {"roughness", Graph::f(0)}, {"normal", n}});
    Val sum = g.add(g.add(surface, retro), diffuse);
    check_coverage(g);
    const PolyFit& e = fit_era();
    const PolyFit& t = fit_tir_ratio();
    const PolyFit& h = fit_metal_hits();
    const PolyFit& d = fit_fdr();
    const RetroLobeFit& r = fit_retro_lobe();
    return "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n"
           "  <!-- Generated by retroprism_glsl_gen (glsl_gen/portable.cpp) from the parameter "
           "table and fits\n"
           "       of the C++ model; do not edit. The portable implementation of the node from "
           "standard nodes,\n"
           "       chosen by MaterialX for every target without an implementation of the node "
           "(OSL, MDL);\n"
           "       approximations and the inputs it does not honour: docs/portable.md.\n"
           "       Fits: ERA of ideal prisms in (sin theta_t, cant), degree " +
           std::to_string(kEraDegreeSin) + " x " + std::to_string(kEraDegreeCant) +
           ", largest error " + num(e.max_error) + " (RMS " + num(e.rms_error) +
           ");\n"
           "       ERA of uncoated prisms A Q, Q in (onset tilt, eta), degree " +
           std::to_string(kTirDegreeY) + " x " + std::to_string(kTirDegreeEta) +
           ", eta in [1, 3] " + "weighted " + num(kTirWeight) + " in [" + num(kTirWeightLo) + ", " +
           num(kTirWeightHi) + "]:\n       largest error of E " + num(t.max_error) + " (RMS " +
           num(t.rms_error) + "), largest relative error " + num(t.max_rel_error) +
           " where weighted (entrance <= 45 deg);\n"
           "       metallized faces met H(sin theta_t), degree " +
           std::to_string(kHitsDegree) + ", largest error " + num(h.max_error) +
           ";\n"
           "       F_dr(eta), degree " +
           std::to_string(kFdrDegree) + ", largest error " + num(d.max_error) +
           "; retro lobe: GGX of width " + num(r.width) + " alpha_o / 2, scale " + num(r.scale) +
           ",\n       largest relative error " + num(r.max_error) +
           " within 1/e of the peak;\n       diffraction: " + diffraction_fits_text() +
           ". -->\n"
           "  <nodegraph name=\"NG_rp_prismatic_retroreflector_bsdf\" "
           "nodedef=\"ND_rp_prismatic_retroreflector_bsdf\">\n" +
           g.xml() + "    <output name=\"out\" type=\"BSDF\" nodename=\"" + sum.text +
           "\"/>\n  </nodegraph>\n</materialx>\n";
}

} // namespace retroprism::glsl
