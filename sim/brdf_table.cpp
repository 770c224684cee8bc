// brdf_table.cpp: the tabulated BRDF of `retroprism simulate` (see brdf_table.h).
#include "brdf_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "study.h"

namespace retroprism::sim {

namespace {

// Channel c's f and standard errors per lobe from its simulation's tally: the lobes' factors
// (k_s, k_s, c_r, 1) times the weight; the total with the multinomial variance of a weighted
// sum of exclusive categories.
void channel_values(const Params& p, int c, const Tally& t, BrdfTable& table) {
    const double n = double(t.rays);
    const double factor[4] = {p.weight * p.specular, p.weight * p.specular,
                              p.weight * p.retro_color[size_t(c)], p.weight};
    auto& f = table.f[size_t(c)];
    auto& se = table.se[size_t(c)];
    f.resize(table.grids.size());
    se.resize(table.grids.size());
    for (size_t g = 0; g < table.grids.size(); ++g) {
        const size_t cells = size_t(table.grids[g].cells());
        for (auto& v : f[g])
            v.assign(cells, 0.0);
        for (auto& v : se[g])
            v.assign(cells, 0.0);
        for (size_t cell = 0; cell < cells; ++cell) {
            const double proj = table.projected[g][cell];
            if (!(proj > 0)) continue;
            double pr[4], mean = 0, second = 0;
            for (int k = 0; k < 4; ++k) {
                const std::uint64_t count = t.counts[g][cell * kChannels + size_t(k)];
                pr[k] = double(count) / n;
                const Estimate e = fraction(count, t.rays);
                f[g][size_t(k)][cell] = factor[k] * e.value / proj;
                se[g][size_t(k)][cell] = factor[k] * e.se / proj;
            }
            for (int k : {kSurface, kRetro, kDiffuse}) {
                mean += factor[k] * pr[k];
                second += factor[k] * factor[k] * pr[k];
            }
            f[g][4][cell] = mean / proj;
            se[g][4][cell] = std::sqrt(std::max(0.0, second - mean * mean) / n) / proj;
        }
    }
}

} // namespace

BrdfTable tabulate_brdf(const Params& params, double thetaIDeg, double phiIDeg,
                        const TableOptions& o) {
    const Params p = sanitize(params);
    BrdfTable table;
    for (int c = 1; c < 3; ++c)
        for (int e = 0; e < c; ++e)
            if (p.diffuse_color[size_t(c)] == p.diffuse_color[size_t(e)]) {
                table.run_of[c] = table.run_of[e];
                break;
            }
    table.theta_i_deg = thetaIDeg;
    table.phi_i_deg = phiIDeg;
    table.wi = direction_deg(thetaIDeg, phiIDeg);
    const dvec3 wi = table.wi;
    Sheet base = sheet_from_params(p, 0);
    base.upward_through_prisms = o.way_up_through_prisms;
    table.grids = standard_grids(base, wi);
    f64::rp_material m = prepare_material(p);
    m.retro_anisotropic = 1;
    f64::rp_incident s;
    f64::rp_incident_setup(m, wi, s);
    const std::vector<Feature> features = {{wi, s.alphaPerp},
                                           {dvec3(-wi.x, -wi.y, wi.z), base.alpha}};
    for (const Grid& g : table.grids)
        table.projected.push_back(
            integrate_cells(g, 0, nullptr, features, 4, 64, o.threads).projected);
    const bool grey = table.run_of[1] == 0 && table.run_of[2] == 0;
    for (int c = 0; c < 3; ++c) {
        if (table.run_of[c] != c) continue;
        Sheet sh = sheet_from_params(p, c);
        sh.upward_through_prisms = o.way_up_through_prisms;
        char label[96];
        std::snprintf(label, sizeof label, "simulate theta_i %g%s", thetaIDeg,
                      grey ? "" : (" channel " + std::to_string(c)).c_str());
        RunOptions opt;
        opt.rays = o.rays;
        opt.seed = o.seed;
        opt.threads = o.threads;
        if (o.progress) opt.progress = o.progress(label);
        table.runs[size_t(c)] = simulate(sh, wi, table.grids, opt);
    }
    for (int c = 0; c < 3; ++c)
        channel_values(p, c, table.runs[size_t(table.run_of[c])].tally, table);
    return table;
}

} // namespace retroprism::sim
