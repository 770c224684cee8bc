// render.cpp: `retroprism render DOC.mtlx -o OUT.exr`: a night-time preview of a MaterialX
// material with the C++ reference node (PrismaticRetroreflector<double>), direct lighting only.
//
// Scene (metres; camera at the origin looking down -z, +y up, pinhole):
//  - a diamond sign (a square of side 0.85 m turned 45 degrees in its plane, like a warning
//    sign), centre (-0.62, 0, -8), turned about the vertical so that the headlight's entrance
//    angle at its centre is --sign-angle (default 15 degrees); its tangent (the prisms'
//    reference azimuth, the datum mark) is the sign's horizontal axis;
//  - a sphere of radius 0.5 m, centre (0.75, 0, -8.2); tangent along the parallels
//    (normalize(up x n)), so that oriented prisms show their azimuth dependence;
//  - a headlight: an isotropic point source below the eye, placed so that the observation angle
//    at the sign's centre is --observation (default 0.5 degrees, a car's low beam and driver at
//    ~70 m), intensity such that the illuminance perpendicular to it at the sign's centre is 1;
//  - with --fill, a fill light: a point source up and to the left behind the camera, (-3, 4, 1),
//    giving an illuminance of 60 at the sign's centre (dusk), so the day colour shows.
// Shading: at each hit, wi (to the light) and wo (to the eye) in the surface's local frame
// (normal, tangent), the node's f per lobe times cos(theta_i) times the light's irradiance
// (I / d^2), with shadow rays; the document's normal and tangent inputs are not used.
// Pixels: --samples^2 stratified sub-pixel rays (default 3 x 3), box filter.
//
// Output, written only when everything succeeded (temporary names, then renamed):
//  - OUT.exr: linear Rec.709 radiance (scene units), float, channels R, G, B, A (combined,
//    A = coverage) and one layer per lobe: surface.{R,G,B}, retro.{R,G,B}, diffuse.{R,G,B};
//    R = surface.R + retro.R + diffuse.R (attributes retroprism:*).
//  - the display PNG (OUT.png, or --png PATH): the combined RGB through OpenColorIO:
//    x 2^--exposure (default -6 EV) and the --view transform (default "aces": ACES 1.0
//    SDR-video, sRGB display; see color.h).
// Then it prints the material's R_A table (Y), as `retroprism ra` does.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include <unistd.h>

#include <OpenImageIO/argparse.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/parallel.h>

#include "color.h"
#include "commands.h"
#include "photometry.h"
#include "query.h"
#include "ra_print.h"

namespace fs = std::filesystem;
using glm::dvec3;

namespace retroprism {

namespace {

using Node = PrismaticRetroreflector<double>;
constexpr double kDeg = M_PI / 180.0;
constexpr double kHitEps = 1e-6;

struct Hit {
    double t = 1e300;
    dvec3 p{0}, n{0, 0, 1}, tangent{1, 0, 0};
    int object = -1;
};

struct Sign {
    dvec3 c, n, u, v; // centre, normal, in-plane horizontal (tangent) and vertical axes
    double halfDiagonal = 0;
    bool intersect(const dvec3& o, const dvec3& d, Hit& h) const {
        const double dn = glm::dot(d, n);
        if (std::abs(dn) < 1e-12) return false;
        const double t = glm::dot(c - o, n) / dn;
        if (!(t > kHitEps) || t >= h.t) return false;
        const dvec3 p = o + t * d;
        const double a = glm::dot(p - c, u), b = glm::dot(p - c, v);
        if (std::abs(a) + std::abs(b) > halfDiagonal) return false;
        h.t = t;
        h.p = p;
        h.n = n;
        h.tangent = u;
        h.object = 0;
        return true;
    }
};

struct Sphere {
    dvec3 c;
    double r = 0;
    bool intersect(const dvec3& o, const dvec3& d, Hit& h) const {
        const dvec3 oc = o - c;
        const double b = glm::dot(oc, d), cc = glm::dot(oc, oc) - r * r;
        const double disc = b * b - cc;
        if (disc < 0) return false;
        const double s = std::sqrt(disc);
        double t = -b - s;
        if (!(t > kHitEps)) t = -b + s;
        if (!(t > kHitEps) || t >= h.t) return false;
        h.t = t;
        h.p = o + t * d;
        h.n = glm::normalize(h.p - c);
        const dvec3 tg = glm::cross(dvec3(0, 1, 0), h.n);
        h.tangent = glm::length(tg) > 1e-9 ? glm::normalize(tg) : dvec3(1, 0, 0);
        h.object = 1;
        return true;
    }
};

struct Light {
    dvec3 position;
    double intensity; // radiant intensity, scene units per sr
};

struct Scene {
    dvec3 eye{0, 0, 0};
    double tanX = 0, tanY = 0; // half-extents of the image plane at distance 1
    Sign sign;
    Sphere sphere;
    std::vector<Light> lights;
    double observationAtSign = 0, entranceAtSign = 0; // degrees, measured

