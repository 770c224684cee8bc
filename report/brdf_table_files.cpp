// brdf_table_files.cpp: EXR and JSON files of a tabulated BRDF (see brdf_table_files.h).
#include "brdf_table_files.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include "error.h"
#include "query.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace retroprism::report {

namespace {

const char* const kGridKinds[4] = {"gnomonic", "disk", "strip", "cone"};

// A double rounded to 7 significant digits, so that JSON prints it short.
double r7(double v) {
    if (!std::isfinite(v) || v == 0) return v;
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.7g", v);
    return std::strtod(buf, nullptr);
}

json vec_json(const sim::dvec3& v) {
    return {r7(v.x), r7(v.y), r7(v.z)};
}

OIIO::ImageSpec part_spec(const sim::Grid& grid, const json& meta) {
    OIIO::ImageSpec spec(grid.nx, grid.ny, 31, OIIO::TypeDesc::FLOAT);
    spec.channelnames.clear();
    for (const char* suffix : {"", "_se"})
        for (const char* lobe : sim::kTableLobes)
            for (const char* c : {"R", "G", "B"})
                spec.channelnames.push_back(std::string(lobe) + suffix + "." + c);
    spec.channelnames.push_back("projected_solid_angle.Y");
    spec.attribute("oiio:subimagename", grid.name);
    spec.attribute("compression", "zip");
    spec.attribute("retroprism:quantity",
                   "per lobe: cosine-weighted cell average of the BRDF f [1/sr] and its "
                   "standard error (_se); projected_solid_angle [sr] of the cell above the "
                   "horizon");
    spec.attribute("retroprism:grid", grid.name);
    spec.attribute("retroprism:grid_kind", kGridKinds[grid.kind]);
    spec.attribute("retroprism:mapping",
                   "pixel (i, j), j counted from the bottom row, is cell j*nx+i of the "
                   "parameter rectangle [x0,x1]x[y0,y1] (see the JSON output)");
    float frame[9] = {float(grid.c.x),  float(grid.c.y),  float(grid.c.z),
                      float(grid.e1.x), float(grid.e1.y), float(grid.e1.z),
                      float(grid.e2.x), float(grid.e2.y), float(grid.e2.z)};
    spec.attribute("retroprism:frame_c_e1_e2", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 9), frame);
    float rect[4] = {float(grid.x0), float(grid.x1), float(grid.y0), float(grid.y1)};
    spec.attribute("retroprism:x0_x1_y0_y1", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 4), rect);
    spec.attribute("retroprism:run", meta.dump());
    return spec;
}

std::vector<float> part_pixels(const sim::BrdfTable& t, size_t g) {
    const sim::Grid& grid = t.grids[g];
    std::vector<float> px(size_t(grid.nx) * size_t(grid.ny) * 31, 0.0f);
    for (int cell = 0; cell < grid.cells(); ++cell) {
        const int i = cell % grid.nx, j = cell / grid.nx;
        float* p = &px[(size_t(grid.ny - 1 - j) * size_t(grid.nx) + size_t(i)) * 31];
        for (size_t l = 0; l < 5; ++l)
            for (size_t c = 0; c < 3; ++c) {
                p[l * 3 + c] = float(t.f[c][g][l][size_t(cell)]);
                p[15 + l * 3 + c] = float(t.se[c][g][l][size_t(cell)]);
            }
        p[30] = float(t.projected[g][size_t(cell)]);
    }
    return px;
}

} // namespace

json simulation_json(const Params& material, const sim::TableOptions& o) {
    json doc;
    doc["material"] = params_to_json(sanitize(material));
    doc["simulator"] = {
        {"rays_per_direction", o.rays},
        {"seed", o.seed},
        {"way_up", o.way_up_through_prisms ? "through_prisms" : "direct"},
        {"description",
         "Monte Carlo through the explicit microgeometry (sim/microgeometry.h): Smith random walk "
         "on the rough top surface, exact cube-corner tracing, Lambertian substrate; f per lobe "
         "as cosine-weighted cell averages [1/sr] with binomial standard errors"}};
    doc["incidences"] = json::array();
    return doc;
}

