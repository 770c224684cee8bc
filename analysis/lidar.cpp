#include "lidar.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "color.h"
#include "error.h"
#include "parallel.h"
#include "photometry.h"
#include "quadrature.h"
#include "query.h"
#include "ra_fit.h"
#include "ra_table.h"
#include "parse.h"

namespace retroprism {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

struct GaussLegendre {
    std::vector<double> x, w;
};
GaussLegendre gauss_legendre_rule(int n) {
    GaussLegendre g;
    gauss_legendre(n, g.x, g.w);
    return g;
}

// A unit tangent orthogonal to the unit normal n, from t (any orthogonal one when t is parallel
// to n, zero or not finite).
glm::dvec3 orthogonal_tangent(const glm::dvec3& n, const glm::dvec3& t) {
    glm::dvec3 u = t - n * glm::dot(n, t);
    if (!(glm::dot(u, u) > 1e-20)) {
        u = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        u -= n * glm::dot(n, u);
    }
    return glm::normalize(u);
}

// The target's frame at the beam's centre (lidar.h): normal toward the sensor, the width's
// direction, the height's direction (+y).
struct TargetFrame {
    glm::dvec3 centre, normal, width, height;
};
TargetFrame target_frame(const LidarTarget& t) {
    const double b = t.entrance_deg * kDeg;
    return {glm::dvec3(0, 0, t.range_m), glm::dvec3(std::sin(b), 0, -std::cos(b)),
            glm::dvec3(-std::cos(b), 0, -std::sin(b)), glm::dvec3(0, 1, 0)};
}

// The footprint's bounding box in the target's (width, height) coordinates: the hits of rays on
// the truncation circle, with a margin.
struct Box {
    double u0, u1, v0, v1;
};
Box beam_box(const TargetFrame& tf, double slope) {
    Box b{1e300, -1e300, 1e300, -1e300};
    const int points = 256;
    for (int i = 0; i < points; ++i) {
        const double a = 2.0 * kPi * i / points;
        const glm::dvec3 dir(slope * std::cos(a), slope * std::sin(a), 1.0);
        const glm::dvec3 x = dir * (glm::dot(tf.centre, tf.normal) / glm::dot(dir, tf.normal));
        const double u = glm::dot(x - tf.centre, tf.width), v = glm::dot(x - tf.centre, tf.height);
        b = {std::min(b.u0, u), std::max(b.u1, u), std::min(b.v0, v), std::max(b.v1, v)};
    }
    const double mu = 0.02 * (b.u1 - b.u0), mv = 0.02 * (b.v1 - b.v0);
    return {b.u0 - mu, b.u1 + mu, b.v0 - mv, b.v1 + mv};
}

// Nodes and weights of two Gauss-Legendre panels over [lo, 0] and [0, hi] (one when 0 is an end).
void two_panels(const GaussLegendre& g, double lo, double hi, std::vector<double>& x,
                std::vector<double>& w) {
    x.clear();
    w.clear();
    const double edges[3] = {lo, std::clamp(0.0, lo, hi), hi};
    for (int p = 0; p < 2; ++p) {
        const double a = edges[p], b = edges[p + 1];
        if (!(b > a)) continue;
        for (std::size_t k = 0; k < g.x.size(); ++k) {
            x.push_back(0.5 * (a + b) + 0.5 * (b - a) * g.x[k]);
            w.push_back(0.5 * (b - a) * g.w[k]);
        }
    }
}

void require(bool ok, const std::string& what, double value, const std::string& allowed) {
    if (!ok) throw InputError(what + " " + number_text(value) + ": must be " + allowed);
}

} // namespace

LidarBrdf lidar_node_brdf(const Params& material, double wavelengthNm, int channel) {
    require(wavelengthNm > 0.0 && wavelengthNm <= 2000.0, "--wavelength", wavelengthNm,
            "in (0, 2000] nm");
    require(channel >= 0 && channel <= 2, "--channel", channel, "0 (red), 1 (green) or 2 (blue)");
    using Node = PrismaticRetroreflector<double>;
    const auto node =
        std::make_shared<const Node>(Node(ra_params(material)).at_wavelength(wavelengthNm));
    // aperture_reflectance evaluates one source direction against every point of the receiver's
    // aperture: the incident state (with a pitch, the diffraction pattern of 12 orientations'
    // apertures) is made once per source direction and thread, keyed by this function's
    // instance, and f(incident(wi), wo) is f(wi, wo) bit for bit.
    static std::atomic<std::uint64_t> instances{0};
    const std::uint64_t id = ++instances;
    return [node, channel, id](const glm::dvec3& wi, const glm::dvec3& wo) {
        struct Last {
            std::uint64_t id = 0;
            glm::dvec3 wi{0.0};
            Node::Incident in;
        };
        thread_local Last last;
        if (last.id != id || last.wi != wi) {
            last.id = id;
            last.wi = wi;
            last.in = node->incident(wi);
        }
        return node->f(last.in, wo).total()[channel];
    };
}

