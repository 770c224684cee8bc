// lidar_report.h: a LiDAR sweep (analysis/lidar.h) as text, CSV and a figure (`retroprism
// lidar`).
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

#include "lidar.h"
#include "plot.h"

namespace retroprism {

// Text: one block per material and wavelength, a row per range, per entrance angle the
// returned fraction P_r / P, that of the Lambertian target of the same albedo and their ratio;
// the block's head gives the albedo per entrance angle.
void print_lidar_table(const std::vector<LidarRow>& rows, std::FILE* out);

// CSV: material,wavelength_nm,range_m,entrance_deg,observation_mrad,fraction,reflectance,
// intercepted,albedo,lambertian_albedo_fraction.
void print_lidar_csv(const std::vector<LidarRow>& rows, std::FILE* out);

// Text: per material and wavelength of `rows`, a row per range, per entrance angle the
// material's P_r / P, the model's at the same geometry (`model`, one per row) and their ratio.
void print_lidar_model(const std::vector<LidarRow>& rows, const std::vector<LidarReturn>& model,
                       const std::string& modelLabel, std::FILE* out);

namespace plot {

// A panel per material (rows) and wavelength (columns): P_r / P against range, log scales, a
// colour per entrance angle; thick lines the material, thin lines the Lambertian target of the
// same albedo. `caption` lines below.
OIIO::ImageBuf lidar_figure(const std::string& title, const std::vector<LidarRow>& rows,
                            const std::vector<std::string>& caption, Text& text);

} // namespace plot

} // namespace retroprism
