// accuracy_report.cpp: the values and tables of docs/accuracy.md (see accuracy_report.h and the
// template docs/accuracy.md.in, which holds the prose).
#include "accuracy_report.h"

#include <algorithm>
#include <cmath>

#include "accuracy_plots.h"
#include "plot.h"
#include "template.h"
#include "parse.h"

namespace retroprism::report {

namespace {

using plot::fmt;
using sim::ConfigResult;
using sim::kResolvedSe;
using sim::kVariants;
using sim::Worst;

std::string pct(double v) {
    if (!std::isfinite(v)) return "n/a";
    return fmt("%+.1f%%", 100 * v);
}

std::string worst_str(const Worst& w, bool withWhere = false) {
    if (!w.any) return "n/a";
    return pct(w.value) + (withWhere ? " (" + w.where + ")" : "");
}

bool energy_resolved(const ConfigResult& r) {
    return sim::rel_se(r.sim.energy) <= kResolvedSe;
}

// The worst errors of section 1, per variant and theta_i limit (<= 60, <= 85).
struct Headline {
    std::array<std::array<Worst, 2>, 4> width, energy, peak, diffuse, par, perp;
    std::array<std::array<std::vector<double>, 2>, 4> l1;
};

Headline headline(const sim::StudyResults& s) {
    const double limits[2] = {60, 85};
    Headline h;
    for (const ConfigResult& r : s.results)
        for (size_t v = 0; v < 4; ++v)
            for (size_t L = 0; L < 2; ++L) {
                if (r.c.theta > limits[L]) continue;
                const std::string where = sim::config_label(r.c);
                const double ep = sim::width_err(r, int(v), true);
                const double eq = sim::width_err(r, int(v), false);
                const bool rp = sim::width_resolved(r.sim, true);
                const bool rq = sim::width_resolved(r.sim, false);
                h.par[v][L].add(ep, rp, where);
                h.perp[v][L].add(eq, rq, where);
                h.width[v][L].add(ep, rp, where + ", along");
                h.width[v][L].add(eq, rq, where + ", across");
                h.energy[v][L].add(sim::energy_err(r, int(v)), energy_resolved(r), where);
                h.peak[v][L].add(r.v[v].peak / r.sim.peak.value - 1,
                                 sim::rel_se(r.sim.peak) <= kResolvedSe, where);
                // Diffuse level: every theta_i, one column per prism mode.
                if (L == 1)
                    h.diffuse[v][r.c.prism == f64::RP_PRISM_TIR ? 0 : 1].add(
                        r.v[v].diffuseNormal / r.sim.diffuseNormal.value - 1,
                        sim::rel_se(r.sim.diffuseNormal) <= kResolvedSe, where);
                h.l1[v][L].push_back(r.v[v].l1);
            }
    return h;
}

std::string table_worst(const Headline& h) {
    std::string md =
        "| variant | width, theta_i <= 60 | width, <= 85 | retro energy, <= 60 | retro energy, "
        "<= 85 | retro peak, <= 60 | retro peak, <= 85 | diffuse at n, tir | diffuse at n, "
        "metallized | L1 median / worst, <= 60 | L1 median / worst, <= 85 |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (size_t v = 0; v < 4; ++v) {
        md += std::string("| ") + kVariants[v].name;
        for (auto* w : {&h.width, &h.energy, &h.peak, &h.diffuse})
            for (size_t L = 0; L < 2; ++L)
                md += " | " + worst_str((*w)[v][L]);
        for (size_t L = 0; L < 2; ++L)
            md += " | " + fmt("%.3f", sim::median_of(h.l1[v][L])) + " / " +
                  fmt("%.3f", sim::max_abs(h.l1[v][L]));
        md += " |\n";
    }
    return md;
}

std::string table_worst_where(const Headline& h) {
    std::string md = "| variant | metric | theta_i <= 60 | theta_i <= 85 |\n|---|---|---|---|\n";
    for (size_t v = 0; v < 4; ++v) {
        const std::pair<const char*, const std::array<std::array<Worst, 2>, 4>*> rows[] = {
            {"width along", &h.par},
            {"width across", &h.perp},
            {"retro energy", &h.energy},
            {"retro peak", &h.peak},
            {"diffuse at n (columns: tir / metallized, every theta_i)", &h.diffuse}};
        for (const auto& row : rows) {
            md += std::string("| ") + kVariants[v].name + " | " + row.first;
            for (size_t L = 0; L < 2; ++L) {
                const Worst& w = (*row.second)[v][L];
                md += " | " + worst_str(w, true) + " [" + std::to_string(w.counted) + " / " +
                      std::to_string(w.unresolved) + "]";
            }
            md += " |\n";
        }
    }
    return md;
}

std::string table_per_theta(const sim::StudyResults& s) {
    std::string md = "| theta_i |";
    for (const sim::Variant& v : kVariants)
        md += std::string(" ") + v.name + ": width along / across | energy |";
    md += "\n|---|";
    for (int v = 0; v < 4; ++v)
        md += "---|---|";
    md += "\n";
    for (double theta : s.grid.thetas) {
        md += "| " + number_text(theta);
        for (int v = 0; v < 4; ++v) {
            Worst a, b, e;
            for (const ConfigResult& r : s.results) {
                if (r.c.theta != theta) continue;
                a.add(sim::width_err(r, v, true), sim::width_resolved(r.sim, true), "");
                b.add(sim::width_err(r, v, false), sim::width_resolved(r.sim, false), "");
                e.add(sim::energy_err(r, v), energy_resolved(r), "");
            }
            md += " | " + worst_str(a) + " / " + worst_str(b) + " | " + worst_str(e);
        }
        md += " |\n";
    }
    return md;
}

std::string table_width_formulas(const sim::StudyResults& s) {
    std::string md = "| theta_i |";
    for (double a : s.grid.alphas)
        md += " alpha " + number_text(a) + ": along | across |";
    md += "\n|---|";
    for (size_t i = 0; i < s.grid.alphas.size(); ++i)
        md += "---|---|";
    md += "\n";
    for (double theta : s.grid.thetas) {
        md += "| " + number_text(theta);
        for (double alpha : s.grid.alphas)
            for (int along = 1; along >= 0; --along) {
                std::vector<double> simR, anR;
                for (const ConfigResult& r : s.results) {
                    if (r.c.theta != theta || r.c.alpha != alpha) continue;
                    if (!sim::width_resolved(r.sim, along != 0) || !r.v[1].fit.ok) continue;
                    const double formula = along ? r.v[1].alphaPar : r.v[1].alphaPerp;
                    simR.push_back((along ? r.sim.fit.ax : r.sim.fit.ay) / formula);
                    anR.push_back((along ? r.v[1].fit.ax : r.v[1].fit.ay) / formula);
                }
                md += " | " + (simR.empty() ? std::string("n/a")
                                            : fmt("%.3f", sim::median_of(simR)) + " (" +
                                                  fmt("%.3f", sim::median_of(anR)) + ")");
            }
        md += " |\n";
    }
    return md;
}

std::string table_retro_energy(const sim::StudyResults& s) {
    std::string md = "| prisms | theta_i | alpha | sim retro albedo | paper form | error | "
                     "multiple |\n|---|---|---|---|---|---|---|\n";
    for (int prism : s.grid.prisms)
        for (double theta : s.grid.thetas)
            for (double alpha : s.grid.alphas) {
                double sv = 0, a = 0, mult = 0;
                int n = 0;
                for (double eta : s.grid.etas) {
                    const ConfigResult& r = s.at(theta, alpha, eta, prism);
                    sv += r.sim.energy.value;
                    a += r.v[0].energy;
                    mult += r.sim.energyMultiple.value;
                    ++n;
                }
                md += std::string("| ") + sim::prism_name(prism) + " | " + number_text(theta) +
                      " | " + number_text(alpha) + " | " + fmt("%.4g", sv / n) + " | " +
                      fmt("%.4g", a / n) + " | " + (sv > 0 ? pct(a / sv - 1) : "n/a") + " | " +
                      (sv > 0 ? fmt("%.1f%%", 100 * mult / sv) : "n/a") + " |\n";
            }
    return md;
}

// Section 5's table, and the log ratios of the diffuse levels: paper vs prisms, reciprocal vs
// prisms, paper vs direct, reciprocal vs direct.
std::string table_diffuse(const sim::StudyResults& s, std::array<std::vector<double>, 4>& logErr) {
    std::string md = "| ior | prisms | theta_i | f_d(n): sim, prisms | sim, direct | paper | "
                     "recip. | f_d(60,90): sim, prisms | sim, direct | paper | recip. | albedo: "
                     "sim, prisms | sim, direct | analytic (both forms) "
                     "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    size_t di = 0;
    for (double eta : s.grid.etas)
        for (int prism : s.grid.prisms)
            for (double theta : s.grid.thetas) {
                const ConfigResult& r = s.at(theta, s.diffuse_alpha(), eta, prism);
                const ConfigResult& d = s.direct[di++];
                md += "| " + number_text(eta) + " | " + sim::prism_name(prism) + " | " +
                      number_text(theta);
                for (double v : {r.sim.diffuseNormal.value, d.sim.diffuseNormal.value,
                                 r.v[0].diffuseNormal, r.v[2].diffuseNormal, r.sim.diffuse60.value,
                                 d.sim.diffuse60.value, r.v[0].diffuse60, r.v[2].diffuse60,
                                 r.sim.diffuseAlbedo.value, d.sim.diffuseAlbedo.value})
                    md += " | " + fmt("%.4f", v);
                md += " | " + fmt("%.4f", r.v[0].diffuseAlbedo) + " / " +
                      fmt("%.4f", r.v[2].diffuseAlbedo) + " |\n";
                for (int which = 0; which < 2; ++which) {
                    const double sN =
                        which == 0 ? r.sim.diffuseNormal.value : d.sim.diffuseNormal.value;
                    const double s6 = which == 0 ? r.sim.diffuse60.value : d.sim.diffuse60.value;
                    for (int form = 0; form < 2; ++form) {
                        const sim::VariantResult& a = r.v[size_t(form == 0 ? 0 : 2)];
                        logErr[size_t(which * 2 + form)].push_back(std::log(a.diffuseNormal / sN));
                        logErr[size_t(which * 2 + form)].push_back(std::log(a.diffuse60 / s6));
                    }
                }
            }
    return md;
}

// Section 6: the simulation's row, the largest |z| and the variants' table.
void reciprocity_values(const sim::StudyResults& s, const sim::Reciprocity& rec,
                        TemplateValues& tv) {
    double chi2 = 0;
    int over3 = 0;
    for (double z : rec.z) {
        chi2 += z * z;
        if (std::abs(z) > 3) ++over3;
    }
    const double n = double(rec.z.size());
    tv.text["table_reciprocity_sim"] =
        "| | pairs | sum z^2 / pairs | max abs z | pairs with abs z > 3 (expected for standard "
        "normal z) | median relative difference | max relative difference |\n"
        "|---|---|---|---|---|---|---|\n| simulation | " +
        std::to_string(rec.z.size()) + " | " + fmt("%.3f", n > 0 ? chi2 / n : NAN) + " | " +
        fmt("%.2f", sim::max_abs(rec.z)) + " | " + std::to_string(over3) + " (" +
        fmt("%.1f", 0.0027 * n) + ") | " + fmt("%.2f%%", 100 * sim::median_of([&] {
                                                             std::vector<double> a = rec.rel;
                                                             for (double& x : a)
                                                                 x = std::abs(x);
                                                             return a;
                                                         }())) +
        " | " + fmt("%.1f%%", 100 * sim::max_abs(rec.rel)) + " |\n";
    // The largest deviations, with their pairs.
    const std::vector<sim::ProbeDir> dirs = sim::probe_dirs();
    std::vector<size_t> order;
    for (size_t i = 0; i < s.pairs.size(); ++i)
        order.push_back(i);
    auto z = [&](size_t i) { return sim::reciprocity_z(s.pairs[i], s.options.recipRays); };
    std::sort(order.begin(), order.end(),
              [&](size_t x, size_t y) { return std::abs(z(x)) > std::abs(z(y)); });
    std::string largest;
    for (size_t i = 0; i < std::min<size_t>(5, order.size()); ++i) {
        const sim::RecipPair& q = s.pairs[order[i]];
        largest += (i ? "; " : "") + fmt("z = %+.2f", z(order[i])) + " (" +
                   fmt("theta %g", dirs[size_t(q.a)].theta) + fmt("/%g", dirs[size_t(q.a)].phi) +
                   fmt(" and %g", dirs[size_t(q.b)].theta) + fmt("/%g", dirs[size_t(q.b)].phi) +
                   ", " + sim::material_key(q.alpha, q.eta, q.prism) + ", Q " +
                   fmt("%.4g", q.qab.value) + fmt(" vs %.4g", q.qba.value) + ")";
    }
    tv.text["largest_z"] = largest;
    std::string md = "| variant | wide pairs: median | max | near the retro peak: median | max "
                     "|\n|---|---|---|---|---|\n";
    for (size_t v = 0; v < 4; ++v)
        md += std::string("| ") + kVariants[v].name + " | " +
              fmt("%.2f%%", 100 * sim::median_of(rec.wide[v])) + " | " +
              fmt("%.1f%%", 100 * sim::max_abs(rec.wide[v])) + " | " +
              fmt("%.2f%%", 100 * sim::median_of(rec.near[v])) + " | " +
              fmt("%.1f%%", 100 * sim::max_abs(rec.near[v])) + " |\n";
    tv.text["table_reciprocity_variants"] = md;
    tv.text["recip_chi2"] = fmt("%.3f", rec.z.empty() ? NAN : chi2 / n);
    tv.text["recip_pairs"] = std::to_string(rec.z.size());
    tv.text["recip_max_z"] = fmt("%.2f", sim::max_abs(rec.z));
    tv.text["paper_wide"] = fmt("%.1f%%", 100 * sim::median_of(rec.wide[0]));
    tv.text["paper_near"] = fmt("%.1f%%", 100 * sim::median_of(rec.near[0]));
    tv.text["paper_worst"] =
        fmt("%.0f%%", 100 * std::max(sim::max_abs(rec.wide[0]), sim::max_abs(rec.near[0])));
}

std::string table_surface(const sim::StudyResults& s) {
    std::string md = "| theta_i |";
    for (double a : s.grid.alphas)
        md += " alpha " + number_text(a) + ": sim all orders / sim single / analytic |";
    md += "\n|---|";
    for (size_t i = 0; i < s.grid.alphas.size(); ++i)
        md += "---|";
    md += "\n";
    for (double theta : s.grid.thetas) {
        md += "| " + number_text(theta);
        for (double alpha : s.grid.alphas) {
            double all = 0, single = 0, an = 0;
            int n = 0;
            for (const ConfigResult& r : s.results)
                if (r.c.theta == theta && r.c.alpha == alpha) {
                    all += r.sim.surface.value;
                    single += r.sim.surfaceSingle.value;
                    an += r.v[0].surface;
                    ++n;
                }
            md += " | " + fmt("%.4f", all / n) + " / " + fmt("%.4f", single / n) + " / " +
                  fmt("%.4f", an / n);
        }
        md += " |\n";
    }
    return md;
}

std::string table_appendix(const sim::StudyResults& s) {
    std::string md = "| theta_i | alpha | ior | prisms | sim retro albedo | sim a_par / a_perp |";
    for (const sim::Variant& v : kVariants)
        md += std::string(" ") + v.key + " |";
    md += "\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const ConfigResult& r : s.results) {
        md += "| " + number_text(r.c.theta) + " | " + number_text(r.c.alpha) + " | " +
              number_text(r.c.eta) + " | " + sim::prism_name(r.c.prism) + " | " +
              fmt("%.4g", r.sim.energy.value) + " | " +
              (r.sim.fit.ok ? fmt("%.4g", r.sim.fit.ax) + " / " + fmt("%.4g", r.sim.fit.ay) : "-") +
              " |";
        const bool rp = sim::width_resolved(r.sim, true), rq = sim::width_resolved(r.sim, false);
        for (int v = 0; v < 4; ++v)
            md += " " + (rp ? pct(sim::width_err(r, v, true)) : "-") + " / " +
                  (rq ? pct(sim::width_err(r, v, false)) : "-") + " / " +
                  (energy_resolved(r) ? pct(sim::energy_err(r, v)) : "-") + " |";
        md += "\n";
    }
    return md;
}