    bool trace(const dvec3& o, const dvec3& d, Hit& h) const {
        bool any = sign.intersect(o, d, h);
        any = sphere.intersect(o, d, h) || any;
        return any;
    }
    bool occluded(const dvec3& p, const dvec3& n, const dvec3& to) const {
        const dvec3 o = p + n * 1e-5;
        const dvec3 d = to - o;
        const double dist = glm::length(d);
        Hit h;
        h.t = dist * (1.0 - 1e-9);
        return trace(o, d / dist, h);
    }
};

double angle_deg(const dvec3& a, const dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) / kDeg;
}

Scene build_scene(int width, int height, double observationDeg, double signAngleDeg, bool fill) {
    Scene s;
    const double aspect = double(width) / double(height);
    // Frame at least 2.7 m x 1.6 m at 8 m.
    const double halfW = std::max(1.35, 0.8 * aspect) / 8.0;
    s.tanX = halfW;
    s.tanY = halfW / aspect;
    // The headlight below the eye: first placed for a sign facing the eye, refined below.
    const dvec3 signC(-0.62, 0.0, -8.0);
    const double D = glm::length(signC - s.eye);
    double h = D * std::tan(observationDeg * kDeg);
    dvec3 light = s.eye - dvec3(0, h, 0);
    for (int it = 0; it < 3 && observationDeg > 0; ++it) {
        const double a = angle_deg(light - signC, s.eye - signC);
        h *= observationDeg / a;
        light = s.eye - dvec3(0, h, 0);
    }
    // The sign turned about the vertical (away from the camera's side) by the entrance angle
    // relative to the direction to the light.
    const dvec3 toLight = glm::normalize(light - signC);
    const double yaw0 = std::atan2(toLight.x, toLight.z);
    const double yaw = yaw0 - signAngleDeg * kDeg;
    s.sign.c = signC;
    s.sign.n = dvec3(std::sin(yaw), 0.0, std::cos(yaw));
    s.sign.u = glm::normalize(glm::cross(dvec3(0, 1, 0), s.sign.n));
    s.sign.v = glm::cross(s.sign.n, s.sign.u);
    s.sign.halfDiagonal = 0.85 / std::sqrt(2.0);
    s.sphere.c = dvec3(0.75, 0.0, -8.2);
    s.sphere.r = 0.5;
    const double dl2 = glm::dot(light - signC, light - signC);
    s.lights.push_back({light, dl2}); // illuminance 1 at the sign's centre
    if (fill) {
        const dvec3 f(-3.0, 4.0, 1.0);
        s.lights.push_back({f, 60.0 * glm::dot(f - signC, f - signC)});
    }
    s.observationAtSign = angle_deg(light - signC, s.eye - signC);
    s.entranceAtSign = angle_deg(light - signC, s.sign.n);
    return s;
}

struct Image {
    int width = 0, height = 0;
    // Per pixel: surface, retro, diffuse RGB, coverage.
    std::vector<float> surface, retro, diffuse, alpha;
};

// A progress bar on stderr, drawn only when stderr is a terminal; rows are counted as the
// worker threads finish them.
struct Progress {
    bool tty = false;
    int total = 0;
    std::atomic<int> done{0};
    std::mutex m;
    int shown = -1;
    void step() {
        const int d = ++done;
        if (!tty) return;
        const int pct = int(100.0 * d / total);
        std::lock_guard<std::mutex> lock(m);
        if (pct == shown) return;
        shown = pct;
        const int bar = 40, filled = bar * d / total;
        std::fprintf(stderr, "\rrender [%s%s] %3d%%", std::string(size_t(filled), '#').c_str(),
                     std::string(size_t(bar - filled), '.').c_str(), pct);
        if (d == total) std::fprintf(stderr, "\n");
        std::fflush(stderr);
    }
};

Image render(const Scene& scene, const Node& node, int width, int height, int spp,
             std::atomic<long>& anomalies) {
    Image img;
    img.width = width;
    img.height = height;
    const size_t n = size_t(width) * size_t(height);
    img.surface.assign(3 * n, 0.0f);
    img.retro.assign(3 * n, 0.0f);
    img.diffuse.assign(3 * n, 0.0f);
    img.alpha.assign(n, 0.0f);
    Progress progress;
    progress.tty = isatty(2) != 0;
    progress.total = height;
    OIIO::parallel_for(0, height, [&](int32_t y) {
        for (int x = 0; x < width; ++x) {
            dvec3 sum[3] = {dvec3(0), dvec3(0), dvec3(0)};
            int hits = 0;
            for (int sy = 0; sy < spp; ++sy)
                for (int sx = 0; sx < spp; ++sx) {
                    const double px = (x + (sx + 0.5) / spp) / width;
                    const double py = (y + (sy + 0.5) / spp) / height;
                    const dvec3 d = glm::normalize(
                        dvec3((2 * px - 1) * scene.tanX, (1 - 2 * py) * scene.tanY, -1.0));
                    Hit h;
                    if (!scene.trace(scene.eye, d, h)) continue;
                    ++hits;
                    const dvec3 t = h.tangent, b = glm::cross(h.n, h.tangent);
                    auto local = [&](const dvec3& w) {
                        return dvec3(glm::dot(w, t), glm::dot(w, b), glm::dot(w, h.n));
                    };
                    const dvec3 wo = local(-d);
                    for (const Light& l : scene.lights) {
                        const dvec3 toL = l.position - h.p;
                        const double d2 = glm::dot(toL, toL);
                        const dvec3 wi = local(toL / std::sqrt(d2));
                        if (wi.z <= 0 || wo.z <= 0) continue;
                        if (scene.occluded(h.p, h.n, l.position)) continue;
                        const Node::Eval e = node.eval(wi, wo);
                        const double k = wi.z * l.intensity / d2;
                        const dvec3 lobes[3] = {e.f.surface, e.f.retro, e.f.diffuse};
                        for (int j = 0; j < 3; ++j) {
                            for (int c = 0; c < 3; ++c)
                                if (!std::isfinite(lobes[j][c]) || lobes[j][c] < 0) ++anomalies;
                            sum[j] += lobes[j] * k;
                        }
                    }
                }
            const double inv = 1.0 / (spp * spp);
            const size_t i = size_t(y) * size_t(width) + size_t(x);
            for (int c = 0; c < 3; ++c) {
                img.surface[3 * i + size_t(c)] = float(sum[0][c] * inv);
                img.retro[3 * i + size_t(c)] = float(sum[1][c] * inv);
                img.diffuse[3 * i + size_t(c)] = float(sum[2][c] * inv);
            }
            img.alpha[i] = float(hits * inv);
        }
        progress.step();
    });
    return img;
}

double parse_number(const std::string& text, const std::string& option, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "%s %s: expected a number in [%g, %g]", option.c_str(),
                      text.c_str(), lo, hi);
        throw InputError(buf);
    }
    return v;
}

