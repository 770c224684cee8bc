#include "photometry.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "photopic.h"

namespace retroprism {

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
}

double luminance_709(const glm::dvec3& rgb) {
    return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z;
}

const std::vector<double>& ra_observation_angles() {
    static const std::vector<double> v = {0.2, 0.33, 0.5, 1.0, 1.5};
    return v;
}

const std::vector<double>& ra_entrance_angles() {
    static const std::vector<double> v = {-4.0, 15.0, 30.0, 40.0, 45.0};
    return v;
}

void ra_directions(double entranceDeg, double observationDeg, double rotationDeg, glm::dvec3& wi,
                   glm::dvec3& wo, double presentationDeg) {
    const double b = entranceDeg * kDeg, o = (entranceDeg - observationDeg) * kDeg;
    const glm::dvec3 i(std::sin(b), 0.0, std::cos(b)), coplanar(std::sin(o), 0.0, std::cos(o));
    // Rodrigues: the observation axis about the illumination axis by gamma.
    const double g = presentationDeg * kDeg;
    const glm::dvec3 v = presentationDeg == 0.0
                             ? coplanar
                             : coplanar * std::cos(g) + glm::cross(i, coplanar) * std::sin(g) +
                                   i * (glm::dot(i, coplanar) * (1.0 - std::cos(g)));
    const double e = -rotationDeg * kDeg, c = std::cos(e), s = std::sin(e);
    auto turn = [&](const glm::dvec3& w) {
        return glm::dvec3(c * w.x - s * w.y, s * w.x + c * w.y, w.z);
    };
    wi = turn(i);
    wo = turn(v);
}

RaGeometry ra_geometry(const glm::dvec3& wiIn, const glm::dvec3& woIn) {
    const glm::dvec3 wi = glm::normalize(wiIn), wo = glm::normalize(woIn);
    RaGeometry g;
    auto angle = [](const glm::dvec3& a, const glm::dvec3& b) {
        return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) / kDeg;
    };
    g.entrance = angle(wi, glm::dvec3(0, 0, 1));
    g.observation = angle(wi, wo);
    // ra_directions turns (sin beta, 0, cos beta) by -epsilon about the normal.
    if (std::hypot(wi.x, wi.y) > 0) g.rotation = -std::atan2(wi.y, wi.x) / kDeg;
    if (g.rotation <= -180) g.rotation += 360;
    const double e = g.rotation * kDeg, c = std::cos(e), s = std::sin(e);
    auto unturn = [&](const glm::dvec3& w) {
        return glm::dvec3(c * w.x - s * w.y, s * w.x + c * w.y, w.z);
    };
    const glm::dvec3 i = unturn(wi), v = unturn(wo);
    const double o = (g.entrance - g.observation) * kDeg;
    const glm::dvec3 coplanar(std::sin(o), 0.0, std::cos(o));
    // The presentation angle: from the coplanar observation axis to wo about wi (Rodrigues).
    const glm::dvec3 a = coplanar - i * glm::dot(i, coplanar), b = v - i * glm::dot(i, v);
    if (glm::length(a) > 0 && glm::length(b) > 0)
        g.presentation = std::atan2(glm::dot(i, glm::cross(a, b)), glm::dot(a, b)) / kDeg;
    return g;
}

Params ra_params(const Params& material) {
    Params p = material;
    p.normal = {0.0, 0.0, 1.0};
    p.tangent = {1.0, 0.0, 0.0};
    return p;
}

glm::dvec3 ra_value(const PrismaticRetroreflector<double>& node, double entranceDeg,
                    double observationDeg, double rotationDeg) {
    glm::dvec3 wi, wo;
    ra_directions(entranceDeg, observationDeg, rotationDeg, wi, wo);
    return node.eval(wi, wo).f.total() * (wi.z * wo.z);
}

double ra_at_entry(const RaEntry& e,
                   const std::function<glm::dvec3(double, double, double, double)>& ra) {
    auto y = [&](double rotation) {
        return luminance_709(ra(e.entrance_deg, e.observation_deg, rotation, e.presentation_deg));
    };
    return e.rotation_deg ? y(*e.rotation_deg) : 0.5 * (y(0.0) + y(90.0));
}