// "iso +1.3%, aniso +1.3%, ...": the worst of a metric per variant over theta_i <= thetaMax and
// roughness <= alphaMax (metric 0: width along and across; 1: retro energy).
std::string worst_per_variant(const sim::StudyResults& s, double thetaMax, double alphaMax,
                              int metric) {
    std::string out;
    for (int v = 0; v < 4; ++v) {
        Worst w;
        for (const ConfigResult& r : s.results) {
            if (r.c.theta > thetaMax || r.c.alpha > alphaMax) continue;
            if (metric == 0) {
                w.add(sim::width_err(r, v, true), sim::width_resolved(r.sim, true), "");
                w.add(sim::width_err(r, v, false), sim::width_resolved(r.sim, false), "");
            } else {
                w.add(sim::energy_err(r, v), energy_resolved(r), "");
            }
        }
        out += (v ? ", " : "") + std::string(kVariants[v].key) + " " + worst_str(w);
    }
    return out;
}

// "+1.2% (20), -3.4% (40), ...": variant v's median width error (over ior and prism mode) at
// every theta_i > 0 at roughness alpha.
std::string width_row(const sim::StudyResults& s, int v, bool along, double alpha) {
    std::string out;
    for (double theta : s.grid.thetas) {
        if (theta == 0) continue;
        std::vector<double> e;
        for (const ConfigResult& r : s.results)
            if (r.c.theta == theta && r.c.alpha == alpha && sim::width_resolved(r.sim, along))
                e.push_back(sim::width_err(r, v, along));
        const double m = sim::median_of(e);
        out += (out.empty() ? "" : ", ") + (std::isfinite(m) ? pct(m) : std::string("n/a")) +
               fmt(" (%g)", theta);
    }
    return out;
}

