#include "portable.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>

#include "prismatic_retroreflector.h"

namespace retroprism::glsl {

namespace {

// Degrees of the fits: enough that the fit error is far below the graph's other approximations
// (the figures are printed in the generated file and docs/portable.md).
constexpr int kEraDegreeSin = 14;
constexpr int kEraDegreeCant = 6;
constexpr int kFdrDegree = 10;
constexpr double kCantRange = 30.0; // cant_angle's range, degrees (the parameter table's)

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

double poly2(const std::vector<std::vector<double>>& c, double u, double v) {
    double sum = 0;
    for (size_t i = c.size(); i-- > 0;) {
        double q = 0;
        for (size_t j = c[i].size(); j-- > 0;)
            q = q * v + c[i][j];
        sum = sum * u + q;
    }
    return sum;
}

// Fits f(u, v) on the grid us x vs with degrees (du, dv).
PolyFit fit2(const std::vector<double>& us, const std::vector<double>& vs, int du, int dv,
             const std::function<double(double, double)>& f) {
    std::vector<std::vector<double>> rows;
    std::vector<double> values;
    for (double u : us)
        for (double v : vs) {
            std::vector<double> row;
            for (int i = 0; i <= du; ++i)
                for (int j = 0; j <= dv; ++j)
                    row.push_back(std::pow(u, i) * std::pow(v, j));
            rows.push_back(row);
            values.push_back(f(u, v));
        }
    const std::vector<double> x = least_squares(rows, values);
    PolyFit fit;
    fit.coef.assign(size_t(du + 1), std::vector<double>(size_t(dv + 1)));
    for (int i = 0; i <= du; ++i)
        for (int j = 0; j <= dv; ++j)
            fit.coef[size_t(i)][size_t(j)] = x[size_t(i * (dv + 1) + j)];
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
        {"prism_reflection",
         "a string enum: no standard node of MaterialX 1.39 reads a string's value (string inputs "
         "connect only to string inputs, and there is no string comparison), so the graph keeps "
         "the default, ideal prisms"},
        {"metal_reflectance", "used only by prism_reflection = metallized (see prism_reflection)"},
        {"era_mode", "a string enum (see prism_reflection): the graph keeps the default, the "
                     "azimuth-averaged ERA"},
        {"orientation", "the prisms' azimuth matters only for era_mode matched_pair and oriented"},
        {"tangent", "the reference azimuth of orientation (see orientation)"},
        {"retro_lobe", "a string enum (see prism_reflection): the graph keeps the default, the "
                       "isotropic lobe"},
        {"fidelity", "a string enum (see prism_reflection); the graph is one approximation tier"},
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
    Val eta = float_input(g, "ior");
    Val eta2 = g.mul(eta, eta);
    Val c2 = g.mul(c, c);
    Val gEta = g.sqrt(g.max(g.add(g.sub(eta2, Graph::f(1)), c2), Graph::f(0)));
    Val sinT = g.div(g.sqrt(g.max(g.sub(Graph::f(1), c2), Graph::f(0))), eta);
    Val trans = transmittance(g, c, gEta);
    Val trans2 = g.mul(trans, trans);
    g.comment("E: the averaged ERA of ideal prisms, fitted in (sin theta_t, cant_angle)");
    Val u = g.sub(g.mul(sinT, Graph::f(2)), Graph::f(1));
    Val cant = g.div(float_input(g, "cant_angle"), Graph::f(kCantRange));
    Val era = g.clamp(g.poly(fit_era().coef, u, cant), 0, 1);
    g.comment("Surface lobe: dielectric_bsdf, GGX of the Beckmann roughness");
    Val alpha = g.max(float_input(g, "roughness"), Graph::f(minAlpha));
    Val alpha2 = g.node("combine2", "vector2", {{"in1", alpha}, {"in2", alpha}});
    Val surface = g.node("dielectric_bsdf", "BSDF",
                         {{"weight", g.mul(weight, float_input(g, "specular"))},
                          {"ior", eta},
                          {"roughness", alpha2},
                          {"normal", n},
                          {"scatter_mode", {"string", "value", "R"}}});
    g.comment("Retro lobe: GGX about V, alpha_o = sqrt2 alpha (eta^2 - 1) / ((eta cos_t + cos_v) "
              "sqrt(cos_v))");
    Val alphaRough = g.div(g.mul(g.mul(alpha, Graph::f(std::sqrt(2.0))), g.sub(eta2, Graph::f(1))),
                           g.mul(g.add(gEta, c), g.sqrt(c)));
    g.comment("Random dihedral errors (dihedral_spread, sigma): alpha_o^2 + 8 sigma^2 eta^2 cos_t "
              "/ cos_v, the product of the node's two widenings (docs/dihedral.md) on one width");
    Val sigma = g.mul(float_input(g, "dihedral_spread"), Graph::f(f64::RP_ARCMIN));
    Val alphaO =
        g.sqrt(g.add(g.mul(alphaRough, alphaRough),
                     g.div(g.mul(g.mul(g.mul(sigma, sigma), Graph::f(8)), g.mul(eta, gEta)), c)));
    Val alphaG =
        g.clamp(g.mul(g.max(alphaO, Graph::f(minAlpha)), Graph::f(0.5 * fit_retro_lobe().width)),
                minAlpha, 1.0);
    Val retroTint =
        g.mul(color_input(g, "retro_color"),
              g.mul(g.mul(weight, Graph::f(fit_retro_lobe().scale)), g.mul(era, trans2)));
    Val retro =
        g.node("generalized_schlick_bsdf", "BSDF",
               {{"color0", retroTint},
                {"color82", retroTint},
                {"color90", retroTint},
                {"roughness", g.node("combine2", "vector2", {{"in1", alphaG}, {"in2", alphaG}})},
                {"normal", v},
                {"scatter_mode", {"string", "value", "R"}}});
    g.comment("Diffuse lobe: Lambert of k_d T^2 (1 - E) / (eta^2 (1 - k_d F_dr(eta)))");
    Val kd = color_input(g, "diffuse_color");
    Val fdr = g.clamp(g.poly(fit_fdr().coef, g.sub(eta, Graph::f(2)), Graph::f(0)), 0, 1);
    Val denom = g.mul(g.sub(Graph::grey(1), g.mul(kd, fdr)), eta2);
    Val diffuseColor =
        g.mul(g.div(kd, denom), g.mul(weight, g.mul(trans2, g.sub(Graph::f(1), era))));
    Val diffuse = g.node("oren_nayar_diffuse_bsdf", "BSDF",
                         {{"color", diffuseColor}, {"roughness", Graph::f(0)}, {"normal", n}});
    Val sum = g.add(g.add(surface, retro), diffuse);
    check_coverage(g);
    const PolyFit& e = fit_era();
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
           "       F_dr(eta), degree " +
           std::to_string(kFdrDegree) + ", largest error " + num(d.max_error) +
           "; retro lobe: GGX of width " + num(r.width) + " alpha_o / 2, scale " + num(r.scale) +
           ",\n       largest relative error " + num(r.max_error) +
           " within 1/e of the peak. -->\n"
           "  <nodegraph name=\"NG_rp_prismatic_retroreflector_bsdf\" "
           "nodedef=\"ND_rp_prismatic_retroreflector_bsdf\">\n" +
           g.xml() + "    <output name=\"out\" type=\"BSDF\" nodename=\"" + sum.text +
           "\"/>\n  </nodegraph>\n</materialx>\n";
}

} // namespace retroprism::glsl