double lidar_node_albedo(const Params& material, double wavelengthNm, int channel,
                         double entranceDeg, double rotationDeg) {
    require(wavelengthNm > 0.0 && wavelengthNm <= 2000.0, "--wavelength", wavelengthNm,
            "in (0, 2000] nm");
    require(channel >= 0 && channel <= 2, "--channel", channel, "0 (red), 1 (green) or 2 (blue)");
    const PrismaticRetroreflector<double> node =
        PrismaticRetroreflector<double>(ra_params(material)).at_wavelength(wavelengthNm);
    glm::dvec3 wi, wo;
    ra_directions(entranceDeg, 0.0, rotationDeg, wi, wo);
    return node.albedo(wi).total()[channel];
}

LidarBrdf lambertian_brdf(double rho) {
    return [rho](const glm::dvec3& wi, const glm::dvec3& wo) {
        return wi.z > 0.0 && wo.z > 0.0 ? rho / kPi : 0.0;
    };
}

void check_lidar_inputs(const LidarSensor& s, const LidarTarget& t, const LidarQuadrature& q) {
    require(std::isfinite(t.range_m) && t.range_m >= 0.1 && t.range_m <= 1e5, "--range", t.range_m,
            "in [0.1, 100000] m");
    const glm::dvec3& d = s.receiver_offset;
    const double offset = glm::length(d);
    if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z)) ||
        !(offset <= 0.1 * t.range_m))
        throw InputError(
            "--offset " + number_text(d.x) + "," + number_text(d.y) + "," + number_text(d.z) +
            ": must be finite, at most range / 10 = " + number_text(0.1 * t.range_m) + " m long");
    require(s.divergence_mrad > 0.0 && s.divergence_mrad <= 100.0, "--divergence",
            s.divergence_mrad, "in (0, 100] mrad");
    require(s.aperture_m > 0.0 && s.aperture_m <= std::min(1.0, 0.1 * t.range_m), "--aperture",
            s.aperture_m,
            "in (0, " + number_text(std::min(1.0, 0.1 * t.range_m)) + "] m (1 m and range / 10)");
    require(std::isfinite(t.rotation_deg), "--rotation", t.rotation_deg, "finite");
    // Every ray of the truncated beam meets the target's plane in front of the sensor, with a
    // margin: |tan(beta)| kBeamTruncation tan(divergence / 2) < 0.9.
    const double slope = kBeamTruncation * std::tan(0.5e-3 * s.divergence_mrad);
    const double betaMax = std::atan(0.9 / slope) / kDeg;
    require(std::abs(t.entrance_deg) < betaMax, "--entrance", t.entrance_deg,
            "in (-" + number_text(betaMax) + ", " + number_text(betaMax) +
                ") degrees (the beam, to 4 times its 1/e^2 radius, meets the target's plane)");
    const bool infinite = t.width_m == 0.0 && t.height_m == 0.0;
    const bool finite =
        t.width_m > 0.0 && t.width_m <= 1e4 && t.height_m > 0.0 && t.height_m <= 1e4;
    if (!infinite && !finite)
        throw InputError("--size " + number_text(t.width_m) + "," + number_text(t.height_m) +
                         ": width and height must both be in (0, 10000] m, or both 0 (a target "
                         "larger than the footprint)");
    require(q.footprint >= 1 && q.footprint <= 64, "footprint order", q.footprint, "in [1, 64]");
    require(q.aperture_radial >= 1 && q.aperture_radial <= 64, "aperture radial order",
            q.aperture_radial, "in [1, 64]");
    require(q.aperture_angular >= 4 && q.aperture_angular <= 256, "aperture angular order",
            q.aperture_angular, "in [4, 256]");
}

