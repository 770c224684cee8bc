// [lidar]: the LiDAR return (analysis/lidar.h). A Lambertian target against the closed forms
// (the view factor of a disc from a point, the power of a Gaussian beam on a rectangle) within
// 0.1%; the bundled materials against a direct integration written here (midpoint rules on
// Cartesian grids over the beam's slopes or the target, and over the aperture's disc, the node
// evaluated in a frame built here) within 1%; the library's quadrature against doubled orders;
// bad inputs rejected naming the option and its range, by the library and by `retroprism lidar`.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include "color.h"
#include "lidar.h"
#include "photometry.h"
#include "query.h"
#include "test_support.h"

using namespace retroprism;
using rptest::dvec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

Params microprismatic() {
    const std::string f =
        std::string(RP_SOURCE_DIR) + "/examples/materials/microprismatic_160um.json";
    return params_from_json(read_json(f), f);
}
Params dg983() {
    return document_params(std::string(RP_SOURCE_DIR) + "/examples/sheeting/dg983_white.mtlx", "");
}

// View factor from a differential area to a coaxially parallel disc of radius a at height h,
// its axis offset laterally by l from the area (Howell, A Catalog of Radiation Heat Transfer
// Configuration Factors, B-13).
double view_factor_parallel_disc(double h, double l, double a) {
    const double s = h * h + l * l + a * a;
    return 0.5 * (1.0 - (h * h + l * l - a * a) / std::sqrt(s * s - 4.0 * l * l * a * a));
}

// The direct integration: the beam's power over a Cartesian midpoint grid (in the beam's slopes
// for a target larger than the footprint, in the target's plane for a rectangle), the aperture
// over a Cartesian midpoint grid of the disc's square keeping the points inside, each weighted
// by the disc's area over their number (the grid's own count misses the area by 0.4% at 48).
struct Direct {
    int footprint = 24; // cells per axis
    int aperture = 48;  // cells per axis of the disc's square
};

using Brdf = std::function<double(const dvec3&, const dvec3&)>;
// A BRDF as the direct integration calls it: for one incident direction (a point of the
// footprint), the function of the outgoing direction it evaluates over the aperture.
using BrdfFrom = std::function<std::function<double(const dvec3&)>(const dvec3&)>;

// The node of `material` at `nm`, red channel, in the local frame.
std::shared_ptr<const PrismaticRetroreflector<double>> node_of(const Params& material, double nm) {
    return std::make_shared<const PrismaticRetroreflector<double>>(
        PrismaticRetroreflector<double>(ra_params(material)).at_wavelength(nm));
}
Brdf node_at(const Params& material, double nm) {
    const auto node = node_of(material, nm);
    return [node](const dvec3& wi, const dvec3& wo) { return node->f(wi, wo).total()[0]; };
}
// The same node through its incident state (f(incident(wi), wo), which [consistency] holds equal
// to f(wi, wo) bit for bit): the state made once per footprint point, not once per aperture point.
BrdfFrom node_from(const Params& material, double nm) {
    const auto node = node_of(material, nm);
    return [node](const dvec3& wi) {
        return
            [node, in = node->incident(wi)](const dvec3& wo) { return node->f(in, wo).total()[0]; };
    };
}
BrdfFrom from(const LidarBrdf& f) {
    return [f](const dvec3& wi) { return [f, wi](const dvec3& wo) { return f(wi, wo); }; };
}

