// brdf_maps.h: a material's BRDF tabulated for pictures: hemisphere maps of f cos(theta_o) per
// lobe and in-plane slices of its luminance, evaluated in double (`retroprism demo`), with a
// count of the values the node must never return.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "prismatic_retroreflector.h"

namespace retroprism {

// Counts values that should never come out of the node (NaN, Inf, negative), with one example.
struct Anomalies {
    std::atomic<long> count{0};
    std::string example;
    void check(const PrismaticRetroreflector<double>::Lobes& f, const glm::dvec3& wi,
               const glm::dvec3& wo);
};

// Hemisphere maps: one panel of n x n pixels per incidence angle thetaIDeg[k] (phi_i = 0, wi
// toward +x), side by side; 12 channels per pixel (surface, retro, diffuse, total; RGB), the
// value f cos(theta_o) at the pixel centre: orthographic view from +z, pixel (u, v) of the unit
// disk -> wo = (u, v, sqrt(1 - u^2 - v^2)), u right, v up; 0 outside.
std::vector<float> hemisphere_maps(const PrismaticRetroreflector<double>& node,
                                   const std::vector<double>& thetaIDeg, int n,
                                   Anomalies& anomalies);

// One in-plane slice: the luminance of f cos(theta_o) per lobe at signed angles s (degrees),
// wo = (sin s, 0, cos s), so s > 0 is on the light's side of the normal.
struct BrdfSlice {
    double thetaIDeg = 0;
    std::vector<double> s;
    std::vector<double> y[4]; // surface, retro, diffuse, total
};

// The slice's angles: uniformSamples + 1 uniform ones over [-90, 90] plus a geometric
// refinement toward the retro (+theta_i) and mirror (-theta_i) peaks, which can be far narrower
// than the uniform step at low roughness.
std::vector<double> slice_angles(double thetaIDeg, int uniformSamples);

// The slice at incidence thetaIDeg over slice_angles(thetaIDeg, uniformSamples).
BrdfSlice brdf_slice(const PrismaticRetroreflector<double>& node, double thetaIDeg,
                     int uniformSamples, Anomalies& anomalies);

} // namespace retroprism
