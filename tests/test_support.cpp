#include "test_support.h"

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>

namespace rptest {

dvec3 dir_deg(double thetaDeg, double phiDeg) {
    const double t = thetaDeg * M_PI / 180.0, p = phiDeg * M_PI / 180.0;
    return dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

std::uint64_t Rng::next_u64() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double Rng::uniform() {
    return double(next_u64() >> 11) * 0x1.0p-53;
}

namespace {

// Regularised lower incomplete gamma P(a, x) by its series (x < a + 1).
double gamma_p_series(double a, double x) {
    double sum = 1.0 / a, term = sum;
    for (int n = 1; n < 100000; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Regularised upper incomplete gamma Q(a, x) by Lentz's continued fraction (x >= a + 1).
double gamma_q_fraction(double a, double x) {
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-16) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

} // namespace

double chi2_sf(double x, double dof) {
    if (!(x > 0)) return 1.0;
    const double a = 0.5 * dof, hx = 0.5 * x;
    return hx < a + 1.0 ? 1.0 - gamma_p_series(a, hx) : gamma_q_fraction(a, hx);
}

double sidak(double alpha, int tests) {
    return 1.0 - std::pow(1.0 - alpha, 1.0 / tests);
}

std::vector<Corner> parameter_corners() {
    std::vector<Corner> out;
    for (double roughness : {0.0, 1e-4, 0.05, 1.0})
        for (double ior : {1.0, 1.49, 3.0})
            for (int prism : {0, 1, 2})
                for (int era : {0, 1, 2}) {
                    Params p;
                    p.roughness = roughness;
                    p.ior = ior;
                    p.prism_reflection = prism;
                    p.era_mode = era;
                    p.orientation = 17.0;
                    p.diffuse_color = {1.0, 1.0, 1.0};
                    p.retro_color = {1.0, 1.0, 1.0};
                    out.push_back(
                        {"roughness=" + std::to_string(roughness) + " ior=" + std::to_string(ior) +
                             " prism=" + std::to_string(prism) + " era=" + std::to_string(era),
                         p});
                }
    // Dihedral errors (a ring of spots about the retro direction), alone and with a cant and the
    // anisotropic lobe, at the roughness and ior extremes.
    for (double roughness : {1e-4, 0.05, 1.0})
        for (double ior : {1.0, 1.49, 3.0})
            for (int era : {0, 2}) {
                Params p;
                p.roughness = roughness;
                p.ior = ior;
                p.era_mode = era;
                p.orientation = 17.0;
                p.dihedral_error = era == 0 ? 60.0 : 8.0;
                p.dihedral_spread = era == 0 ? 0.0 : 5.0;
                p.cant_angle = era == 0 ? 0.0 : -20.0;
                p.retro_lobe = era == 0 ? 0 : 1;
                p.diffuse_color = {1.0, 1.0, 1.0};
                p.retro_color = {1.0, 1.0, 1.0};
                out.push_back({"roughness=" + std::to_string(roughness) +
                                   " ior=" + std::to_string(ior) + " era=" + std::to_string(era) +
                                   " dihedral=" + std::to_string(p.dihedral_error) +
                                   " spread=" + std::to_string(p.dihedral_spread) +
                                   " cant=" + std::to_string(p.cant_angle) +
                                   " retro_lobe=" + std::to_string(p.retro_lobe),
                               p});
            }
    // Diffraction at the prism aperture (prism_pitch), per colour channel or at one wavelength,
    // from a pitch far below the wavelength (the pattern wider than the hemisphere) to 2 mm, with
    // every ERA mode, a dispersion, dihedral errors and a cant, and the fast tier; the first
    // uncoated prisms and the last two ideal and metallised ones whose geometric lobe is narrow
    // against the pattern's rings, so that the exact tier evaluates the pattern itself (the face
    // orders', the aperture's fully, and the aperture's damped by a ring of spots).
    struct Diffracting {
        double roughness, ior, pitch, wavelength, abbe, dihedral, cant;
        int era, prism, fidelity;
    };
    const Diffracting diffracting[] = {{1e-4, 1.49, 30.0, 0.0, 0.0, 0.0, 0.0, 0, 1, 0},
                                       {0.05, 1.49, 200.0, 905.0, 57.0, 0.0, 0.0, 1, 1, 0},
                                       {1e-4, 3.0, 100.0, 1550.0, 0.0, 8.0, -20.0, 2, 0, 1},
                                       {1.0, 1.0, 10.0, 0.0, 30.0, 60.0, 0.0, 0, 2, 0},
                                       {1e-4, 1.49, 2000.0, 400.0, 57.0, 0.0, 10.0, 0, 1, 1},
                                       {0.05, 1.586, 0.01, 0.0, 0.0, 4.0, 0.0, 0, 0, 0},
                                       {1e-4, 1.49, 160.0, 0.0, 0.0, 0.0, 0.0, 0, 0, 0},
                                       {0.002, 1.586, 100.0, 905.0, 30.0, 3.0, 10.0, 1, 2, 0}};
    for (const Diffracting& d : diffracting) {
        Params p;
        p.roughness = d.roughness;
        p.ior = d.ior;
        p.prism_pitch = d.pitch;
        p.wavelength = d.wavelength;
        p.abbe_number = d.abbe;
        p.dihedral_error = d.dihedral;
        p.cant_angle = d.cant;
        p.era_mode = d.era;
        p.prism_reflection = d.prism;
        p.fidelity = d.fidelity;
        p.orientation = 17.0;
        p.diffuse_color = {1.0, 1.0, 1.0};
        p.retro_color = {1.0, 1.0, 1.0};
        out.push_back(
            {"roughness=" + std::to_string(d.roughness) + " ior=" + std::to_string(d.ior) +
                 " pitch=" + std::to_string(d.pitch) +
                 " wavelength=" + std::to_string(d.wavelength) + " abbe=" + std::to_string(d.abbe) +
                 " era=" + std::to_string(d.era) + " prism=" + std::to_string(d.prism) +
                 " dihedral=" + std::to_string(d.dihedral) + " cant=" + std::to_string(d.cant) +
                 " fidelity=" + std::to_string(d.fidelity),
             p});
    }
    return out;
}

CommandRun run_command(const std::string& cmd) {
    FILE* p = popen((cmd + " 2>&1").c_str(), "r");
    if (!p) throw std::runtime_error("cannot run " + cmd);
    CommandRun r;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0)
        r.output.append(buf, n);
    const int st = pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

CommandRun run_cli(const std::string& args) {
    return run_command(std::string(RP_CLI_PATH) + " " + args);
}

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

std::vector<CorpusFile> fuzz_corpus(const std::string& target) {
    namespace fs = std::filesystem;
    std::vector<CorpusFile> out;
    for (const auto& entry :
         fs::directory_iterator(fs::path(RP_SOURCE_DIR) / "fuzz" / "corpus" / target)) {
        std::ifstream in(entry.path(), std::ios::binary);
        out.push_back({entry.path().string(),
                       {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()}});
    }
    return out;
}

} // namespace rptest