double direct_return(const BrdfFrom& brdf, const LidarSensor& s, const LidarTarget& t,
                     const Direct& d) {
    const double b = t.entrance_deg * kDeg, e = t.rotation_deg * kDeg;
    const dvec3 c(0, 0, t.range_m), n(std::sin(b), 0, -std::cos(b));
    const dvec3 wAxis(-std::cos(b), 0, -std::sin(b)), hAxis(0, 1, 0);
    const dvec3 tng = wAxis * std::cos(e) + hAxis * std::sin(e), bit = glm::cross(n, tng);
    const double a = 0.5 * s.aperture_m, tw = std::tan(0.5e-3 * s.divergence_mrad);
    // rho_ap at x: the aperture's grid.
    auto rhoAp = [&](const dvec3& x) {
        const dvec3 wiW = glm::normalize(-x);
        const dvec3 wi(glm::dot(wiW, tng), glm::dot(wiW, bit), glm::dot(wiW, n));
        const auto f = brdf(wi);
        const double h = 2.0 * a / d.aperture;
        double sum = 0;
        int inside = 0;
        for (int i = 0; i < d.aperture; ++i)
            for (int j = 0; j < d.aperture; ++j) {
                const double px = -a + (i + 0.5) * h, py = -a + (j + 0.5) * h;
                if (px * px + py * py > a * a) continue;
                ++inside;
                const dvec3 y = s.receiver_offset + dvec3(px, py, 0);
                const dvec3 v = y - x;
                const double r2 = glm::dot(v, v);
                const dvec3 woW = v / std::sqrt(r2);
                const dvec3 wo(glm::dot(woW, tng), glm::dot(woW, bit), glm::dot(woW, n));
                if (wo.z <= 0) continue;
                sum += f(wo) * wo.z * (-woW.z) / r2;
            }
        return sum * kPi * a * a / inside;
    };
    double total = 0;
    if (t.width_m == 0) {
        const double lim = kBeamTruncation * tw, h = 2.0 * lim / d.footprint;
        for (int i = 0; i < d.footprint; ++i)
            for (int j = 0; j < d.footprint; ++j) {
                const double sx = -lim + (i + 0.5) * h, sy = -lim + (j + 0.5) * h;
                const double g =
                    2.0 / (kPi * tw * tw) * std::exp(-2.0 * (sx * sx + sy * sy) / (tw * tw));
                const dvec3 dir(sx, sy, 1.0);
                const dvec3 x = dir * (glm::dot(c, n) / glm::dot(dir, n));
                total += g * h * h * rhoAp(x);
            }
    } else {
        const double hu = t.width_m / d.footprint, hv = t.height_m / d.footprint;
        for (int i = 0; i < d.footprint; ++i)
            for (int j = 0; j < d.footprint; ++j) {
                const dvec3 x = c + wAxis * (-0.5 * t.width_m + (i + 0.5) * hu) +
                                hAxis * (-0.5 * t.height_m + (j + 0.5) * hv);
                // Irradiance over power: the beam's intensity toward x, cos(theta_i) / r^2.
                const double r = glm::length(x), cosAxis = x.z / r;
                const double sx = x.x / x.z, sy = x.y / x.z;
                const double intensity = 2.0 / (kPi * tw * tw) *
                                         std::exp(-2.0 * (sx * sx + sy * sy) / (tw * tw)) /
                                         (cosAxis * cosAxis * cosAxis);
                total += intensity * (-glm::dot(x, n) / r) / (r * r) * hu * hv * rhoAp(x);
            }
    }
    return total;
}

struct Case {
    const char* name;
    Params material;
    double nm;
    LidarSensor sensor;
    LidarTarget target;
};

std::vector<Case> cases() {
    struct Row {
        const char* name;
        bool sign; // dg983_white.mtlx, else microprismatic_160um.json
        double nm, offsetX, offsetY, range, entrance, rotation, width, height;
    };
    const Row rows[] = {
        {"plate 905 nm, 10 m, beta 0", false, 905, 0.03, 0, 10, 0, 0, 0, 0},
        {"sign 1550 nm, 2 m, beta 30, epsilon 20", true, 1550, 0.02, 0.01, 2, 30, 20, 0, 0},
        {"plate 1550 nm, coaxial, 5 m, beta 10", false, 1550, 0, 0, 5, 10, 0, 0, 0},
        {"plate 905 nm, retro point inside the aperture off its centre, 3 m", false, 905, 0.008, 0,
         3, 0, 0, 0, 0},
        {"plate 905 nm, retro point just outside the aperture's rim, 3 m", false, 905, 0.0135, 0, 3,
         0, 0, 0, 0},
        {"plate 0.52 x 0.11 m at 150 m, beta 20 (smaller than the footprint)", false, 905, 0.05, 0,
         150, 20, 0, 0.52, 0.11}};
    std::vector<Case> v;
    for (const Row& r : rows) {
        Case c{r.name, r.sign ? dg983() : microprismatic(), r.nm, {}, {}};
        c.sensor.receiver_offset = dvec3(r.offsetX, r.offsetY, 0);
        c.target = {r.range, r.entrance, r.rotation, r.width, r.height};
        v.push_back(c);
    }
    return v;
}

} // namespace

