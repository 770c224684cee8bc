// batch_sample.h: sample() of the batch evaluator (batch.h) over one block of queries, in a file
// of its own compiled with the library's flags. Sampling branches per query (its lobe choice,
// the visible-normal inversion), so it runs as a plain loop over the node's float core, which
// the flags of the vector kernels (nodes/batch.cpp; CMakeLists.txt says why they are needed)
// slow by a fifth.
#pragma once

#include <cstddef>

#include "prism_core.h"

namespace retroprism::batch_detail {

// Queries [0, count): wi (in the space of the frame n, t, b) and u as three arrays each; the
// results, as the node's sample() gives them, to out (surface rgb, retro rgb, diffuse rgb, pdf,
// the sampled direction xyz in the frame's space: 0 for an empty sample) and lobe (-1 for an
// empty sample), every array given.
void sample_block(const f32::rp_material& m, const f32::vec3& n, const f32::vec3& t,
                  const f32::vec3& b, const float* const wi[3], const float* const u[3],
                  float* const out[13], int* lobe, std::size_t count);

} // namespace retroprism::batch_detail