// The findings' lobe widths at the roughnesses 0.02 (w002) and 0.3 (w03), when in the grid.
void width_findings(const sim::StudyResults& s, TemplateValues& tv) {
    const std::pair<const char*, double> rows[] = {{"w002", 0.02}, {"w03", 0.3}};
    for (const auto& [name, alpha] : rows) {
        const std::string n = name;
        const auto& as = s.grid.alphas;
        tv.flags[n] = std::find(as.begin(), as.end(), alpha) != as.end();
        tv.text[n + "_alpha"] = number_text(alpha);
        for (const auto& [key, v] :
             {std::pair<const char*, int>{"iso", 0}, {"aniso", 1}, {"anisorec", 3}}) {
            tv.text[n + "_" + key + "_along"] = tv.flags[n] ? width_row(s, v, true, alpha) : "";
            tv.text[n + "_" + key + "_across"] = tv.flags[n] ? width_row(s, v, false, alpha) : "";
        }
    }
}

// The findings' diffuse albedo (tir prisms), the metallized prisms and the surface lobe.
void lobe_findings(const sim::StudyResults& s, TemplateValues& tv) {
    std::array<Worst, 3> paper, recip; // roughness <= 0.1 and theta_i <= 75; 0.3; 85
    for (const ConfigResult& r : s.results) {
        if (r.c.prism != f64::RP_PRISM_TIR || !(r.sim.diffuseAlbedo.value > 0)) continue;
        const size_t band = r.c.theta > 75 ? 2 : r.c.alpha > 0.1 ? 1 : 0;
        paper[band].add(r.v[0].diffuseAlbedo / r.sim.diffuseAlbedo.value - 1, true, "");
        recip[band].add(r.v[2].diffuseAlbedo / r.sim.diffuseAlbedo.value - 1, true, "");
    }
    for (size_t b = 0; b < 3; ++b) {
        tv.text["albedo_paper_" + std::to_string(b)] = worst_str(paper[b]);
        tv.text["albedo_recip_" + std::to_string(b)] = worst_str(recip[b]);
    }
    std::vector<double> ratio, paperRatio;
    size_t di = 0;
    for (double eta : s.grid.etas)
        for (int prism : s.grid.prisms)
            for (double theta : s.grid.thetas) {
                const ConfigResult& d = s.direct[di++];
                if (prism != f64::RP_PRISM_METALLIZED) continue;
                const ConfigResult& r = s.at(theta, s.diffuse_alpha(), eta, prism);
                if (!(d.sim.diffuseAlbedo.value > 0)) continue;
                ratio.push_back(r.v[0].diffuseAlbedo / d.sim.diffuseAlbedo.value);
                // The same with the paper's substrate term 1 - E in place of the node's.
                Params p;
                p.ior = eta;
                p.prism_reflection = prism;
                const f64::rp_material m = prepare_material(sanitize(p));
                const double th = theta * (f64::RP_PI / 180.0);
                f64::rp_incident inc;
                f64::rp_incident_lobes(m, f64::vec3(std::sin(th), 0.0, std::cos(th)), inc);
                if (inc.passed > 0)
                    paperRatio.push_back(ratio.back() * (1.0 - inc.era) / inc.passed);
            }
    tv.flags["metallized"] = !ratio.empty();
    tv.text["metallized_ratio"] = fmt("%.2f", sim::median_of(ratio));
    tv.text["metallized_paper_ratio"] = fmt("%.2f", sim::median_of(paperRatio));
    double all = 0, single = 0;
    int n = 0;
    for (const ConfigResult& r : s.results)
        if (r.c.theta == s.grid.thetas.back() && r.c.alpha == s.grid.alphas.back()) {
            all += r.sim.surface.value;
            single += r.sim.surfaceSingle.value;
            ++n;
        }
    tv.flags["surface_multiple"] = n > 0 && single > 0;
    tv.text["surface_multiple"] = fmt("%.1f%%", 100 * (all / single - 1));
    tv.text["last_theta"] = number_text(s.grid.thetas.back());
    tv.text["last_alpha"] = number_text(s.grid.alphas.back());
}

