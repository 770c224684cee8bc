// batch_baseline.h: the MaterialX-style retroreflective GGX + Lambert baseline
// (nodes/baselines.h, its math nodes/mrm_core.inc) over a batch, by the same means as the node's
// batch kernels (nodes/batch.cpp): a loop over the baseline core's function under
// `#pragma omp simd`, compiled once per instruction set and chosen at run time, in float.
// The fair batched counterpart of the node's batch rows in the benchmarks.
#pragma once

#include <cstddef>

#include "baselines.h"
#include "batch.h"

namespace retroprism::bench {

// f = specular + diffuse lobe of `model` for n queries in the local frame (unit directions);
// every array of f is written.
void mrm_batch_f(const baselines::RetroreflectiveGGXT<float>& model, std::size_t n,
                 BatchDirections wi, BatchDirections wo, BatchColors f,
                 SimdLevel level = simd_level_supported());

} // namespace retroprism::bench