double ra_at_entry(const PrismaticRetroreflector<double>& node, const RaEntry& e) {
    return ra_at_entry(
        e, [&](double entrance, double observation, double rotation, double presentation) {
            glm::dvec3 wi, wo;
            ra_directions(entrance, observation, rotation, wi, wo, presentation);
            return glm::dvec3(node.eval(wi, wo).f.total()) * (wi.z * wo.z);
        });
}

void for_each_wavelength(
    const PrismaticRetroreflector<double>& node, RaSpectrum spectrum,
    const std::function<void(const PrismaticRetroreflector<double>&, double)>& f) {
    if (spectrum == RaSpectrum::Channels) {
        f(node, 1.0);
        return;
    }
    for (size_t k = 0; k < photopic_weights().size(); ++k)
        f(node.at_wavelength(photopic_wavelengths_nm()[k]), photopic_weights()[k]);
}

RaTable ra_table(const Params& material, double rotationDeg, const std::vector<double>& observation,
                 const std::vector<double>& entrance, RaSpectrum spectrum) {
    // A few dozen directions: the azimuth averages integrated rather than tabulated.
    const PrismaticRetroreflector<double> node(
        ra_params(material), PrismaticRetroreflector<double>::Averages::Integrated);
    RaTable t;
    t.observation = observation;
    t.entrance = entrance;
    t.rotation = rotationDeg;
    t.rgb.assign(observation.size(), std::vector<glm::dvec3>(entrance.size(), glm::dvec3(0.0)));
    for_each_wavelength(node, spectrum, [&](const PrismaticRetroreflector<double>& n, double w) {
        for (size_t i = 0; i < observation.size(); ++i)
            for (size_t j = 0; j < entrance.size(); ++j) {
                const glm::dvec3 v = ra_value(n, entrance[j], observation[i], rotationDeg);
                t.rgb[i][j] +=
                    spectrum == RaSpectrum::Channels ? v : glm::dvec3(w * luminance_709(v));
            }
    });
    return t;
}

RaTable ra_table(const BrdfBatch& f, double rotationDeg, const std::vector<double>& observation,
                 const std::vector<double>& entrance) {
    std::vector<std::array<glm::dvec3, 2>> pairs;
    for (double a : observation)
        for (double b : entrance) {
            glm::dvec3 wi, wo;
            ra_directions(b, a, rotationDeg, wi, wo);
            pairs.push_back({wi, wo});
        }
    const std::vector<glm::dvec3> values = f(pairs);
    if (values.size() != pairs.size())
        throw std::runtime_error("ra_table: the BRDF returned " + std::to_string(values.size()) +
                                 " values for " + std::to_string(pairs.size()) + " directions");
    RaTable t;
    t.observation = observation;
    t.entrance = entrance;
    t.rotation = rotationDeg;
    size_t k = 0;
    for (size_t i = 0; i < observation.size(); ++i) {
        std::vector<glm::dvec3> row;
        for (size_t j = 0; j < entrance.size(); ++j, ++k)
            row.push_back(values[k] * (pairs[k][0].z * pairs[k][1].z));
        t.rgb.push_back(row);
    }
    return t;
}

RaDeviation ra_deviation(const RaTable& reference, const RaTable& t) {
    if (reference.observation != t.observation || reference.entrance != t.entrance)
        throw std::runtime_error("ra_deviation: the tables' angles differ");
    RaDeviation d;
    for (size_t i = 0; i < t.observation.size(); ++i) {
        std::vector<double> row;
        for (size_t j = 0; j < t.entrance.size(); ++j) {
            const double r = luminance_709(reference.rgb[i][j]);
            const double y = luminance_709(t.rgb[i][j]);
            const double rel = r > 0 ? (y - r) / r : (y == 0 ? 0.0 : INFINITY);
            row.push_back(rel);
            if (std::abs(rel) > d.max_abs || (i == 0 && j == 0)) {
                d.max_abs = std::abs(rel);
                d.observation = t.observation[i];
                d.entrance = t.entrance[j];
            }
        }
        d.relative.push_back(row);
    }
    return d;
}

} // namespace retroprism
