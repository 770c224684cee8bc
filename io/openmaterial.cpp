#include "openmaterial.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "error.h"
#include "query.h"

namespace retroprism {

namespace {

using json = nlohmann::json;

constexpr double kTwoPi = 6.283185307179586;
// The schema's bounds (material_brdf_schema.json 1.1.0): wavelengths in m, angles in rad as the
// schema writes them (pi/2 and 2 pi to 7 digits).
constexpr double kMinWavelength = 1e-9, kMaxWavelength = 17.16e-3;
constexpr double kMaxTheta = 1.570796, kMaxPhi = 6.283185;

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.9g", v);
    return b;
}

const json& member(const json& j, const char* key, const std::string& path,
                   const std::string& source) {
    if (!j.is_object() || !j.contains(key))
        throw InputError(source + ": " + path + key + ": required");
    return j.at(key);
}

std::string string_field(const json& j, const char* key, const std::string& path,
                         const std::string& source) {
    const json& v = member(j, key, path, source);
    if (!v.is_string()) throw InputError(source + ": " + path + key + ": expected a string");
    return v.get<std::string>();
}

std::vector<std::string> string_list(const json& j, const char* key, const std::string& path,
                                     const std::string& source) {
    const json& v = member(j, key, path, source);
    if (!v.is_array() || v.empty())
        throw InputError(source + ": " + path + key + ": expected an array of at least one string");
    std::vector<std::string> out;
    for (const json& s : v) {
        if (!s.is_string())
            throw InputError(source + ": " + path + key + ": expected an array of strings");
        out.push_back(s.get<std::string>());
    }
    return out;
}

double number_in(const json& v, const std::string& field, double lo, double hi,
                 const std::string& source) {
    if (v.is_null())
        throw InputError(
            source + ": " + field +
            ": null (allowed by the schema, but its meaning is not defined; not read)");
    if (!v.is_number()) throw InputError(source + ": " + field + ": expected a number");
    const double x = v.get<double>();
    if (!(x >= lo && x <= hi))
        throw InputError(source + ": " + field + " " + num(x) + ": must be in [" + num(lo) + ", " +
                         num(hi) + "]");
    return x;
}

// The schema's patterns: N.N.N (digits) and 8-4-4-4-12 hexadecimal digits.
bool semantic_version(const std::string& v) {
    int parts = 0, digits = 0;
    for (char c : v) {
        if (c >= '0' && c <= '9') {
            ++digits;
        } else if (c == '.' && digits > 0) {
            ++parts;
            digits = 0;
        } else {
            return false;
        }
    }
    return parts == 2 && digits > 0;
}
bool uuid_form(const std::string& u) {
    static const int groups[5] = {8, 4, 4, 4, 12};
    std::size_t at = 0;
    for (int g = 0; g < 5; ++g) {
        for (int k = 0; k < groups[g]; ++k, ++at)
            if (at >= u.size() || !std::isxdigit(static_cast<unsigned char>(u[at]))) return false;
        if (g < 4 && (at >= u.size() || u[at++] != '-')) return false;
    }
    return at == u.size();
}

OpenMaterialMetadata parse_metadata(const json& j, const std::string& source) {
    const json& m = member(j, "metadata", "", source);
    if (!m.is_object()) throw InputError(source + ": metadata: expected an object");
    OpenMaterialMetadata out;
    const std::string p = "metadata.";
    out.name = string_field(m, "name", p, source);
    out.uuid = string_field(m, "uuid", p, source);
    out.material_version = string_field(m, "materialVersion", p, source);
    out.openmaterial_version = string_field(m, "openMaterial3dVersion", p, source);
    if (!uuid_form(out.uuid))
        throw InputError(source + ": metadata.uuid " + out.uuid +
                         ": expected 8-4-4-4-12 hexadecimal digits");
    for (const auto& [key, value] :
         {std::make_pair("materialVersion", out.material_version),
          std::make_pair("openMaterial3dVersion", out.openmaterial_version)})
        if (!semantic_version(value))
            throw InputError(source + ": metadata." + key + " " + value +
                             ": expected a semantic version N.N.N");
    out.copyrights = string_list(m, "copyrights", p, source);
    out.license = string_field(m, "license", p, source);
    out.authors = string_list(m, "authors", p, source);
    out.sources = string_field(m, "sources", p, source);
    if (m.contains("description")) out.description = string_field(m, "description", p, source);
    if (m.contains("typicalSensorTechnology"))
        out.sensor_technology = string_field(m, "typicalSensorTechnology", p, source);
    return out;
}

bool same_wavelength(double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b));
}

using Row = std::array<double, 5>;
using Iter = std::vector<Row>::const_iterator;

