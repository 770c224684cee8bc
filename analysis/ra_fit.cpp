#include "ra_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <stdexcept>

#include "error.h"
#include "minimize.h"
#include "photometry.h"

namespace retroprism {

namespace {

// One continuous input of a search: its box, its base value and how it is set.
struct Var {
    BoxVar box;
    double start = 0; // the base value
    std::function<void(double)> set;
};

// Six significant digits, as a document written from the value reads it back.
double round6(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return std::strtod(buf, nullptr);
}

// x rounded to 6 significant digits, and to the box's bound when within 1e-6 of its range of it
// (a logistic coordinate far out reaches a bound only in the limit: 2e-225 for a bound of 0,
// which no float of a document holds).
double round_in_box(double x, const BoxVar& box) {
    const double tolerance = 1e-6 * (box.hi - box.lo);
    if (std::abs(x - box.lo) <= tolerance) return box.lo;
    if (std::abs(x - box.hi) <= tolerance) return box.hi;
    return round6(x);
}

void set_all(const std::vector<Var>& vars, const std::vector<double>& x, bool rounded) {
    for (size_t k = 0; k < vars.size(); ++k)
        vars[k].set(rounded ? round_in_box(x[k], vars[k].box) : x[k]);
}

// Minimises cost() over the vars (each set before a call) by search_box (util/minimize.h) from
// its usual starts: the base values, the centre, and the centre moved to either side along
// each coordinate.
NmResult search(const std::vector<Var>& vars, const std::function<double()>& cost) {
    std::vector<BoxVar> box;
    std::vector<double> base;
    for (const Var& v : vars) {
        box.push_back(v.box);
        base.push_back(v.start);
    }
    auto f = [&](const std::vector<double>& x) {
        set_all(vars, x, false);
        return cost();
    };
    return search_box(f, box, box_starts(box, base), 150 + 100 * int(vars.size()));
}

// The objective's cost of `model` against the table (ra_fit.h): the mean square of
// ln(model / measured), its largest square, or the largest square of model / measured - 1.
double ra_cost(const RaMeasurements& t, const std::vector<double>& model,
               RaObjective objective = RaObjective::Rms) {
    double sum = 0, largest = 0;
    for (size_t i = 0; i < model.size(); ++i) {
        const double m = std::max(model[i], 1e-300);
        const double r = objective == RaObjective::Relative
                             ? m / t.entries[i].ra - 1
                             : std::log(m) - std::log(t.entries[i].ra);
        sum += r * r;
        largest = std::max(largest, r * r);
    }
    if (objective != RaObjective::Rms) return largest;
    return sum / double(std::max<size_t>(model.size(), 1));
}

// search() for `objective`: the least-squares search, and for the minimax objectives, whose
// cost has corners the simplex can stall on, a second search from the least-squares inputs,
// kept only where its inputs as rounded (round_in_box) cost less than the least-squares ones:
// a start on a bound enters the search a little inside it (search_box's logistic coordinates),
// where the minimax cost can be higher than at the bound. cost(o) is the cost under objective o
// of the inputs as set. Evaluations of both searches.
NmResult search_for(std::vector<Var> vars, RaObjective objective,
                    const std::function<double(RaObjective)>& cost) {
    const NmResult squares = search(vars, [&] { return cost(RaObjective::Rms); });
    if (objective == RaObjective::Rms) return squares;
    for (size_t i = 0; i < vars.size(); ++i)
        vars[i].start = squares.x[i];
    NmResult r = search(vars, [&] { return cost(objective); });
    r.evaluations += squares.evaluations;
    set_all(vars, squares.x, true);
    const double start = cost(objective);
    set_all(vars, r.x, true);
    if (!(cost(objective) < start)) r.x = squares.x;
    return r;
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

void node_search_space(Params& p, const std::vector<std::string>& held, std::vector<Var>& vars,
                       std::vector<Choice>& choices, std::vector<std::string>& fitted) {
    std::string fittable;
    for (const FitInfo& f : fit_table())
        fittable += std::string(fittable.empty() ? "" : ", ") + f.param->name;
    for (const std::string& name : held) {
        bool known = false;
        for (const FitInfo& f : fit_table())
            known = known || f.param->name == name;
        if (!known)
            throw InputError("--hold " + name +
                             ": not a fitted input (the fitted inputs: " + fittable + ")");
    }
    for (const FitInfo& f : fit_table()) {
        const ParamInfo& info = *f.param;
        if (std::find(held.begin(), held.end(), info.name) != held.end()) continue;
        // A base without a pitch is geometric optics, and stays so.
        if (std::string(info.name) == "prism_pitch" && !(p.prism_pitch > 0)) continue;
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
        v.box = {f.lo, f.hi, f.scale == FitScale::Log};
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

// The fitted range of retro_color (its RP_FIT line).
const FitInfo& retro_color_fit() {
    for (const FitInfo& f : fit_table())
        if (std::string(f.param->name) == "retro_color") return f;
    throw std::logic_error("the parameter table fits no retro_color");
}

// retro_color = s chroma with s such that the mean of ln(model / measured) over `rows` is 0
// (objective max: the mean of its largest and smallest; relative: the largest and smallest
// model / measured equally far from 1), each channel kept in the fitted range
// and rounded to 6 digits (ra_fit.h, step 2).
Color3 scaled_retro_color(Params p, const Color3& chroma, const RaMeasurements& rows,
                          RaObjective objective, RaSpectrum spectrum) {
    const FitInfo& range = retro_color_fit();
    double s = luminance_709(glm::dvec3(p.retro_color[0], p.retro_color[1], p.retro_color[2]));
    auto set = [&](double scale) {
        for (int c = 0; c < 3; ++c)
            p.retro_color[size_t(c)] =
                round6(std::clamp(scale * chroma[size_t(c)], range.lo, range.hi));
    };
    for (int iteration = 0; iteration < 30; ++iteration) {
        set(s);
        const std::vector<double> model = ra_node_values(p, rows.entries, spectrum);
        double mean = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (size_t i = 0; i < model.size(); ++i) {
            const double r = std::log(std::max(model[i], 1e-300) / rows.entries[i].ra);
            mean += r;
            lo = std::min(lo, r);
            hi = std::max(hi, r);
        }
        mean /= double(model.size());
        if (objective == RaObjective::Max) mean = 0.5 * (lo + hi);
        // exp(hi) s' - 1 = 1 - exp(lo) s': the largest and smallest ratio equally far from 1.
        if (objective == RaObjective::Relative)
            mean = std::log(0.5 * (std::exp(lo) + std::exp(hi)));
        s *= std::exp(-mean);
        if (std::abs(mean) < 1e-9) break;
    }
    set(s);
    return p.retro_color;
}

// chroma_C of ra_fit.h's step 2: the base's hue at luminance 1 when `hue`, else (1, 1, 1).
Color3 color_chroma(bool hue, const Params& base) {
    const glm::dvec3 c(base.retro_color[0], base.retro_color[1], base.retro_color[2]);
    const double y = luminance_709(c);
    if (!hue || !(y > 0)) return {1.0, 1.0, 1.0};
    return {c.x / y, c.y / y, c.z / y};
}

} // namespace

RaObjective ra_objective(const std::string& name) {
    if (name == "rms") return RaObjective::Rms;
    if (name == "max") return RaObjective::Max;
    if (name == "relative") return RaObjective::Relative;
    throw InputError("--objective " + name + ": not one of rms, max, relative");
}

const char* ra_objective_name(RaObjective objective) {
    switch (objective) {
    case RaObjective::Max:
        return "max";
    case RaObjective::Relative:
        return "relative";
    case RaObjective::Rms:
        break;
    }
    return "rms";
}

std::vector<double> ra_node_values(const Params& material, const std::vector<RaEntry>& entries,
                                   RaSpectrum spectrum) {
    // A few dozen directions: the azimuth averages integrated rather than tabulated.
    const PrismaticRetroreflector<double> node(
        ra_params(material), PrismaticRetroreflector<double>::Averages::Integrated);
    std::vector<double> v(entries.size(), 0.0);
    for_each_wavelength(node, spectrum, [&](const PrismaticRetroreflector<double>& n, double w) {
        for (size_t i = 0; i < entries.size(); ++i)
            v[i] += w * ra_at_entry(n, entries[i]);
    });
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
    r.log_rms = std::sqrt(ra_cost(t, model));
    return r;
}

RaNodeFit fit_ra_node(const RaMeasurements& t, const Params& base,
                      const std::vector<std::string>& held, RaObjective objective,
                      RaSpectrum spectrum) {
    Params p = base;
    std::vector<Var> vars;
    std::vector<Choice> choices;
    RaNodeFit fit;
    node_search_space(p, held, vars, choices, fit.fitted);
    require_rows(t, fit.fitted);
    auto cost = [&](RaObjective o) {
        return ra_cost(t, ra_node_values(p, t.entries, spectrum), o);
    };
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
        const NmResult r = search_for(vars, objective, cost);
        fit.evaluations += r.evaluations;
        set_all(vars, r.x, true);
        // Values that fit alike (metallized is ideal with a darker retro_color): the first.
        const double c = cost(objective);
        if (c < bestCost * (1.0 - 1e-6)) {
            bestCost = c;
            best = p;
        }
    }
    fit.params = best;
    fit.report = ra_fit_report(t, ra_node_values(best, t.entries, spectrum));
    return fit;
}

RaMrmFit fit_ra_mrm(const RaMeasurements& t, RaObjective objective) {
    RaMrmFit fit;
    baselines::RetroreflectiveGGX m;
    std::vector<Var> vars(3);
    vars[0] = {{1e-4, 1.0, true}, m.roughness, [&](double x) { m.roughness = x; }};
    vars[1] = {{1.01, 3.0, false}, m.ior, [&](double x) { m.ior = x; }};
    vars[2] = {{0.0, 1.0, false}, m.specular, [&](double x) { m.specular = x; }};
    require_rows(t, {"roughness", "ior", "specular"});
    const NmResult r = search_for(
        vars, objective, [&](RaObjective o) { return ra_cost(t, ra_mrm_values(m, t.entries), o); });
    set_all(vars, r.x, true);
    fit.model = m;
    fit.evaluations = r.evaluations;
    fit.report = ra_fit_report(t, ra_mrm_values(m, t.entries));
    return fit;
}

RaColoredFit fit_ra_colors(const RaMeasurements& t, const Params& base,
                           const std::vector<std::string>& held, const std::string& color,
                           RaObjective objective, RaSpectrum spectrum) {
    RaColoredFit out;
    const std::vector<std::string> colors = ra_table_colors(t);
    if (colors.empty()) {
        if (!color.empty()) ra_color_rows(t, color); // throws: the table has no colours
        out.fit = fit_ra_node(t, base, held, objective, spectrum);
        out.rows = t;
        return out;
    }
    const bool hasWhite = std::find(colors.begin(), colors.end(), "white") != colors.end();
    const std::string reference = hasWhite ? "white" : colors.front();
    const std::string chosen = color.empty() ? reference : color;
    out.rows = ra_color_rows(t, chosen);
    out.fit = fit_ra_node(ra_color_rows(t, reference), base, held, objective, spectrum);
    for (const std::string& c : colors) {
        const RaMeasurements rows = ra_color_rows(t, c);
        Params p = out.fit.params;
        const bool hue = c == chosen && c != "white";
        p.retro_color = scaled_retro_color(p, color_chroma(hue, base), rows, objective, spectrum);
        out.colors.push_back({c, p.retro_color, hue,
                              ra_fit_report(rows, ra_node_values(p, rows.entries, spectrum))});
        if (c == chosen) {
            out.fit.params = p;
            out.fit.report = out.colors.back().report;
        }
    }
    return out;
}

} // namespace retroprism