TEST_CASE("LiDAR: a Lambertian target against the closed forms within 0.1%", "[lidar]") {
    // The closed forms hold for the footprint's centre; over the footprint the view factor
    // changes at second order in the beam's slopes (divergence 3 mrad: < 1e-5 relative).
    const double tol = 1e-3;
    const LidarBrdf grey = lambertian_brdf(0.4);
    double worst = 0;
    for (double range : {2.0, 20.0, 200.0}) {
        LidarSensor s;
        LidarTarget t;
        t.range_m = range;
        const double a = 0.5 * s.aperture_m;
        for (double l : {0.0, 0.03, 0.1}) {
            s.receiver_offset = dvec3(l, 0, 0);
            if (l > 0.1 * range) continue;
            const LidarReturn r = lidar_return(grey, s, t);
            const double closed = 0.4 * view_factor_parallel_disc(range, l, a);
            INFO("range " << range << " offset " << l << ": " << r.fraction << " against "
                          << closed);
            CHECK(std::abs(r.fraction / closed - 1.0) < tol);
            worst = std::max(worst, std::abs(r.fraction / closed - 1.0));
            CHECK(std::abs(r.reflectance - 0.4) < 0.4 * 1e-12);
            // The footprint's Gauss-Legendre rule (two panels of 12 over +-8 standard deviations
            // of the Gaussian) integrates it to 3e-8.
            CHECK(std::abs(r.intercepted - 1.0) < 1e-6);
        }
        // Tilted, coaxial: the disc's projected solid angle times cos(beta) (the tilt's other
        // component integrates to 0 over the disc by symmetry).
        s.receiver_offset = dvec3(0);
        for (double beta : {30.0, 60.0}) {
            t.entrance_deg = beta;
            const LidarReturn r = lidar_return(grey, s, t);
            const double closed = 0.4 * std::cos(beta * kDeg) * a * a / (range * range + a * a);
            INFO("range " << range << " beta " << beta << ": " << r.fraction << " against "
                          << closed);
            CHECK(std::abs(r.fraction / closed - 1.0) < tol);
            worst = std::max(worst, std::abs(r.fraction / closed - 1.0));
        }
        t.entrance_deg = 0;
        // A rectangle smaller than the footprint at normal incidence: the beam's power on it is
        // erf(sqrt(2) W / (2 R t)) erf(sqrt(2) H / (2 R t)), t = tan(divergence / 2).
        t.width_m = 0.02 * range;
        t.height_m = 0.005 * range;
        const LidarReturn r = lidar_return(grey, s, t);
        const double tw = std::tan(0.5e-3 * s.divergence_mrad);
        const double power = std::erf(std::sqrt(2.0) * t.width_m / (2 * range * tw)) *
                             std::erf(std::sqrt(2.0) * t.height_m / (2 * range * tw));
        const double closed = 0.4 * power * a * a / (range * range + a * a);
        INFO("rectangle at " << range << ": " << r.fraction << " against " << closed);
        CHECK(std::abs(r.intercepted / power - 1.0) < 1e-6);
        CHECK(std::abs(r.fraction / closed - 1.0) < tol);
        worst = std::max(worst, std::abs(r.fraction / closed - 1.0));
    }
    std::printf("[lidar] Lambertian target against the closed forms: worst %.2e\n", worst);
}