void header_values(const sim::StudyResults& s, const std::string& docPath,
                   const std::string& plotDir, TemplateValues& tv) {
    const sim::StudyOptions& o = s.options;
    tv.text["quick"] = o.quick ? " --quick" : "";
    tv.text["rays"] = std::to_string(o.rays);
    tv.text["diffuse_rays"] = std::to_string(o.diffuseRays);
    tv.text["recip_rays"] = std::to_string(o.recipRays);
    tv.text["seed"] = std::to_string(o.seed);
    tv.text["doc_option"] = docPath != "docs/accuracy.md" ? " --doc " + docPath : "";
    tv.text["date"] = s.date;
    tv.text["machine"] = s.machine;
    tv.text["configs"] = std::to_string(s.results.size());
    tv.text["direct_runs"] = std::to_string(s.direct.size());
    tv.text["recip_runs"] = std::to_string(s.pairs.size() / 55 * 11);
    tv.text["total_rays"] = fmt("%.4g", s.simRays);
    tv.text["sim_seconds"] = fmt("%.0f", s.simSeconds);
    tv.text["rays_per_second"] = fmt("%.3g", s.simRays / s.simSeconds);
    tv.text["threads"] = std::to_string(s.threadsUsed);
    tv.text["rays_per_thread"] = fmt("%.3g", s.simRays / s.simSeconds / s.threadsUsed);
    tv.text["minutes"] = fmt("%.1f", s.elapsed / 60);
    tv.text["plot_dir"] = plotDir;
    tv.text["resolved_pct"] = fmt("%.0f", 100 * kResolvedSe);
    tv.text["diffuse_alpha"] = number_text(s.diffuse_alpha());
    tv.text["recip_cone_deg"] = fmt("%g", sim::kRecipConeDeg);
    std::string images;
    for (const std::string& p : accuracy_plot_names(s.grid))
        images += (images.empty() ? "" : "\n\n") + ("![" + p + "](" + plotDir + "/" + p + ")");
    tv.text["plot_images"] = images;
}

