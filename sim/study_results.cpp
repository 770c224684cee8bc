// study_results.cpp: the CSV schema and the archive of the accuracy study (see
// study_results.h).
#include "study_results.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <type_traits>

#include "error.h"
#include "parse.h"

namespace retroprism::sim {

namespace {

// The one CSV schema: visit(column name, field) for every column in order, on a const result
// (writing) or a mutable one (reading). Fields are doubles, counts (std::uint64_t) or the prism
// mode (int, written by name).
template <class Result, class Visit>
void csv_columns(Result& r, Visit&& visit) {
    auto& s = r.sim;
    visit("theta_i_deg", r.c.theta);
    visit("roughness", r.c.alpha);
    visit("ior", r.c.eta);
    visit("prism_reflection", r.c.prism);
    visit("rays", s.rays);
    visit("sim_retro_peak", s.peak.value);
    visit("sim_retro_peak_se", s.peak.se);
    visit("sim_fit_alpha_par", s.fit.ax);
    visit("sim_fit_alpha_par_se", s.fit.se_ax);
    visit("sim_fit_alpha_perp", s.fit.ay);
    visit("sim_fit_alpha_perp_se", s.fit.se_ay);
    visit("sim_fit_shift_par", s.fit.mx);
    visit("sim_retro_energy", s.energy.value);
    visit("sim_retro_energy_se", s.energy.se);
    visit("sim_retro_primary", s.energyPrimary.value);
    visit("sim_retro_multiple", s.energyMultiple.value);
    visit("sim_diffuse_normal", s.diffuseNormal.value);
    visit("sim_diffuse_normal_se", s.diffuseNormal.se);
    visit("sim_diffuse_60_90", s.diffuse60.value);
    visit("sim_diffuse_60_90_se", s.diffuse60.se);
    visit("sim_diffuse_albedo", s.diffuseAlbedo.value);
    visit("sim_surface", s.surface.value);
    visit("sim_surface_single", s.surfaceSingle.value);
    visit("sim_absorbed", s.absorbed.value);
    visit("sim_trapped", s.trapped);
    visit("sim_l1_noise", s.l1Noise);
    visit("sim_l1_retro_noise", s.l1RetroNoise);
    visit("retro_grid_half_par", s.hx);
    visit("retro_grid_half_perp", s.hy);
    for (int k = 0; k < 4; ++k) {
        auto& v = r.v[size_t(k)];
        const std::string key = std::string(kVariants[k].key) + "_";
        visit(key + "alpha_par", v.alphaPar);
        visit(key + "alpha_perp", v.alphaPerp);
        visit(key + "fit_alpha_par", v.fit.ax);
        visit(key + "fit_alpha_perp", v.fit.ay);
        visit(key + "retro_peak", v.peak);
        visit(key + "retro_energy", v.energy);
        visit(key + "surface", v.surface);
        visit(key + "diffuse_normal", v.diffuseNormal);
        visit(key + "diffuse_60_90", v.diffuse60);
        visit(key + "diffuse_albedo", v.diffuseAlbedo);
        visit(key + "l1", v.l1);
        visit(key + "l1_retro", v.l1Retro);
    }
}

std::vector<std::string> split_csv(const std::string& line) {
    std::vector<std::string> fields;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');)
        fields.push_back(c);
    return fields;
}

// The flat list of numbers of the archive, written (loading false) or read back in the same
// order.
struct Archive {
    bool loading = false;
    std::string where; // the option and file being loaded, for the errors ("--load FILE")
    std::vector<double> data;
    size_t pos = 0;
    void io(double& v) {
        if (loading) {
            if (pos >= data.size()) throw InputError(where + ": the results file is truncated");
            v = data[pos++];
        } else {
            data.push_back(v);
        }
    }
    template <class T>
    std::enable_if_t<std::is_arithmetic_v<T>> io(T& v) {
        double d = double(v);
        io(d);
        // A count, flag or enum must be a whole number the type can hold.
        if constexpr (std::is_integral_v<T>)
            // (below 2^digits: the type's maximum itself may round up to it as a double)
            if (!(d == std::floor(d) && d >= double(std::numeric_limits<T>::lowest()) &&
                  d < std::ldexp(1.0, std::numeric_limits<T>::digits)))
                throw InputError(where + ": value " + std::to_string(pos) +
                                 " of the results file is not a whole number in range");
        v = T(d);
    }
    void io(Estimate& e) {
        io(e.value);
        io(e.se);
    }
    void io(LobeFit& f) {
        io(f.ok);
        for (double* d : {&f.ax, &f.ay, &f.se_ax, &f.se_ay, &f.mx})
            io(*d);
        io(f.my);
        io(f.cells);
        io(f.chi2_reduced);
    }
    template <class T>
    void io(std::vector<T>& v) {
        std::uint64_t n = v.size();
        io(n);
        // Each element is at least one number: a longer list than the file holds is an error
        // before it is allocated.
        if (loading && n > data.size() - pos)
            throw InputError(where + ": the results file is truncated");
        if (loading) v.resize(size_t(n));
        for (T& x : v)
            io(x);
    }
    void io(SimResult& s) {
        io(s.rays);
        io(s.seconds);
        io(s.threads);
        io(s.fit);
        for (Estimate* e :
             {&s.peak, &s.energy, &s.energyPrimary, &s.energyMultiple, &s.diffuseNormal,
              &s.diffuse60, &s.diffuseAlbedo, &s.surface, &s.surfaceSingle, &s.absorbed})
            io(*e);
        io(s.trapped);
        io(s.l1Noise);
        io(s.l1RetroNoise);
        for (auto* v : {&s.rowX, &s.colX, &s.stripX})
            io(*v);
        io(s.row);
        io(s.col);
        for (auto& v : s.strip)
            io(v);
        io(s.hx);
        io(s.hy);
    }
    void io(VariantResult& r) {
        for (double* d : {&r.alphaPar, &r.alphaPerp, &r.peak, &r.energy, &r.surface,
                          &r.diffuseNormal, &r.diffuse60, &r.diffuseAlbedo, &r.l1, &r.l1Retro})
            io(*d);
        io(r.fit);
        io(r.row);
        io(r.col);
        for (auto& v : r.strip)
            io(v);
    }
    void io(RecipPair& p) {
        io(p.alpha);
        io(p.eta);
        io(p.prism);
        io(p.a);
        io(p.b);
        io(p.qab);
        io(p.qba);
    }
    void io(ConfigResult& r) {
        io(r.c.theta);
        io(r.c.alpha);
        io(r.c.eta);
        io(r.c.prism);
        io(r.sim);
        for (VariantResult& v : r.v)
            io(v);
    }
    // The whole study: options, timing and results.
    void io(StudyResults& s) {
        io(s.options.rays);
        io(s.options.diffuseRays);
        io(s.options.recipRays);
        io(s.options.seed);
        io(s.simSeconds);
        io(s.simRays);
        io(s.threadsUsed);
        io(s.elapsed);
        io(s.results);
        io(s.direct);
        io(s.pairs);
    }
    // A shard: options, K/N, the grid, its metadata, then each unit's index, rays, seconds and
    // results.
    void io(StudyShard& s) {
        io(s.options.quick);
        for (std::uint64_t* v :
             {&s.options.rays, &s.options.diffuseRays, &s.options.recipRays, &s.options.seed})
            io(*v);
        io(s.shard.k);
        io(s.shard.n);
        const std::vector<StudyUnit> units = study_units(s.options);
        if (loading && !(s.shard.n >= 1 && size_t(s.shard.n) <= units.size() && s.shard.k >= 1 &&
                         s.shard.k <= s.shard.n))
            throw InputError(where + ": shard " + std::to_string(s.shard.k) + "/" +
                             std::to_string(s.shard.n) +
                             " is not K/N with 1 <= K <= N <= " + std::to_string(units.size()));
        StudyGrid g = study_grid(s.options.quick);
        for (auto* v : {&g.thetas, &g.alphas, &g.etas})
            io(*v);
        io(g.prisms);
        const StudyGrid mine = study_grid(s.options.quick);
        if (loading && !(g.thetas == mine.thetas && g.alphas == mine.alphas &&
                         g.etas == mine.etas && g.prisms == mine.prisms))
            throw InputError(where + ": the study's grid is not this program's" +
                             (s.options.quick ? " --quick grid" : " grid"));
        io(s.simSeconds);
        io(s.elapsed);
        io(s.threadsUsed);
        std::uint64_t count = s.units.size();
        io(count);
        if (loading && count > units.size())
            throw InputError(where + ": " + std::to_string(count) + " units, of a study of " +
                             std::to_string(units.size()));
        if (loading) s.units.resize(size_t(count));
        size_t next = 0;
        for (UnitResult& u : s.units) {
            std::uint64_t index = u.index;
            io(index);
            if (loading && (index < next || index >= units.size()))
                throw InputError(where + ": unit " + std::to_string(index) +
                                 " is not after the previous unit and below " +
                                 std::to_string(units.size()));
            u.index = size_t(index);
            next = u.index + 1;
            io(u.rays);
            io(u.seconds);
            if (units[u.index].kind == UnitKind::Reciprocity)
                io(u.pairs);
            else
                io(u.config);
        }
        if (loading && pos != data.size())
            throw InputError(where + ": trailing numbers after the last unit (" +
                             std::to_string(data.size() - pos) + ")");
    }
};

// The first line of a shard's file.
constexpr const char* kShardHeader = "retroprism accuracy study shard";

// Writes the header lines, then the archive's numbers one per line in the round-trip-exact
// %.17g; `what` ("--save FILE") names it in the error.
void write_archive(const std::string& path, const std::string& header, const Archive& ar,
                   const std::string& what) {
    std::ofstream out(path);
    out << header;
    char buf[40];
    for (double d : ar.data) {
        std::snprintf(buf, sizeof buf, "%.17g\n", d);
        out << buf;
    }
    if (!out) throw InputError(what + ": cannot write");
}

// The numbers that follow the header lines, for loading; `where` ("--load FILE") names the file
// in the errors.
Archive read_archive(std::istream& in, const std::string& where) {
    Archive ar;
    ar.loading = true;
    ar.where = where;
    std::string tok;
    while (in >> tok) {
        // Saved with %.17g: NaN and infinities are written as nan and inf.
        const std::optional<double> v = try_parse_number(tok, false);
        if (!v)
            throw InputError(where + ": \"" + tok + "\" (value " +
                             std::to_string(ar.data.size() + 1) + ") is not a number");
        ar.data.push_back(*v);
    }
    return ar;
}

} // namespace

void write_results_csv(const std::string& path, const std::vector<ConfigResult>& results) {
    std::ofstream csv(path);
    const ConfigResult header{};
    bool first = true;
    csv_columns(header, [&](const std::string& name, const auto&) {
        csv << (first ? "" : ",") << name;
        first = false;
    });
    csv << "\n";
    for (const ConfigResult& r : results) {
        first = true;
        csv_columns(r, [&](const std::string&, const auto& field) {
            csv << (first ? "" : ",");
            first = false;
            if constexpr (std::is_same_v<std::decay_t<decltype(field)>, int>)
                csv << prism_name(field);
            else
                csv << field;
        });
        csv << "\n";
    }
    if (!csv) throw InputError(path + ": cannot write");
}

std::vector<ConfigResult> read_results_csv(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError(path + ": cannot open the accuracy study's results");
    return parse_results_csv(in, path);
}

std::vector<ConfigResult> parse_results_csv(std::istream& in, const std::string& path) {
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> head = split_csv(line);
    std::vector<ConfigResult> out;
    int lineNo = 1;
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.empty()) continue;
        const std::string where = path + ":" + std::to_string(lineNo);
        const std::vector<std::string> f = split_csv(line);
        if (f.size() != head.size())
            throw InputError(where + ": expected " + std::to_string(head.size()) +
                             " fields, found " + std::to_string(f.size()));
        ConfigResult r;
        csv_columns(r, [&](const std::string& name, auto& field) {
            const auto it = std::find(head.begin(), head.end(), name);
            if (it == head.end()) throw InputError(path + ":1: no column " + name);
            const std::string& text = f[size_t(it - head.begin())];
            using T = std::decay_t<decltype(field)>;
            if constexpr (std::is_same_v<T, int>) {
                field = prism_of_name(text);
                if (field < 0)
                    throw InputError(where + ": unknown prism_reflection '" + text + "'");
            } else if constexpr (std::is_integral_v<T>) {
                // Counts: whole numbers a double holds exactly (no out-of-range conversion).
                field = T(parse_count(text, where + ": " + name, 0, 9.0e15));
            } else {
                field = T(parse_number(text, where + ": " + name));
            }
        });
        out.push_back(r);
    }
    return out;
}