TEST_CASE("LiDAR: the bundled materials against a direct integration within 1%", "[lidar]") {
    // Each case also integrates a Lambertian target directly, against the library's: the direct
    // rules' own error at these grids (the disc's edge cells), printed beside.
    for (const Case& c : cases()) {
        const LidarReturn r = lidar_return(lidar_node_brdf(c.material, c.nm), c.sensor, c.target);
        const double direct = direct_return(node_from(c.material, c.nm), c.sensor, c.target, {});
        const double lambert = direct_return(from(lambertian_brdf(1.0)), c.sensor, c.target, {}) /
                               r.lambertian_fraction;
        const double dev = r.fraction / direct - 1.0;
        std::printf("[lidar] %-66s library %.5e direct %.5e deviation %+.1e (Lambertian %+.1e; "
                    "observation %.3f mrad, equivalent reflectance %.4g)\n",
                    c.name, r.fraction, direct, dev, lambert - 1.0, r.observation_mrad,
                    r.reflectance);
        INFO(c.name << ": library " << r.fraction << ", direct " << direct);
        CHECK(std::abs(dev) < 0.01);
        CHECK(std::abs(lambert - 1.0) < 0.01);
    }
}

TEST_CASE("LiDAR: the node's BRDF is the node's f, its incident state kept per direction",
          "[lidar]") {
    // lidar_node_brdf makes the incident state once per source direction and thread (keyed by
    // the instance): interleaving two instances and three source directions must give the
    // node's f(wi, wo) bit for bit, as if nothing were kept.
    Params a, b;
    a.prism_pitch = 120.0;
    b.prism_pitch = 60.0;
    b.prism_reflection = 1; // tir
    const LidarBrdf fa = lidar_node_brdf(a, 905), fb = lidar_node_brdf(b, 905);
    const Brdf ga = node_at(a, 905), gb = node_at(b, 905);
    const dvec3 wis[3] = {glm::normalize(dvec3(0.1, 0.0, 1.0)),
                          glm::normalize(dvec3(-0.3, 0.2, 1.0)), dvec3(0.0, 0.6, -0.8)};
    long differ = 0, checked = 0;
    for (int k = 0; k < 96; ++k) {
        const dvec3 wi = wis[k % 3];
        const dvec3 wo = glm::normalize(wi + dvec3(0.004 * (k % 7), 0.003 * (k % 5), 0.0));
        const bool first = (k / 3) % 2 == 0;
        differ += first ? fa(wi, wo) != ga(wi, wo) : fb(wi, wo) != gb(wi, wo);
        ++checked;
    }
    CHECK(checked == 96);
    CHECK(differ == 0);
}

// The default orders against doubled ones: the fast case the geometries where the aperture sees
// the most of the lobe (2 m, the lobe's peak inside the aperture and just outside its rim), the
// [ci] case all.
void check_doubled(const std::vector<Case>& all) {
    LidarQuadrature fine;
    fine.footprint *= 2;
    fine.aperture_radial *= 2;
    fine.aperture_angular *= 2;
    double worst = 0;
    for (const Case& c : all) {
        const LidarBrdf f = lidar_node_brdf(c.material, c.nm);
        const double coarse = lidar_return(f, c.sensor, c.target).fraction;
        const double ref = lidar_return(f, c.sensor, c.target, fine).fraction;
        INFO(c.name << ": default " << coarse << ", doubled " << ref);
        worst = std::max(worst, std::abs(coarse / ref - 1.0));
    }
    std::printf("[lidar] default quadrature against doubled orders, %zu cases: worst %.2e\n",
                all.size(), worst);
    // A tenth of the 1% the return is checked to.
    CHECK(worst < 1e-3);
}

TEST_CASE("LiDAR: the default quadrature against doubled orders", "[lidar]") {
    const std::vector<Case> all = cases();
    check_doubled({all[1], all[3], all[4]});
}

TEST_CASE("LiDAR: the default quadrature against doubled orders, every case", "[lidar][ci]") {
    check_doubled(cases());
}

