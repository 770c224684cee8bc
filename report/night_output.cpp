#include "night_output.h"

#include <cstdio>
#include <filesystem>
#include <vector>

#include <unistd.h>

#include <OpenImageIO/imagebuf.h>

#include "display.h"
#include "query.h"

namespace fs = std::filesystem;

namespace retroprism {

namespace {

constexpr int kExrChannels = 13;

fs::path temp_name(const fs::path& dst) {
    return dst.parent_path() / ("." + dst.filename().string() + ".tmp" + std::to_string(getpid()));
}

std::string lights_description(const NightImage& img, bool fill) {
    const NightSceneInfo& s = img.scene;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "headlight at (%.4f, %.4f, %.4f), eye at the origin looking down -z; "
                  "observation angle %.3f deg and entrance angle %.2f deg at the sign's centre; "
                  "illuminance 1 there%s",
                  s.lights[0].position.x, s.lights[0].position.y, s.lights[0].position.z,
                  s.observationAtSign, s.entranceAtSign,
                  fill ? "; fill light at (-3, 4, 1), illuminance 60 at the sign's centre" : "");
    return buf;
}

// The EXR image (RGBA combined, then one layer per lobe) and the linear display RGB.
OIIO::ImageBuf exr_image(const NightImage& img, const NightOutput& out,
                         std::vector<float>& display) {
    const size_t n = size_t(img.width) * size_t(img.height);
    std::vector<float> exr(n * size_t(kExrChannels));
    display.assign(n * 3, 0.0f);
    for (size_t i = 0; i < n; ++i) {
        float* px = &exr[i * size_t(kExrChannels)];
        for (size_t c = 0; c < 3; ++c) {
            const float s = img.surface[3 * i + c], r = img.retro[3 * i + c],
                        d = img.diffuse[3 * i + c];
            px[c] = s + r + d;
            px[4 + c] = s;
            px[7 + c] = r;
            px[10 + c] = d;
            display[3 * i + c] = s + r + d;
        }
        px[3] = img.alpha[i];
    }
    OIIO::ImageSpec spec(img.width, img.height, kExrChannels, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R",         "G",         "B",        "A",       "surface.R",
                         "surface.G", "surface.B", "retro.R",  "retro.G", "retro.B",
                         "diffuse.R", "diffuse.G", "diffuse.B"};
    spec.alpha_channel = 3;
    spec.attribute("compression", "zip");
    spec.attribute("ImageDescription",
                   "retroprism render: prismatic retroreflector (Guo, Guo & Pan 2018), material " +
                       out.material + " of " + out.document);
    spec.attribute("retroprism:document", out.document);
    spec.attribute("retroprism:material", out.material);
    spec.attribute("retroprism:inputs", params_to_json(out.inputs).dump());
    spec.attribute("retroprism:quantity",
                   "linear Rec.709 radiance in scene units: f cos(theta_i) I / d^2 summed over the "
                   "lights; R,G,B = surface + retro + diffuse; A = coverage");
    spec.attribute("retroprism:lights", lights_description(img, out.fill));
    spec.attribute("retroprism:display", display_description(out.view, out.exposureEv));
    OIIO::ImageBuf buf(spec);
    buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, exr.data());
    return buf;
}

} // namespace

void write_night_images(const NightImage& img, const NightOutput& out) {
    std::vector<float> display;
    const OIIO::ImageBuf exrBuf = exr_image(img, out, display);
    apply_display(display, out.view, out.exposureEv);
    OIIO::ImageBuf pngBuf(OIIO::ImageSpec(img.width, img.height, 3, OIIO::TypeDesc::FLOAT));
    pngBuf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, display.data());

    const fs::path exrPath(out.exrPath), pngPath(out.pngPath);
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
}

} // namespace retroprism