fs::path temp_name(const fs::path& dst) {
    return dst.parent_path() / ("." + dst.filename().string() + ".tmp" + std::to_string(getpid()));
}

} // namespace

int cmd_render(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism render: a night-time preview of a MaterialX material with the C++ "
             "reference node: a diamond sign and a sphere under a headlight beside the camera "
             "(small observation angle), optionally a fill light; direct lighting. Writes a "
             "linear EXR (RGBA and one layer per lobe) and a display PNG through OpenColorIO, "
             "then prints the material's R_A table")
        .usage("retroprism render DOC.mtlx -o OUT.exr [--material NAME] [--width W --height H] "
               "[--fill] [--png OUT.png] [--exposure EV] [--view aces|standard] [--samples N] "
               "[--observation DEG] [--sign-angle DEG]");
    std::string doc;
    ap.arg("filename").hidden().action([&](OIIO::cspan<const char*> a) { doc = a[0]; });
    ap.arg("-o FILE").dest("out").help("output EXR (the PNG goes beside it, same stem)");
    ap.arg("--material NAME").help("the material of the document (default: its first)");
    ap.arg("--width W").help("image width in pixels (default 960)").defaultval("960");
    ap.arg("--height H").help("image height in pixels (default 540)").defaultval("540");
    ap.arg("--fill").help("add the fill light (dusk), showing the day colour").store_true();
    ap.arg("--png FILE").help("display PNG path (default: OUT with .png)");
    ap.arg("--exposure EV").help("exposure of the PNG in stops (default -6)").defaultval("-6");
    ap.arg("--view NAME").help("PNG view transform: aces (default) or standard").defaultval("aces");
    ap.arg("--samples N").help("N x N rays per pixel (default 3)").defaultval("3");
    ap.arg("--observation DEG")
        .help("observation angle at the sign's centre, [0, 5] degrees (default 0.5)")
        .defaultval("0.5");
    ap.arg("--sign-angle DEG")
        .help("entrance angle of the headlight at the sign's centre, [0, 80] degrees (default 15)")
        .defaultval("15");
    ap.exit_on_error(false);
    if (ap.parse_args(argc, argv) < 0) {
        std::fprintf(stderr, "retroprism render: %s\n", ap.geterror().c_str());
        return 2;
    }
    if (ap.aborted() || ap["help"].get<int>()) return 0;
    const auto t0 = std::chrono::steady_clock::now();

    // Every input is checked before anything is rendered or written.
    if (doc.empty()) throw InputError("render: give a MaterialX document (.mtlx)");
    const std::string out = ap["out"].get<std::string>();
    if (out.empty()) throw InputError("render: give the output EXR with -o OUT.exr");
    const fs::path exrPath(out);
    if (exrPath.extension() != ".exr")
        throw InputError("-o " + out + ": the output must be an OpenEXR file ending in .exr");
    fs::path pngPath = ap["png"].get<std::string>();
    if (pngPath.empty()) pngPath = fs::path(exrPath).replace_extension(".png");
    if (pngPath.extension() != ".png")
        throw InputError("--png " + pngPath.string() + ": the display image must end in .png");
    for (const fs::path& p : {exrPath, pngPath}) {
        std::error_code ec;
        const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
        if (!fs::is_directory(dir, ec))
            throw InputError(p.string() + ": the folder " + dir.string() + " does not exist");
    }
    const int width = int(parse_number(ap["width"].get<std::string>(), "--width", 8, 8192));
    const int height = int(parse_number(ap["height"].get<std::string>(), "--height", 8, 8192));
    const int spp = int(parse_number(ap["samples"].get<std::string>(), "--samples", 1, 16));
    const double exposure = parse_number(ap["exposure"].get<std::string>(), "--exposure", -30, 30);
    const double observation =
        parse_number(ap["observation"].get<std::string>(), "--observation", 0, 5);
    const double signAngle =
        parse_number(ap["sign-angle"].get<std::string>(), "--sign-angle", 0, 80);
    const std::string view = ap["view"].get<std::string>();
    const auto& views = display_views();
    if (std::find(views.begin(), views.end(), view) == views.end())
        throw InputError("--view " + view + ": expected aces or standard");
    const bool fill = ap["fill"].get<int>() != 0;

    std::string materialName;
    const Params material = document_params(doc, ap["material"].get<std::string>(), &materialName);
    Params shading = material;
    shading.normal = {0.0, 0.0, 1.0};
    shading.tangent = {1.0, 0.0, 0.0};
    const Node node(shading);
    const Scene scene = build_scene(width, height, observation, signAngle, fill);

    std::atomic<long> anomalies{0};
    const Image img = render(scene, node, width, height, spp, anomalies);
    if (anomalies > 0)
        throw std::runtime_error("the node returned " + std::to_string(long(anomalies)) +
                                 " NaN, infinite or negative values; nothing written");

    // The EXR: RGBA combined, then one layer per lobe.
    const size_t n = size_t(width) * size_t(height);
    const int nch = 13;
    std::vector<float> exr(n * size_t(nch));
    std::vector<float> display(n * 3);
    for (size_t i = 0; i < n; ++i) {
        float* px = &exr[i * size_t(nch)];
        for (int c = 0; c < 3; ++c) {
            const float s = img.surface[3 * i + size_t(c)], r = img.retro[3 * i + size_t(c)],
                        d = img.diffuse[3 * i + size_t(c)];
            px[c] = s + r + d;
            px[4 + c] = s;
            px[7 + c] = r;
            px[10 + c] = d;
            display[3 * i + size_t(c)] = s + r + d;
        }
        px[3] = img.alpha[i];
    }
    OIIO::ImageSpec spec(width, height, nch, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R",         "G",         "B",        "A",       "surface.R",
                         "surface.G", "surface.B", "retro.R",  "retro.G", "retro.B",
                         "diffuse.R", "diffuse.G", "diffuse.B"};
    spec.alpha_channel = 3;
    spec.attribute("compression", "zip");
    spec.attribute("ImageDescription",
                   "retroprism render: prismatic retroreflector (Guo, Guo & Pan 2018), material " +
                       materialName + " of " + doc);
    spec.attribute("retroprism:document", doc);
    spec.attribute("retroprism:material", materialName);
    spec.attribute("retroprism:inputs", params_to_json(material).dump());
    spec.attribute("retroprism:quantity",
                   "linear Rec.709 radiance in scene units: f cos(theta_i) I / d^2 summed over the "
                   "lights; R,G,B = surface + retro + diffuse; A = coverage");
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "headlight at (%.4f, %.4f, %.4f), eye at the origin looking down -z; "
                  "observation angle %.3f deg and entrance angle %.2f deg at the sign's centre; "
                  "illuminance 1 there%s",
                  scene.lights[0].position.x, scene.lights[0].position.y,
                  scene.lights[0].position.z, scene.observationAtSign, scene.entranceAtSign,
                  fill ? "; fill light at (-3, 4, 1), illuminance 60 at the sign's centre" : "");
    spec.attribute("retroprism:lights", buf);
    spec.attribute("retroprism:display", display_description(view, exposure));
    OIIO::ImageBuf exrBuf(spec);
    exrBuf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, exr.data());

    apply_display(display, view, exposure);
    OIIO::ImageBuf pngBuf(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT));
    pngBuf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, display.data());

    // Both files under temporary names, then renamed; on any failure neither remains.
    const fs::path exrTmp = temp_name(exrPath), pngTmp = temp_name(pngPath);
    auto cleanup = [&] {
        std::error_code ec;
        fs::remove(exrTmp, ec);
        fs::remove(pngTmp, ec);
    };
    if (!exrBuf.write(exrTmp.string(), OIIO::TypeDesc::FLOAT, "openexr")) {
        const std::string err = exrBuf.geterror();
        cleanup();
        throw InputError(exrPath.string() + ": cannot write (" + err + ")");
    }
    if (!pngBuf.write(pngTmp.string(), OIIO::TypeDesc::UINT8, "png")) {
        const std::string err = pngBuf.geterror();
        cleanup();
        throw InputError(pngPath.string() + ": cannot write (" + err + ")");
    }
    std::error_code ec;
    fs::rename(exrTmp, exrPath, ec);
    if (!ec) {
        fs::rename(pngTmp, pngPath, ec);
        if (ec) {
            std::error_code ignored;
            fs::remove(exrPath, ignored);
        }
    }
    if (ec) {
        cleanup();
        throw InputError(exrPath.string() + ": cannot write (" + ec.message() + ")");
    }

    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("wrote %s (linear: R,G,B,A and layers surface, retro, diffuse)\n",
                exrPath.string().c_str());
    std::printf("wrote %s (%s)\n", pngPath.string().c_str(),
                display_description(view, exposure).c_str());
    std::printf("material \"%s\" of %s: %dx%d, %d rays per pixel, %.1f s; at the sign's centre "
                "observation angle %.3f deg, entrance angle %.2f deg%s\n",
                materialName.c_str(), doc.c_str(), width, height, spp * spp, secs,
                scene.observationAtSign, scene.entranceAtSign, fill ? ", fill light on" : "");
    std::printf("\n");
    print_ra_table(ra_table(material, 0.0), "material \"" + materialName + "\"", false, stdout);
    return 0;
}

} // namespace retroprism
