#include "night_output.h"

#include <cstdio>
#include <filesystem>
#include <utility>
#include <vector>

#include <unistd.h>

#include <OpenImageIO/imagebuf.h>

#include "display.h"
#include "query.h"

namespace fs = std::filesystem;

namespace retroprism {

namespace {

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

// The EXR image (RGBA combined, then one layer per layer present) and the linear display RGB.
OIIO::ImageBuf exr_image(const NightImage& img, const NightOutput& out,
                         std::vector<float>& display) {
    const size_t n = size_t(img.width) * size_t(img.height);
    const auto present = night_layers(img);
    const size_t channels = 4 + 3 * present.size();
    std::vector<float> exr(n * channels);
    display.assign(n * 3, 0.0f);
    for (size_t i = 0; i < n; ++i) {
        float* px = &exr[i * channels];
        for (size_t c = 0; c < 3; ++c) {
            float sum = 0;
            for (size_t l = 0; l < present.size(); ++l) {
                const float v = (*present[l].second)[3 * i + c];
                px[4 + 3 * l + c] = v;
                sum += v;
            }
            px[c] = sum;
            display[3 * i + c] = sum;
        }
        px[3] = img.alpha[i];
    }
    OIIO::ImageSpec spec(img.width, img.height, int(channels), OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "A"};
    std::string sumText;
    for (const auto& l : present) {
        for (const char* c : {".R", ".G", ".B"})
            spec.channelnames.push_back(std::string(l.first) + c);
        sumText += (sumText.empty() ? "" : " + ") + std::string(l.first);
    }
    spec.alpha_channel = 3;
    spec.attribute("compression", "zip");
    spec.attribute("ImageDescription",
                   "retroprism render: prismatic retroreflector (Guo, Guo & Pan 2018), material " +
                       out.material + " of " + out.document);
    spec.attribute("retroprism:document", out.document);
    spec.attribute("retroprism:material", out.material);
    spec.attribute("retroprism:inputs", out.inputsDescription.empty()
                                            ? params_to_json(out.inputs).dump()
                                            : out.inputsDescription);
    spec.attribute("retroprism:quantity",
                   "linear Rec.709 radiance in scene units: f cos(theta_i) I / d^2 summed over the "
                   "lights; R,G,B = " +
                       sumText + "; A = coverage");
    spec.attribute("retroprism:lights", lights_description(img, out.fill));
    spec.attribute("retroprism:display", display_description(out.view, out.exposureEv));
    OIIO::ImageBuf buf(spec);
    buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, exr.data());
    return buf;
}

} // namespace

std::vector<std::pair<const char*, const std::vector<float>*>> night_layers(const NightImage& img) {
    std::vector<std::pair<const char*, const std::vector<float>*>> out;
    for (const auto& l :
         {std::make_pair("surface", &img.surface), std::make_pair("retro", &img.retro),
          std::make_pair("diffuse", &img.diffuse), std::make_pair("other", &img.other)})
        if (!l.second->empty()) out.push_back(l);
    return out;
}

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
