// fuzz_checks_luminaire.h: the property fuzz_luminaire checks, in the form of fuzz_checks.h
// (shared by the target and by the [luminaire] test that replays fuzz/corpus/luminaire): the
// first byte picks the reader (0 IES LM-63, 1 EULUMDAT, 2 candela CSV; any other byte modulo
// 3), the rest is the file. The reader either returns a distribution or throws an InputError
// starting with FILE:LINE; nothing else. A distribution it returns has at least one angle per
// axis, strictly ascending and within the type's range, one finite non-negative candela value
// per grid point and a finite non-negative multiplier; intensity() in directions spread over the
// sphere (and at the zero and non-finite vectors) and intensity_at() at every grid point and
// between them is finite and non-negative, and at a grid point equals the grid's value.
#pragma once

#include <cmath>
#include <cctype>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>

#include "fuzz_checks.h"
#include "luminaire.h"

namespace rpfuzz {

inline bool starts_with_file_line(const std::string& message, const std::string& name) {
    if (message.rfind(name + ":", 0) != 0) return false;
    const size_t k = name.size() + 1;
    return k < message.size() && std::isdigit(static_cast<unsigned char>(message[k]));
}

inline void check_luminaire_grid(const retroprism::LuminousIntensityDistribution& d) {
    const bool typeC = d.type == retroprism::PhotometricType::C;
    auto ascending = [](const std::vector<double>& a, double lo, double hi) {
        for (size_t k = 0; k < a.size(); ++k)
            if (!(a[k] >= lo && a[k] <= hi) || (k > 0 && !(a[k] > a[k - 1]))) return false;
        return !a.empty();
    };
    if (!ascending(d.vertical_deg, typeC ? 0 : -90, typeC ? 180 : 90) ||
        !ascending(d.horizontal_deg, typeC ? 0 : -180, typeC ? 360 : 180))
        throw Violation("angles out of range or not ascending passed the reader");
    if (d.candela.size() != d.vertical_deg.size() * d.horizontal_deg.size())
        throw Violation("the candela grid does not have one value per pair of angles");
    if (!(d.multiplier >= 0 && std::isfinite(d.multiplier)))
        throw Violation("a multiplier " + hexfloat(d.multiplier) + " passed the reader");
    for (double c : d.candela)
        if (!(c >= 0 && std::isfinite(c))) throw Violation("candela " + hexfloat(c) + " passed");
}

inline void check_luminaire_lookup(const retroprism::LuminousIntensityDistribution& d) {
    auto ok = [](double v) { return v >= 0 && std::isfinite(v); };
    const size_t nv = d.vertical_deg.size();
    for (size_t h = 0; h < d.horizontal_deg.size(); h += 1 + d.horizontal_deg.size() / 16)
        for (size_t v = 0; v < nv; v += 1 + nv / 16) {
            const double at = d.intensity_at(d.horizontal_deg[h], d.vertical_deg[v]);
            const double mid = d.intensity_at(d.horizontal_deg[h] + 0.37, d.vertical_deg[v] + 0.37);
            if (!ok(at) || !ok(mid)) throw Violation("intensity_at is negative or not finite");
            // The first plane is never folded by a symmetry, so its grid points are its values.
            if (h == 0 && std::abs(at - d.candela[v]) > 1e-9 * (1 + std::abs(d.candela[v])))
                throw Violation("intensity_at a grid point of the first plane is not its value");
        }
    for (int k = 0; k < 64; ++k) {
        const double z = -1 + (k + 0.5) / 32, r = std::sqrt(std::max(0.0, 1 - z * z));
        const double phi = k * 2.399963229728653;
        if (!ok(d.intensity({r * std::cos(phi), z, r * std::sin(phi)})))
            throw Violation("intensity is negative or not finite");
    }
    const double inf = std::numeric_limits<double>::infinity();
    if (d.intensity({0, 0, 0}) != 0 || d.intensity({inf, 0, 1}) != 0 ||
        d.intensity({std::nan(""), 0, 1}) != 0)
        throw Violation("intensity of the zero or a non-finite vector is not 0");
}

inline void check_luminaire(const std::uint8_t* data, size_t size) {
    if (size == 0) return;
    const int format = data[0] % 3;
    const char* const names[3] = {"fuzz_lamp.ies", "fuzz_lamp.ldt", "fuzz_lamp.csv"};
    const std::string name = names[format];
    std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
    retroprism::LuminousIntensityDistribution d;
    try {
        d = format == 0   ? retroprism::parse_ies(in, name)
            : format == 1 ? retroprism::parse_eulumdat(in, name)
                          : retroprism::parse_candela_csv(in, name);
    } catch (const retroprism::InputError& e) {
        if (!starts_with_file_line(e.what(), name))
            throw Violation(std::string("the reader's error does not start with FILE:LINE: ") +
                            e.what());
        return;
    } catch (const std::exception& e) {
        throw Violation(std::string("the reader threw ") + typeid(e).name() + ": " + e.what());
    }
    check_luminaire_grid(d);
    check_luminaire_lookup(d);
}

} // namespace rpfuzz