// Linear interpolation over column `col` of the sorted rows [b, e) (all equal in the columns
// before it), the value of each bracketing group given by `inner`; clamped at the ends.
template <class Inner>
double interpolate_column(Iter b, Iter e, int col, double x, const Inner& inner) {
    const auto less = [col](const Row& r, double v) { return r[col] < v; };
    const auto group = [&](double v) {
        const Iter lo = std::lower_bound(b, e, v, less);
        Iter hi = lo;
        while (hi != e && (*hi)[col] == v)
            ++hi;
        return std::make_pair(lo, hi);
    };
    Iter at = std::lower_bound(b, e, x, less);
    if (at == e) --at;
    const double v1 = (*at)[col];
    if (x >= v1 || at == b) {
        const auto g = group(v1);
        return inner(g.first, g.second);
    }
    const double v0 = (*(at - 1))[col];
    const auto g0 = group(v0), g1 = group(v1);
    const double t = (x - v0) / (v1 - v0);
    return (1.0 - t) * inner(g0.first, g0.second) + t * inner(g1.first, g1.second);
}

// phi_o over the rows [b, e) of one theta_i and theta_o, periodic over 2 pi.
double interpolate_phi(Iter b, Iter e, double phi) {
    phi = std::fmod(phi, kTwoPi);
    if (phi < 0) phi += kTwoPi;
    const auto less = [](const Row& r, double v) { return r[3] < v; };
    Iter at = std::lower_bound(b, e, phi, less);
    // Between the last row and the first one plus 2 pi when phi is outside [first, last].
    const Row& r1 = at == e ? *b : *at;
    const Row& r0 = at == b ? *(e - 1) : *(at - 1);
    double p0 = r0[3], p1 = r1[3];
    if (at == e) p1 += kTwoPi;
    if (at == b) p0 -= kTwoPi;
    if (!(p1 > p0)) return r1[4];
    const double t = (phi - p0) / (p1 - p0);
    return (1.0 - t) * r0[4] + t * r1[4];
}

} // namespace

BrdfTable parse_brdf_table(const json& j, const std::string& source) {
    if (!j.is_object()) throw InputError(source + ": expected a JSON object");
    BrdfTable t;
    t.metadata = parse_metadata(j, source);
    const json& brdf = member(j, "brdf", "", source);
    if (!brdf.is_object()) throw InputError(source + ": brdf: expected an object");
    const json& w = member(brdf, "wavelengths", "brdf.", source);
    if (!w.is_array() || w.empty())
        throw InputError(source + ": brdf.wavelengths: expected an array of at least one number");
    for (std::size_t i = 0; i < w.size(); ++i)
        t.wavelengths.push_back(number_in(w[i], "brdf.wavelengths[" + std::to_string(i) + "]",
                                          kMinWavelength, kMaxWavelength, source));
    if (brdf.contains("receiverSolidAngles")) {
        const json& r = brdf.at("receiverSolidAngles");
        if (!r.is_array())
            throw InputError(source + ": brdf.receiverSolidAngles: expected an array");
        for (std::size_t i = 0; i < r.size(); ++i) {
            const std::string p = "brdf.receiverSolidAngles[" + std::to_string(i) + "].";
            ReceiverSolidAngle s;
            s.wavelength = number_in(member(r[i], "wavelength", p, source), p + "wavelength",
                                     kMinWavelength, kMaxWavelength, source);
            s.solid_angle = number_in(member(r[i], "solidAngle", p, source), p + "solidAngle", 0.0,
                                      4.0 * M_PI, source);
            if (!(s.solid_angle > 0))
                throw InputError(source + ": " + p + "solidAngle: must be above 0");
            t.receiver_solid_angles.push_back(s);
        }
    }
    const json& rows = member(brdf, "lookupTable", "brdf.", source);
    if (!rows.is_array() || rows.empty())
        throw InputError(source + ": brdf.lookupTable: expected an array of at least one row");
    const double hi[5] = {kMaxWavelength, kMaxTheta, kMaxTheta, kMaxPhi, HUGE_VAL};
    const double lo[5] = {kMinWavelength, 0.0, 0.0, 0.0, 0.0};
    const char* names[5] = {"wavelength", "theta_i", "theta_o", "phi_o", "f"};
    t.rows.reserve(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const std::string p = "brdf.lookupTable[" + std::to_string(i) + "]";
        if (!rows[i].is_array() || rows[i].size() != 5)
            throw InputError(source + ": " + p +
                             ": expected [wavelength, theta_i, theta_o, phi_o, f]");
        Row r;
        for (int c = 0; c < 5; ++c)
            r[c] = number_in(rows[i][c], p + "[" + std::to_string(c) + "] (" + names[c] + ")",
                             lo[c], hi[c], source);
        if (std::none_of(t.wavelengths.begin(), t.wavelengths.end(),
                         [&](double x) { return same_wavelength(x, r[0]); }))
            throw InputError(source + ": " + p + "[0] (wavelength) " + num(r[0]) +
                             ": not among brdf.wavelengths");
        if (!t.rows.empty()) {
            const Row& q = t.rows.back();
            if (!std::lexicographical_compare(q.begin(), q.begin() + 4, r.begin(), r.begin() + 4))
                throw InputError(source + ": " + p +
                                 ": rows must be sorted by wavelength, theta_i, theta_o, phi_o, "
                                 "each row after the one before (no repeats)");
        }
        t.rows.push_back(r);
    }
    return t;
}