void save_study(const std::string& path, const StudyResults& s) {
    Archive ar;
    StudyResults copy = s;
    ar.io(copy);
    write_archive(path, s.machine + "\n" + s.date + "\n", ar, "--save " + path);
}

StudyResults load_study(const std::string& path, bool quick) {
    std::ifstream in(path);
    if (!in) throw InputError("--load " + path + ": cannot open file");
    return parse_study(in, path, quick);
}

StudyResults parse_study(std::istream& in, const std::string& path, bool quick) {
    StudyResults s;
    s.options.quick = quick;
    s.grid = study_grid(quick);
    std::getline(in, s.machine);
    if (s.machine == kShardHeader)
        throw InputError("--load " + path +
                         ": the partial results of one shard (simulate "
                         "--study --shard K/N); give every shard to --merge");
    std::getline(in, s.date);
    Archive ar = read_archive(in, "--load " + path);
    ar.io(s);
    if (s.results.size() != s.grid.size())
        throw InputError("--load " + path + ": " + std::to_string(s.results.size()) +
                         " configurations, expected " + std::to_string(s.grid.size()) +
                         " (the same --quick as the run that saved it)");
    return s;
}

void save_study_shard(const std::string& path, const StudyShard& s) {
    Archive ar;
    StudyShard copy = s;
    ar.io(copy);
    write_archive(path, std::string(kShardHeader) + "\n" + s.machine + "\n" + s.date + "\n", ar,
                  "--save " + path);
}

StudyShard load_study_shard(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError("--merge " + path + ": cannot open file");
    return parse_study_shard(in, path);
}

StudyShard parse_study_shard(std::istream& in, const std::string& path) {
    StudyShard s;
    s.source = path;
    std::string header;
    std::getline(in, header);
    if (header != kShardHeader)
        throw InputError("--merge " + path +
                         ": not the partial results of a shard (simulate "
                         "--study --shard K/N --save FILE writes them)");
    std::getline(in, s.machine);
    std::getline(in, s.date);
    Archive ar = read_archive(in, "--merge " + path);
    ar.io(s);
    return s;
}

} // namespace retroprism::sim