void headline_values(const sim::StudyResults& s, TemplateValues& tv) {
    const Headline h = headline(s);
    tv.text["table_worst"] = table_worst(h);
    tv.text["table_worst_where"] = table_worst_where(h);
    std::vector<double> noise60, noise85;
    for (const ConfigResult& r : s.results) {
        if (r.c.theta <= 60) noise60.push_back(r.sim.l1Noise);
        noise85.push_back(r.sim.l1Noise);
    }
    tv.text["noise_median_60"] = fmt("%.3f", sim::median_of(noise60));
    tv.text["noise_median_all"] = fmt("%.3f", sim::median_of(noise85));
    tv.text["noise_worst"] = fmt("%.3f", sim::max_abs(noise85));
    const char* forms[2] = {"paper", "recip"};
    const char* prisms[2] = {"tir", "metallized"};
    for (size_t f = 0; f < 2; ++f)
        for (size_t p = 0; p < 2; ++p)
            tv.text[std::string("diffuse_") + forms[f] + "_" + prisms[p]] =
                worst_str(h.diffuse[f == 0 ? 0 : 2][p]);
}

} // namespace

std::string accuracy_report(const sim::StudyResults& s, const std::string& tmpl,
                            const std::string& where, const std::string& docPath,
                            const std::string& plotDir) {
    TemplateValues tv;
    header_values(s, docPath, plotDir, tv);
    headline_values(s, tv);
    tv.text["table_per_theta"] = table_per_theta(s);
    tv.text["table_width_formulas"] = table_width_formulas(s);
    tv.text["table_retro_energy"] = table_retro_energy(s);
    std::array<std::vector<double>, 4> logErr;
    tv.text["table_diffuse"] = table_diffuse(s, logErr);
    const char* names[4] = {"rms_paper_prisms", "rms_recip_prisms", "rms_paper_direct",
                            "rms_recip_direct"};
    for (size_t i = 0; i < 4; ++i)
        tv.text[names[i]] = fmt("%.3f", sim::rms(logErr[i]));
    tv.flags["recip_closer_prisms"] = sim::rms(logErr[1]) < sim::rms(logErr[0]);
    tv.flags["paper_closer_direct"] = sim::rms(logErr[2]) < sim::rms(logErr[3]);
    reciprocity_values(s, sim::analyse_reciprocity(s), tv);
    tv.text["table_surface"] = table_surface(s);
    tv.text["table_appendix"] = table_appendix(s);
    tv.text["energy_40_01"] = worst_per_variant(s, 40, 0.1, 1);
    tv.text["energy_60"] = worst_per_variant(s, 60, 1, 1);
    tv.text["energy_85"] = worst_per_variant(s, 85, 1, 1);
    tv.text["width_40_01"] = worst_per_variant(s, 40, 0.1, 0);
    width_findings(s, tv);
    lobe_findings(s, tv);
    // Tables end without their last line break: the template has it.
    for (auto& [name, text] : tv.text)
        if (name.rfind("table_", 0) == 0 && !text.empty() && text.back() == '\n') text.pop_back();
    return fill_template(tmpl, tv, where);
}

} // namespace retroprism::report