double aperture_reflectance(const LidarBrdf& f, const LidarHit& hit, const glm::dvec3& emitter,
                            const LidarAperture& aperture, const LidarQuadrature& q) {
    const glm::dvec3 n = glm::normalize(hit.normal);
    const glm::dvec3 t = orthogonal_tangent(n, hit.tangent);
    const glm::dvec3 b = glm::cross(n, t);
    const glm::dvec3 x = hit.position;
    const glm::dvec3 toEmitter = emitter - x;
    const glm::dvec3 c = aperture.centre;
    if (!(glm::dot(toEmitter, n) > 0.0) || !(glm::dot(c - x, n) > 0.0)) return 0.0;
    const glm::dvec3 wiW = glm::normalize(toEmitter);
    const glm::dvec3 wi(glm::dot(wiW, t), glm::dot(wiW, b), glm::dot(wiW, n));
    const glm::dvec3 axis = glm::normalize(aperture.axis);
    const double a = 0.5 * aperture.diameter;
    // The polar rule's centre: where the retro direction meets the aperture's plane, if inside.
    glm::dvec3 centre = c;
    bool atRetro = false;
    const double along = glm::dot(wiW, axis);
    if (std::abs(along) > 1e-12) {
        const glm::dvec3 p = x + wiW * (glm::dot(c - x, axis) / along);
        if (glm::length(p - c) < a) centre = p, atRetro = true;
    }
    const glm::dvec3 e1 = orthogonal_tangent(axis, glm::dvec3(1, 0, 0));
    const glm::dvec3 e2 = glm::cross(axis, e1);
    const glm::dvec3 qc = centre - c;
    const GaussLegendre g = gauss_legendre_rule(q.aperture_radial);
    double sum = 0.0;
    for (int j = 0; j < q.aperture_angular; ++j) {
        const double phi = 2.0 * kPi * (j + 0.5) / q.aperture_angular;
        const glm::dvec3 e = e1 * std::cos(phi) + e2 * std::sin(phi);
        const double qe = glm::dot(qc, e);
        const double rMax = -qe + std::sqrt(std::max(0.0, qe * qe + a * a - glm::dot(qc, qc)));
        double ring = 0.0;
        for (int p = 0; p < kApertureRadialPanels; ++p) {
            // Geometric panels toward the retro point, even ones about the disc's centre.
            const double lo = atRetro ? (p == 0 ? 0.0 : std::pow(4.0, p - kApertureRadialPanels))
                                      : double(p) / kApertureRadialPanels;
            const double hi = atRetro ? std::pow(4.0, p + 1 - kApertureRadialPanels)
                                      : double(p + 1) / kApertureRadialPanels;
            for (int k = 0; k < q.aperture_radial; ++k) {
                const double r = rMax * (0.5 * (lo + hi) + 0.5 * (hi - lo) * g.x[k]);
                const double wr = rMax * 0.5 * (hi - lo) * g.w[k] * r;
                const glm::dvec3 d = centre + e * r - x;
                const double dist2 = glm::dot(d, d);
                const glm::dvec3 woW = d / std::sqrt(dist2);
                const double cosAperture = -glm::dot(woW, axis);
                const glm::dvec3 wo(glm::dot(woW, t), glm::dot(woW, b), glm::dot(woW, n));
                if (!(cosAperture > 0.0) || !(wo.z > 0.0)) continue;
                ring += wr * f(wi, wo) * wo.z * cosAperture / dist2;
            }
        }
        sum += ring;
    }
    return sum * 2.0 * kPi / q.aperture_angular;
}

LidarReturn lidar_return(const LidarBrdf& f, const LidarSensor& sensor, const LidarTarget& target,
                         const LidarQuadrature& q) {
    check_lidar_inputs(sensor, target, q);
    const TargetFrame tf = target_frame(target);
    const double tw = std::tan(0.5e-3 * sensor.divergence_mrad);
    Box box = beam_box(tf, kBeamTruncation * tw);
    if (target.width_m > 0.0) {
        box.u0 = std::max(box.u0, -0.5 * target.width_m);
        box.u1 = std::min(box.u1, 0.5 * target.width_m);
        box.v0 = std::max(box.v0, -0.5 * target.height_m);
        box.v1 = std::min(box.v1, 0.5 * target.height_m);
    }
    const GaussLegendre g = gauss_legendre_rule(q.footprint);
    std::vector<double> us, uw, vs, vw;
    two_panels(g, box.u0, box.u1, us, uw);
    two_panels(g, box.v0, box.v1, vs, vw);
    const double e = target.rotation_deg * kDeg;
    LidarHit hit;
    hit.normal = tf.normal;
    hit.tangent = tf.width * std::cos(e) + tf.height * std::sin(e);
    const LidarAperture aperture{sensor.receiver_offset, glm::dvec3(0, 0, 1), sensor.aperture_m};
    const LidarBrdf lambert = lambertian_brdf(1.0);
    struct Node {
        double power = 0, node = 0, lambert = 0;
    };
    std::vector<Node> nodes(us.size() * vs.size());
    parallel_for(nodes.size(), 0, [&](std::size_t i) {
        const std::size_t iu = i % us.size(), iv = i / us.size();
        LidarHit h = hit;
        h.position = tf.centre + tf.width * us[iu] + tf.height * vs[iv];
        const glm::dvec3& x = h.position;
        const double r = glm::length(x);
        // The beam's power per unit area of the target: g(s) d^2s/dA, d^2s/dA = cos(theta_i) r /
        // z^3 (the solid angle cos(theta_i) dA / r^2 over cos^3 of the ray's angle to the axis).
        const double sx = x.x / x.z, sy = x.y / x.z;
        const double gs = 2.0 / (kPi * tw * tw) * std::exp(-2.0 * (sx * sx + sy * sy) / (tw * tw));
        const double cosI = -glm::dot(x, tf.normal) / r;
        Node& o = nodes[i];
        o.power = uw[iu] * vw[iv] * gs * cosI * r / (x.z * x.z * x.z);
        o.node = aperture_reflectance(f, h, glm::dvec3(0.0), aperture, q);
        o.lambert = aperture_reflectance(lambert, h, glm::dvec3(0.0), aperture, q);
    });
    LidarReturn out;
    for (const Node& o : nodes) {
        out.intercepted += o.power;
        out.fraction += o.power * o.node;
        out.lambertian_fraction += o.power * o.lambert;
    }
    out.reflectance = out.lambertian_fraction > 0.0 ? out.fraction / out.lambertian_fraction : 0.0;
    const glm::dvec3 toEmitter = -tf.centre, toAperture = sensor.receiver_offset - tf.centre;
    out.observation_mrad = 1e3 * std::atan2(glm::length(glm::cross(toEmitter, toAperture)),
                                            glm::dot(toEmitter, toAperture));
    return out;
}

