#include "ra_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>

#include "error.h"
#include "minimize.h"
#include "photometry.h"

namespace retroprism {

namespace {

// One continuous input of a search: its range, scale and how it is set.
struct Var {
    double lo = 0, hi = 1;
    bool log = false;
    double start = 0; // the base value
    std::function<void(double)> set;
};

double sigmoid(double u) {
    return 1.0 / (1.0 + std::exp(-u));
}

double value_of(const Var& v, double u) {
    const double t = sigmoid(u);
    return v.log ? std::exp(std::log(v.lo) + t * (std::log(v.hi) - std::log(v.lo)))
                 : v.lo + t * (v.hi - v.lo);
}

// The logistic coordinate of a value, kept 1e-3 of the range inside it.
double coordinate_of(const Var& v, double x) {
    const double a = v.log ? std::log(v.lo) : v.lo, b = v.log ? std::log(v.hi) : v.hi;
    const double y = v.log ? std::log(std::max(x, 1e-300)) : x;
    const double t = std::clamp((y - a) / (b - a), 1e-3, 1.0 - 1e-3);
    return std::log(t / (1.0 - t));
}

// Six significant digits, as a document written from the value reads it back.
double round6(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return std::strtod(buf, nullptr);
}

void set_all(const std::vector<Var>& vars, const std::vector<double>& u, bool rounded) {
    for (size_t k = 0; k < vars.size(); ++k) {
        const double x = value_of(vars[k], u[k]);
        vars[k].set(rounded ? round6(x) : x);
    }
}

// Minimises cost() over the vars (each set before a call) by Nelder-Mead in logistic
// coordinates: from the base values, the centre, and the centre with each coordinate moved to
// either side; then restarted from the best until it improves by less than 1e-9 relative.
NmResult search(const std::vector<Var>& vars, const std::function<double()>& cost) {
    const size_t n = vars.size();
    auto f = [&](const std::vector<double>& u) {
        set_all(vars, u, false);
        return cost();
    };
    if (n == 0) {
        NmResult r;
        r.f = cost();
        r.evaluations = 1;
        return r;
    }
    std::vector<std::vector<double>> starts;
    std::vector<double> base(n), centre(n, 0.0);
    for (size_t k = 0; k < n; ++k)
        base[k] = coordinate_of(vars[k], vars[k].start);
    starts.push_back(base);
    starts.push_back(centre);
    for (size_t k = 0; k < n; ++k)
        for (double side : {-2.0, 2.0}) {
            std::vector<double> s = centre;
            s[k] = side;
            starts.push_back(s);
        }
    const int maxEval = 150 + 100 * int(n);
    NmResult best;
    int evals = 0;
    for (const std::vector<double>& s : starts) {
        const NmResult r = nelder_mead(f, s, 0.7, maxEval);
        evals += r.evaluations;
        if (r.f < best.f) best = r;
    }
    for (int restart = 0; restart < 4; ++restart) {
        const NmResult r = nelder_mead(f, best.x, 0.3, maxEval);
        evals += r.evaluations;
        const bool better = r.f < best.f * (1.0 - 1e-9);
        if (r.f < best.f) best = r;
        if (!better) break;
    }
    best.evaluations = evals;
    return best;
}

double log_cost(const RaMeasurements& t, const std::vector<double>& model) {
    double sum = 0;
    for (size_t i = 0; i < model.size(); ++i) {
        const double r = std::log(std::max(model[i], 1e-300)) - std::log(t.entries[i].ra);
        sum += r * r;
    }
    return sum / double(std::max<size_t>(model.size(), 1));
}

void require_rows(const RaMeasurements& t, const std::vector<std::string>& fitted) {
    if (t.entries.size() >= fitted.size()) return;
    std::string names;
    for (const std::string& s : fitted)
        names += (names.empty() ? "" : ", ") + s;
    throw InputError(t.file + ": " + std::to_string(t.entries.size()) + " rows, fewer than the " +
                     std::to_string(fitted.size()) + " inputs fitted (" + names +
                     "); give at least " + std::to_string(fitted.size()) + " rows");
}

// The node's continuous fitted inputs as Vars setting `p`, and its discrete ones (the number
// of values and how to set the i-th).
struct Choice {
    int count = 0;
    std::function<void(int)> set;
};

void node_search_space(Params& p, std::vector<Var>& vars, std::vector<Choice>& choices,
                       std::vector<std::string>& fitted) {
    for (const FitInfo& f : fit_table()) {
        const ParamInfo& info = *f.param;
        fitted.push_back(info.name);
        if (f.scale == FitScale::Choice) {
            Choice c;
            if (info.type == ParamType::Enum) {
                int* field = input_field<int>(p, info.name);
                c.count = int(enum_values(info).size());
                c.set = [field](int i) { *field = i; };
            } else {
                bool* field = input_field<bool>(p, info.name);
                c.count = 2;
                c.set = [field](int i) { *field = i != 0; };
            }
            choices.push_back(c);
            continue;
        }
        Var v;
        v.lo = f.lo;
        v.hi = f.hi;
        v.log = f.scale == FitScale::Log;
        if (info.type == ParamType::Color) {
            Color3* field = input_field<Color3>(p, info.name);
            v.start = luminance_709(glm::dvec3((*field)[0], (*field)[1], (*field)[2]));
            v.set = [field](double x) { *field = {x, x, x}; };
        } else {
            double* field = input_field<double>(p, info.name);
            v.start = *field;
            v.set = [field](double x) { *field = x; };
        }
        vars.push_back(v);
    }
}

} // namespace

std::vector<double> ra_node_values(const Params& material, const std::vector<RaEntry>& entries) {
    const PrismaticRetroreflector<double> node(ra_params(material));
    std::vector<double> v;
    for (const RaEntry& e : entries)
        v.push_back(ra_at_entry(node, e));
    return v;
}

std::vector<double> ra_mrm_values(const baselines::RetroreflectiveGGX& m,
                                  const std::vector<RaEntry>& entries) {
    std::vector<double> v;
    for (const RaEntry& e : entries)
        v.push_back(ra_at_entry(
            e, [&](double entrance, double observation, double rotation, double presentation) {
                glm::dvec3 wi, wo;
                ra_directions(entrance, observation, rotation, wi, wo, presentation);
                return m.f(wi, wo) * (wi.z * wo.z);
            }));
    return v;
}

RaFitReport ra_fit_report(const RaMeasurements& t, const std::vector<double>& model) {
    RaFitReport r;
    r.model = model;
    for (size_t i = 0; i < model.size(); ++i) {
        const double y = t.entries[i].ra;
        r.error.push_back((model[i] - y) / y);
        r.max_error = std::max(r.max_error, std::abs(r.error.back()));
    }
    r.log_rms = std::sqrt(log_cost(t, model));
    return r;
}

RaNodeFit fit_ra_node(const RaMeasurements& t, const Params& base) {
    Params p = base;
    std::vector<Var> vars;
    std::vector<Choice> choices;
    RaNodeFit fit;
    node_search_space(p, vars, choices, fit.fitted);
    require_rows(t, fit.fitted);
    auto cost = [&] { return log_cost(t, ra_node_values(p, t.entries)); };
    // Every combination of the discrete inputs, a search of the continuous ones for each.
    size_t combinations = 1;
    for (const Choice& c : choices)
        combinations *= size_t(c.count);
    double bestCost = std::numeric_limits<double>::infinity();
    Params best = p;
    for (size_t k = 0; k < combinations; ++k) {
        size_t rest = k;
        for (const Choice& c : choices) {
            c.set(int(rest % size_t(c.count)));
            rest /= size_t(c.count);
        }
        for (Var& v : vars) // every combination starts from the base values
            v.set(v.start);
        const NmResult r = search(vars, cost);
        fit.evaluations += r.evaluations;
        set_all(vars, r.x, true);
        // Values that fit alike (metallized is ideal with a darker retro_color): the first.
        const double c = cost();
        if (c < bestCost * (1.0 - 1e-6)) {
            bestCost = c;
            best = p;
        }
    }
    fit.params = best;
    fit.report = ra_fit_report(t, ra_node_values(best, t.entries));
    return fit;
}

RaMrmFit fit_ra_mrm(const RaMeasurements& t) {
    RaMrmFit fit;
    baselines::RetroreflectiveGGX m;
    std::vector<Var> vars(3);
    vars[0] = {1e-4, 1.0, true, m.roughness, [&](double x) { m.roughness = x; }};
    vars[1] = {1.01, 3.0, false, m.ior, [&](double x) { m.ior = x; }};
    vars[2] = {0.0, 1.0, false, m.specular, [&](double x) { m.specular = x; }};
    require_rows(t, {"roughness", "ior", "specular"});
    const NmResult r = search(vars, [&] { return log_cost(t, ra_mrm_values(m, t.entries)); });
    set_all(vars, r.x, true);
    fit.model = m;
    fit.evaluations = r.evaluations;
    fit.report = ra_fit_report(t, ra_mrm_values(m, t.entries));
    return fit;
}

} // namespace retroprism
