// batch.h: the node over batches of directions for the Python module. A batch runs on every
// core (util/parallel.h) with the GIL released; each row is the C++ node's own answer in the
// batch's precision (float32: PrismaticRetroreflector<float>, float64: <double>), so it does not
// depend on the batch, its order or the thread count.
#pragma once

#include <pybind11/numpy.h>

#include "arrays.h"
#include "prismatic_retroreflector.h"

namespace retroprism::python {

// The node of one set of inputs in both precisions.
struct Node {
    explicit Node(const Params& p) : params(p), f32(p), f64(p) {}
    Params params;
    PrismaticRetroreflector<float> f32;
    PrismaticRetroreflector<double> f64;
};

// {"f", "surface", "retro", "diffuse"}: (N, 3) arrays of the BRDF without the cosine, per lobe
// and in total (the node's eval(); f() when withPdf is false), and "pdf" (N,) when withPdf.
pyb::dict eval_batch(const Node& node, const Batch& wi, const Batch& wo, bool withPdf);

// {"wo", "f", "surface", "retro", "diffuse", "pdf", "lobe", "valid"}: the node's sample() per
// row; rows without a sample have valid False, lobe -1 and zeros.
pyb::dict sample_batch(const Node& node, const Batch& wi, const Batch& u);

// {"surface", "retro", "diffuse", "total"}: (N, 3) directional albedos (the node's albedo()).
pyb::dict albedo_batch(const Node& node, const Batch& wi, int grid);

// (N,) retroreflected fraction E of the mean refracted direction of each wi.
pyb::array retro_fraction_batch(const Node& node, const Batch& wi);

} // namespace retroprism::python