json incidence_json(const sim::BrdfTable& t, std::uint64_t rays, const std::string& exrPath) {
    const sim::Run& r0 = t.runs[0];
    json inc;
    inc["theta_i_deg"] = t.theta_i_deg;
    inc["phi_i_deg"] = t.phi_i_deg;
    inc["wi"] = vec_json(t.wi);
    inc["rays"] = rays;
    inc["threads"] = r0.threads;
    inc["seconds"] = r7(r0.seconds);
    inc["rays_per_second"] = r7(r0.rays_per_second());
    json fates = json::object();
    for (int fate = 0; fate < sim::kFates; ++fate) {
        json perChannel = json::array();
        for (int c = 0; c < 3; ++c)
            perChannel.push_back(
                r7(double(t.runs[size_t(t.run_of[c])].tally.fates[size_t(fate)]) / double(rays)));
        fates[sim::fate_name(fate)] = perChannel;
    }
    inc["fates_fraction_rgb"] = fates;
    inc["retro_primary_fraction"] = r7(double(r0.tally.retro_primary) / double(rays));
    inc["surface_single_fraction"] = r7(double(r0.tally.surface_single) / double(rays));
    json jg = json::array();
    for (size_t g = 0; g < t.grids.size(); ++g) {
        const sim::Grid& grid = t.grids[g];
        json o;
        o["name"] = grid.name;
        o["kind"] = kGridKinds[grid.kind];
        o["c"] = vec_json(grid.c);
        o["e1"] = vec_json(grid.e1);
        o["e2"] = vec_json(grid.e2);
        o["x0_x1_y0_y1"] = {r7(grid.x0), r7(grid.x1), r7(grid.y0), r7(grid.y1)};
        o["nx"] = grid.nx;
        o["ny"] = grid.ny;
        json centres = json::array(), proj = json::array();
        for (int cell = 0; cell < grid.cells(); ++cell) {
            centres.push_back(vec_json(grid.cell_centre(cell)));
            proj.push_back(r7(t.projected[g][size_t(cell)]));
        }
        o["cell_centre"] = centres;
        o["projected_solid_angle"] = proj;
        for (size_t l = 0; l < 5; ++l) {
            json fv = json::array(), sv = json::array();
            for (int cell = 0; cell < grid.cells(); ++cell) {
                json a = json::array(), b = json::array();
                for (size_t c = 0; c < 3; ++c) {
                    a.push_back(r7(t.f[c][g][l][size_t(cell)]));
                    b.push_back(r7(t.se[c][g][l][size_t(cell)]));
                }
                fv.push_back(a);
                sv.push_back(b);
            }
            o[std::string(sim::kTableLobes[l])] = {{"f", fv}, {"se", sv}};
        }
        jg.push_back(o);
    }
    inc["grids"] = jg;
    inc["exr"] = exrPath;
    return inc;
}

void write_table_exr(const std::string& path, const sim::BrdfTable& table, const json& meta) {
    std::vector<OIIO::ImageSpec> specs;
    std::vector<std::vector<float>> pixels;
    for (size_t g = 0; g < table.grids.size(); ++g) {
        specs.push_back(part_spec(table.grids[g], meta));
        pixels.push_back(part_pixels(table, g));
    }
    // Multi-part EXR: every part shares one display window.
    int fullW = 1, fullH = 1;
    for (const OIIO::ImageSpec& sp : specs) {
        fullW = std::max(fullW, sp.width);
        fullH = std::max(fullH, sp.height);
    }
    for (OIIO::ImageSpec& sp : specs) {
        sp.full_x = sp.full_y = 0;
        sp.full_width = fullW;
        sp.full_height = fullH;
    }
    const std::string tmp = path + ".tmp" + std::to_string(getpid());
    auto out = OIIO::ImageOutput::create("openexr");
    if (!out) throw InputError(path + ": cannot create an EXR writer");
    bool ok = out->open(tmp, int(specs.size()), specs.data());
    for (size_t g = 0; ok && g < specs.size(); ++g) {
        if (g > 0) ok = out->open(tmp, specs[g], OIIO::ImageOutput::AppendSubimage);
        ok = ok && out->write_image(OIIO::TypeDesc::FLOAT, pixels[g].data());
    }
    ok = out->close() && ok;
    std::error_code ec;
    if (!ok) {
        const std::string err = out->geterror();
        fs::remove(tmp, ec);
        throw InputError(path + ": cannot write (" + err + ")");
    }
    fs::rename(tmp, path, ec);
    if (ec) throw InputError(path + ": cannot write (" + ec.message() + ")");
}

void write_json_file(const std::string& path, const json& doc) {
    const std::string tmp = path + ".tmp" + std::to_string(getpid());
    {
        std::ofstream f(tmp);
        f << doc.dump() << "\n";
        if (!f) throw InputError(path + ": cannot write");
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw InputError(path + ": cannot write (" + ec.message() + ")");
}

} // namespace retroprism::report