TEST_CASE("LiDAR: every input changes the return", "[lidar]") {
    // STYLE.md's rule: each input varied alone from a base must change the result. The base: a
    // plate at 150 m, where the footprint (1/e^2 radius 0.23 m) outgrows it, so its size acts.
    // Materials where the input acts: the plate diffracts (wavelength), the yellow sign's
    // channels differ, the white sign's matched pairs turn with the rotation once the refracted
    // direction is tilted beyond 19.5 degrees (entrance 30; below, the ERA is the same at every
    // azimuth, MODEL.md section 2).
    const std::string dir = std::string(RP_SOURCE_DIR) + "/examples/materials/";
    const Params white = params_from_json(read_json(dir + "white_sign.json"), "white_sign.json");
    const Params yellow = params_from_json(read_json(dir + "yellow_sign.json"), "yellow_sign.json");
    LidarSensor s;
    LidarTarget t;
    t.range_m = 150;
    t.entrance_deg = 10;
    t.width_m = 0.52;
    t.height_m = 0.11;
    auto fraction = [](const Params& m, double nm, int channel, const LidarSensor& s2,
                       const LidarTarget& t2) {
        return lidar_return(lidar_node_brdf(m, nm, channel), s2, t2).fraction;
    };
    struct Variation {
        const char* input;
        double base, varied;
    };
    std::vector<Variation> v;
    const double plateBase = fraction(microprismatic(), 905, 0, s, t);
    v.push_back({"wavelength", plateBase, fraction(microprismatic(), 1550, 0, s, t)});
    v.push_back({"channel", fraction(yellow, 905, 0, s, t), fraction(yellow, 905, 2, s, t)});
    LidarTarget tr = t;
    tr.entrance_deg = 30;
    const double whiteBase = fraction(white, 905, 0, s, tr);
    tr.rotation_deg = 45;
    v.push_back({"rotation", whiteBase, fraction(white, 905, 0, s, tr)});
    auto vary = [&](const char* input, const LidarSensor& s2, const LidarTarget& t2) {
        v.push_back({input, plateBase, fraction(microprismatic(), 905, 0, s2, t2)});
    };
    vary("offset", {dvec3(0.1, 0, 0), 3.0, 0.025}, t);
    vary("divergence", {dvec3(0.03, 0, 0), 6.0, 0.025}, t);
    vary("aperture", {dvec3(0.03, 0, 0), 3.0, 0.05}, t);
    vary("range", s, {100.0, 10.0, 0.0, 0.52, 0.11});
    vary("entrance", s, {150.0, 25.0, 0.0, 0.52, 0.11});
    vary("width", s, {150.0, 10.0, 0.0, 0.3, 0.11});
    vary("height", s, {150.0, 10.0, 0.0, 0.52, 0.2});
    for (const Variation& x : v) {
        INFO(x.input << ": " << x.base << " -> " << x.varied);
        CHECK(std::abs(x.varied / x.base - 1.0) > 1e-3);
    }
}

TEST_CASE("LiDAR: the per-ray function is the view factor for a Lambertian surface", "[lidar]") {
    // A hit 7 m in front of a disc facing it, surface tilted; the aperture's centre on its normal.
    LidarHit hit;
    hit.position = dvec3(1, 2, 7);
    hit.normal = dvec3(0, 0, -1);
    hit.tangent = dvec3(0, 1, 0);
    LidarAperture ap;
    ap.centre = dvec3(1.05, 2, 0);
    ap.diameter = 0.05;
    const double rho = aperture_reflectance(lambertian_brdf(1.0), hit, dvec3(1, 2, 0), ap);
    const double closed = view_factor_parallel_disc(7.0, 0.05, 0.025);
    CHECK(std::abs(rho / closed - 1.0) < 1e-6);
    // Behind the surface: nothing.
    hit.normal = dvec3(0, 0, 1);
    CHECK(aperture_reflectance(lambertian_brdf(1.0), hit, dvec3(1, 2, 0), ap) == 0.0);
}