LidarMaterial lidar_material(const std::string& arg) {
    const std::size_t eq = arg.find('=');
    const std::string path = eq == std::string::npos ? arg : arg.substr(eq + 1);
    LidarMaterial m;
    m.label = eq == std::string::npos ? path : arg.substr(0, eq);
    const auto ends = [&](const std::string& ext) {
        return path.size() >= ext.size() &&
               path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
    };
    if (ends(".json"))
        m.params = params_from_json(read_json(path), path);
    else if (ends(".mtlx"))
        m.params = document_params(path, "");
    else
        throw InputError(arg + ": expected a material FILE.json or a MaterialX document DOC.mtlx");
    return m;
}

std::vector<LidarRow> lidar_sweep(const std::vector<LidarMaterial>& materials,
                                  const LidarSensor& sensor, const LidarTarget& target,
                                  const std::vector<double>& wavelengthsNm,
                                  const std::vector<double>& rangesM,
                                  const std::vector<double>& entrancesDeg, int channel,
                                  const LidarQuadrature& q) {
    // Every geometry first, so that bad input is reported before any work.
    for (double range : rangesM)
        for (double entrance : entrancesDeg) {
            LidarTarget t = target;
            t.range_m = range;
            t.entrance_deg = entrance;
            check_lidar_inputs(sensor, t, q);
        }
    std::vector<LidarRow> rows;
    for (const LidarMaterial& m : materials)
        for (double nm : wavelengthsNm) {
            const LidarBrdf f = lidar_node_brdf(m.params, nm, channel);
            for (double entrance : entrancesDeg) {
                const double albedo =
                    lidar_node_albedo(m.params, nm, channel, entrance, target.rotation_deg);
                for (double range : rangesM) {
                    LidarTarget t = target;
                    t.range_m = range;
                    t.entrance_deg = entrance;
                    LidarRow row;
                    row.material = m.label;
                    row.wavelength_nm = nm;
                    row.range_m = range;
                    row.entrance_deg = entrance;
                    row.ret = lidar_return(f, sensor, t, q);
                    row.observation_mrad = row.ret.observation_mrad;
                    row.albedo = albedo;
                    row.lambertian_albedo = albedo * row.ret.lambertian_fraction;
                    rows.push_back(row);
                }
            }
        }
    return rows;
}

std::vector<LidarReturn> lidar_returns_at(const LidarBrdf& f, const std::vector<LidarRow>& rows,
                                          const LidarSensor& sensor, const LidarTarget& target,
                                          const LidarQuadrature& q) {
    std::vector<LidarReturn> out;
    for (const LidarRow& r : rows) {
        LidarTarget t = target;
        t.range_m = r.range_m;
        t.entrance_deg = r.entrance_deg;
        out.push_back(lidar_return(f, sensor, t, q));
    }
    return out;
}

LidarBrdf lidar_ggx_brdf(const std::string& tableCsv, int channel) {
    require(channel >= 0 && channel <= 2, "--channel", channel, "0 (red), 1 (green) or 2 (blue)");
    const baselines::RetroreflectiveGGX model = fit_ra_mrm(read_ra_table(tableCsv)).model;
    return [model, channel](const glm::dvec3& wi, const glm::dvec3& wo) {
        return model.f(wi, wo)[channel];
    };
}

} // namespace retroprism