BrdfTable read_brdf_table(const std::string& path) {
    return parse_brdf_table(read_json(path), path);
}

namespace {

json metadata_json(const OpenMaterialMetadata& m, bool withSources) {
    json j;
    j["name"] = m.name;
    if (!m.description.empty()) j["description"] = m.description;
    j["uuid"] = m.uuid;
    j["materialVersion"] = m.material_version;
    j["openMaterial3dVersion"] = m.openmaterial_version;
    j["copyrights"] = m.copyrights;
    j["license"] = m.license;
    j["authors"] = m.authors;
    if (withSources) j["sources"] = m.sources;
    if (withSources && !m.sensor_technology.empty())
        j["typicalSensorTechnology"] = m.sensor_technology;
    return j;
}

// A number as its 9-significant-digit decimal, so that the JSON writes it short.
double rounded(double v) {
    return std::strtod(num(v).c_str(), nullptr);
}

} // namespace

std::string brdf_table_json(const BrdfTable& t) {
    json wavelengths = json::array(), solid = json::array();
    for (double w : t.wavelengths)
        wavelengths.push_back(rounded(w));
    for (const ReceiverSolidAngle& s : t.receiver_solid_angles)
        solid.push_back(
            {{"wavelength", rounded(s.wavelength)}, {"solidAngle", rounded(s.solid_angle)}});
    std::ostringstream out;
    out << "{\n  \"metadata\": " << metadata_json(t.metadata, true).dump() << ",\n  \"brdf\": {\n"
        << "    \"wavelengths\": " << wavelengths.dump() << ",\n";
    if (!t.receiver_solid_angles.empty())
        out << "    \"receiverSolidAngles\": " << solid.dump() << ",\n";
    out << "    \"lookupTable\": [\n";
    for (std::size_t i = 0; i < t.rows.size(); ++i) {
        json row = json::array();
        for (double v : t.rows[i])
            row.push_back(rounded(v));
        out << "      " << row.dump() << (i + 1 < t.rows.size() ? ",\n" : "\n");
    }
    out << "    ]\n  }\n}\n";
    return out.str();
}

std::string material_json(const OpenMaterialMetadata& m, double coefficientOfRetroreflection,
                          const std::string& raSources, const std::vector<std::string>& brdfUris) {
    json j;
    j["metadata"] = metadata_json(m, false);
    j["materialProperties"]["retroreflectivityData"] = {
        {"coefficientOfRetroreflection", rounded(coefficientOfRetroreflection)},
        {"sources", raSources}};
    j["materialProperties"]["brdfUris"] = brdfUris;
    return j.dump(2) + "\n";
}

std::string uuid_from(const std::string& text) {
    // FNV-1a 64 (Fowler, Noll, Vo) twice, from two offset bases, for 128 bits.
    auto fnv = [&](std::uint64_t h) {
        for (unsigned char c : text)
            h = (h ^ c) * 0x100000001b3ULL;
        return h;
    };
    std::uint64_t a = fnv(0xcbf29ce484222325ULL), b = fnv(0x84222325cbf29ce4ULL);
    // RFC 9562: version 8 (custom), variant 10.
    a = (a & ~0xF000ULL) | 0x8000ULL;
    b = (b & ~(3ULL << 62)) | (2ULL << 62);
    char s[40];
    std::snprintf(s, sizeof s, "%08x-%04x-%04x-%04x-%012llx", unsigned(a >> 32),
                  unsigned((a >> 16) & 0xFFFF), unsigned(a & 0xFFFF), unsigned(b >> 48),
                  static_cast<unsigned long long>(b & 0xFFFFFFFFFFFFULL));
    return s;
}

std::optional<double> brdf_table_value(const BrdfTable& t, double wavelength, double thetaI,
                                       double thetaO, double phiO) {
    const auto less = [](const Row& r, double v) { return r[0] < v; };
    Iter b = std::lower_bound(t.rows.begin(), t.rows.end(), wavelength * (1.0 - 1e-9), less);
    if (b == t.rows.end() || !same_wavelength((*b)[0], wavelength)) return std::nullopt;
    Iter e = b;
    while (e != t.rows.end() && (*e)[0] == (*b)[0])
        ++e;
    return interpolate_column(b, e, 1, thetaI, [&](Iter bi, Iter ei) {
        return interpolate_column(bi, ei, 2, thetaO,
                                  [&](Iter bo, Iter eo) { return interpolate_phi(bo, eo, phiO); });
    });
}

} // namespace retroprism