TEST_CASE("LiDAR: bad inputs are rejected naming the option and its range", "[lidar]") {
    const LidarBrdf f = lambertian_brdf(1.0);
    auto fails = [&](LidarSensor s, LidarTarget t, const std::string& part) {
        try {
            lidar_return(f, s, t);
        } catch (const InputError& e) {
            INFO(e.what());
            CHECK(rptest::contains(e.what(), part));
            return;
        }
        FAIL("no error for " << part);
    };
    LidarSensor s;
    LidarTarget t;
    fails(s, {-1.0}, "--range -1: must be in [0.1, 100000] m");
    fails(s, {std::nan("")}, "--range nan");
    fails({dvec3(0.03, 0, 0), 0.0, 0.025}, t, "--divergence 0: must be in (0, 100] mrad");
    fails({dvec3(0.03, 0, 0), 3.0, 5.0}, t, "--aperture 5: must be in (0, 1] m");
    fails({dvec3(3, 0, 0), 3.0, 0.025}, t,
          "--offset 3,0,0: must be finite, at most range / 10 = 2 m long");
    fails(s, {20.0, 90.0}, "--entrance 90: must be in (-");
    fails(s, {20.0, 0.0, 0.0, 1.0, 0.0},
          "--size 1,0: width and height must both be in (0, 10000] m");
    CHECK_THROWS_WITH(lidar_node_brdf(Params(), 2500), Catch::Contains("--wavelength 2500"));
    CHECK_THROWS_WITH(lidar_node_brdf(Params(), 905, 3), Catch::Contains("--channel 3"));
    // The command: the library's messages, and its own for its options; exit status 1, no table.
    struct Run {
        const char* args;
        const char* message;
    };
    for (const Run& r :
         {Run{"--range 2,-5", "--range -5: must be in [0.1, 100000] m"},
          Run{"--range 2,x", "--range 2,x: x: expected a finite number"},
          Run{"--offset 1,2", "--offset: expected X,Y,Z in m"},
          Run{"--wavelength 0", "--wavelength 0: must be in (0, 2000] nm"},
          Run{"--channel q", "--channel q: expected r, g or b"},
          Run{"--baseline t.csv --csv", "--baseline prints a text table"},
          Run{"nosuch.txt", "nosuch.txt: expected a material FILE.json or a MaterialX document"}}) {
        const rptest::CommandRun run = rptest::run_cli(std::string("lidar ") + r.args);
        INFO(r.args << ": " << run.output);
        CHECK(run.status == 1);
        CHECK(rptest::contains(run.output, r.message));
        CHECK_FALSE(rptest::contains(run.output, "P_r/P"));
    }
}

namespace {

// `retroprism lidar ARGS`'s output; the command must succeed.
std::string lidar_output(const std::string& args) {
    const rptest::CommandRun run = rptest::run_cli("lidar " + args);
    INFO(run.output);
    REQUIRE(run.status == 0);
    return run.output;
}

LidarTarget at(double range, double entrance) {
    LidarTarget t;
    t.range_m = range;
    t.entrance_deg = entrance;
    return t;
}

} // namespace

TEST_CASE("retroprism lidar: CSV rows answer the library", "[lidar]") {
    const std::string plate =
        std::string(RP_SOURCE_DIR) + "/examples/materials/microprismatic_160um.json";
    const std::string out = lidar_output("plate=" + plate + " --range 5,50 --entrance 0,30 --csv");
    const LidarReturn r = lidar_return(lidar_node_brdf(microprismatic(), 905), {}, at(50, 30));
    char row[128];
    std::snprintf(row, sizeof row, "plate,905,50,30,%.6g,%.6e,", r.observation_mrad, r.fraction);
    CHECK(rptest::contains(out, row));
}

TEST_CASE("retroprism lidar --baseline: the fitted GGX's returns answer the library", "[lidar]") {
    const std::string sign = std::string(RP_SOURCE_DIR) + "/examples/sheeting/dg983_white.mtlx";
    const std::string table = std::string(RP_SOURCE_DIR) + "/examples/sheeting/dg983_white.csv";
    const std::string out =
        lidar_output("sign=" + sign + " --range 50 --entrance 20 --baseline " + table);
    const LidarReturn node = lidar_return(lidar_node_brdf(dg983(), 905), {}, at(50, 20));
    const LidarReturn ggx = lidar_return(lidar_ggx_brdf(table), {}, at(50, 20));
    char row[160];
    std::snprintf(row, sizeof row, "| %9.3e %9.3e %8.4g", node.fraction, ggx.fraction,
                  node.fraction / ggx.fraction);
    CHECK(rptest::contains(out, row));
}
