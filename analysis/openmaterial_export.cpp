#include "openmaterial_export.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "error.h"
#include "parallel.h"
#include "photometry.h"
#include "query.h"

namespace retroprism {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// theta_o and theta_i stay below 89 degrees (the schema's pi/2 is written to 7 digits).
constexpr double kMaxThetaDeg = 89.0;
// Where theta_o is this close to theta_i, phi_o is sampled finely about 0 and 180 degrees.
constexpr double kNearRetroDeg = 5.0;

std::vector<double> sorted_unique(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    v.erase(
        std::unique(v.begin(), v.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
        v.end());
    return v;
}

std::vector<double> theta_o_grid(double thetaIDeg) {
    std::vector<double> v;
    for (double t = 0; t <= 88.0; t += 4.0)
        v.push_back(t);
    v.push_back(thetaIDeg);
    for (double d : kRetroOffsetsDeg)
        for (double s : {-1.0, 1.0}) {
            const double t = thetaIDeg + s * d;
            if (t >= 0.0 && t <= kMaxThetaDeg) v.push_back(t);
        }
    return sorted_unique(v);
}

std::vector<double> phi_o_grid(double thetaIDeg, double thetaODeg) {
    std::vector<double> v;
    for (double p = 0; p < 360.0; p += 15.0)
        v.push_back(p);
    if (std::abs(thetaODeg - thetaIDeg) <= kNearRetroDeg) {
        const double s = std::max(std::sin(thetaODeg * kDeg), 1e-3);
        for (double d : kRetroOffsetsDeg) {
            const double dp = std::min(d / s, 90.0);
            for (double centre : {0.0, 180.0, 360.0})
                for (double sign : {-1.0, 1.0}) {
                    const double p = centre + sign * dp;
                    if (p >= 0.0 && p < 360.0) v.push_back(p);
                }
        }
    }
    return sorted_unique(v);
}

} // namespace

IsotropicNode::IsotropicNode(const Params& material, double wavelengthNm, int channel)
    : node_(PrismaticRetroreflector<double>(ra_params(material)).at_wavelength(wavelengthNm)),
      channel_(channel) {
    const int mode = sanitize(material).era_mode;
    rotations_ = mode == 0 ? 1 : kTableRotations;
    period_ = mode == 1 ? 180.0 : 120.0;
}

double IsotropicNode::f(double thetaI, double thetaO, double phiO) const {
    double sum = 0;
    for (int k = 0; k < rotations_; ++k) {
        const double e = rotations_ == 1 ? 0.0 : -period_ * (k + 0.5) / rotations_ * kDeg;
        const glm::dvec3 wi(std::sin(thetaI) * std::cos(e), std::sin(thetaI) * std::sin(e),
                            std::cos(thetaI));
        const glm::dvec3 wo(std::sin(thetaO) * std::cos(phiO + e),
                            std::sin(thetaO) * std::sin(phiO + e), std::cos(thetaO));
        sum += node_.f(wi, wo).total()[channel_];
    }
    return sum / rotations_;
}

BrdfTable node_brdf_table(const Params& material, const OpenMaterialExport& e) {
    for (double nm : e.wavelengths_nm)
        if (!(nm > 0.0 && nm <= 2000.0))
            throw InputError("--wavelength " + std::to_string(nm) + ": must be in (0, 2000] nm");
    if (e.channel < 0 || e.channel > 2)
        throw InputError("--channel: expected 0 (red), 1 (green) or 2 (blue)");
    BrdfTable t;
    const std::vector<double> nms = sorted_unique(e.wavelengths_nm);
    std::string inputs = params_to_json(material).dump();
    for (double nm : nms)
        inputs += " " + std::to_string(nm);
    OpenMaterialMetadata& m = t.metadata;
    m.name = e.name;
    m.description = e.description;
    m.uuid = uuid_from(inputs + " channel " + std::to_string(e.channel));
    m.copyrights = {"unspecified"};
    m.license = "unspecified";
    m.authors = {"retroprism export"};
    m.sources = "simulated: the retroprism prismatic retroreflector node (Guo, Guo & Pan 2018, "
                "with diffraction at the prism aperture), colour channel " +
                std::string(1, "rgb"[e.channel]) +
                ", averaged over the rotation about the "
                "normal; inputs " +
                params_to_json(material).dump();
    m.sensor_technology = "lidar";
    for (double nm : nms) {
        t.wavelengths.push_back(nm * 1e-9);
        const IsotropicNode node(material, nm, e.channel);
        std::vector<double> thetaI;
        for (double ti = 0; ti <= 85.0; ti += 5.0)
            thetaI.push_back(ti);
        std::vector<std::vector<std::array<double, 5>>> slices(thetaI.size());
        parallel_for(thetaI.size(), 0, [&](std::size_t i) {
            for (double to : theta_o_grid(thetaI[i]))
                for (double po : phi_o_grid(thetaI[i], to))
                    slices[i].push_back({nm * 1e-9, thetaI[i] * kDeg, to * kDeg, po * kDeg,
                                         node.f(thetaI[i] * kDeg, to * kDeg, po * kDeg)});
        });
        for (const auto& s : slices)
            t.rows.insert(t.rows.end(), s.begin(), s.end());
    }
    return t;
}

double openmaterial_ra(const Params& material) {
    const PrismaticRetroreflector<double> node(ra_params(material));
    const double ra = luminance_709(ra_value(node, -4.0, 0.2, 0.0));
    if (!(ra <= 5000.0))
        throw InputError("the material's R_A " + std::to_string(ra) +
                         " cd lx^-1 m^-2 is above the 5000 OpenMATERIAL's schema allows "
                         "(coefficientOfRetroreflection)");
    return ra;
}

BrdfTable write_openmaterial(const Params& material, const OpenMaterialExport& e,
                             const std::string& dir) {
    namespace fs = std::filesystem;
    const BrdfTable t = node_brdf_table(material, e);
    const double ra = openmaterial_ra(material);
    const std::string tableName = e.name + "_brdf.xompt";
    auto write = [&](const std::string& file, const std::string& text) {
        const fs::path path = fs::path(dir) / file, tmp = path.string() + ".tmp";
        {
            std::ofstream out(tmp, std::ios::binary);
            out << text;
            if (!out) throw InputError(path.string() + ": cannot write");
        }
        fs::rename(tmp, path);
    };
    write(tableName, brdf_table_json(t));
    write(e.name + ".xomp",
          material_json(t.metadata, ra,
                        "simulated: the retroprism node's R_A (luminance Y of its colour channels) "
                        "at observation 0.2 deg, entrance -4 deg, rotation 0 (ASTM E810 "
                        "geometry)",
                        {tableName}));
    return t;
}

TableCheck check_brdf_table(const BrdfTable& t, const Params& material, int channel) {
    TableCheck c;
    std::vector<double> centre;
    for (double w : t.wavelengths) {
        const double nm = w * 1e9;
        const IsotropicNode node(material, nm, channel);
        double fmax = 0;
        for (const auto& r : t.rows)
            if (r[0] == w) fmax = std::max(fmax, r[4]);
        for (std::size_t i = 0; i < t.rows.size(); ++i) {
            const auto& r = t.rows[i];
            if (r[0] != w) continue;
            ++c.rows;
            const double f = node.f(r[1], r[2], r[3]);
            if (f > 1e-6 * fmax)
                c.max_row_error = std::max(c.max_row_error, std::abs(r[4] / f - 1.0));
            if (std::abs(r[2] - r[1]) > kNearRetroDeg * kDeg) continue;
            // Centres near the retro direction: toward the next phi_o of the same theta_o, and
            // (from phi_o 0) toward the next theta_o in the plane of incidence.
            auto centreAt = [&](double theta, double phi) {
                const double exact = node.f(r[1], theta, phi);
                if (!(exact > 1e-3 * fmax)) return;
                const std::optional<double> v = brdf_table_value(t, w, r[1], theta, phi);
                if (v) centre.push_back(std::abs(*v / exact - 1.0));
            };
            if (i + 1 < t.rows.size() && t.rows[i + 1][0] == w && t.rows[i + 1][1] == r[1] &&
                t.rows[i + 1][2] == r[2])
                centreAt(r[2], 0.5 * (r[3] + t.rows[i + 1][3]));
            if (r[3] != 0.0) continue;
            std::size_t j = i + 1;
            while (j < t.rows.size() && t.rows[j][0] == w && t.rows[j][1] == r[1] &&
                   t.rows[j][2] == r[2])
                ++j;
            if (j < t.rows.size() && t.rows[j][0] == w && t.rows[j][1] == r[1])
                centreAt(0.5 * (r[2] + t.rows[j][2]), 0.0);
        }
    }
    c.centres = centre.size();
    if (!centre.empty()) {
        std::sort(centre.begin(), centre.end());
        c.median_centre_error = centre[centre.size() / 2];
        c.p90_centre_error = centre[centre.size() * 9 / 10];
        c.max_centre_error = centre.back();
    }
    return c;
}

} // namespace retroprism
