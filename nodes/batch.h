// batch.h: the node over batches of queries (wi, wo) with one material, in float, for renderers
// that shade many points at once (wavefront integrators, OSL's batched shading, light loops).
//
// Conventions: those of the node (prismatic_retroreflector.h): directions in the frame of the
// node's normal and tangent, normalised here; f per lobe without the cosine; pdf the one-sample
// mixture's. Inputs and outputs are structure-of-arrays: query i reads wi.x[i], wi.y[i], wi.z[i]
// and writes surface.r[i], ... A query the node would answer with zero (below the horizon,
// non-finite) gets zero values, a zero pdf and, for sample, lobe -1 and wo = 0.
//
// The math is the node's core (prism_core.inc), the same source the scalar node and the GLSL
// compile: batch.cpp loops over its per-query functions under `#pragma omp simd`, compiled once
// per instruction set (AVX-512, AVX2, SSE4.2, the x86-64 baseline) and chosen at run time; the
// exponentials, logarithms, sines and erfc go to glibc's vector math library (libmvec).
// Results equal the scalar float node's within the float contract of `retroprism check`.
#pragma once

#include <cstddef>

#include "prismatic_retroreflector.h"

namespace retroprism {

// Instruction sets of the batch kernels, in increasing order.
enum class SimdLevel { Baseline = 0, Sse42 = 1, Avx2 = 2, Avx512 = 3 };
// GCC's target attributes of the levels above baseline, the features simd_level_supported()
// tests: what a kernel compiled for that level may use (nodes/batch.cpp, and kernels built the
// same way elsewhere, such as bench/batch_baseline.cpp's).
#define RP_TARGET_SSE42 __attribute__((target("sse4.2,popcnt")))
#define RP_TARGET_AVX2 __attribute__((target("avx2,fma,bmi,bmi2,popcnt")))
#define RP_TARGET_AVX512                                                                           \
    __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,bmi,bmi2,popcnt")))
// The best level this CPU runs.
SimdLevel simd_level_supported();
// "baseline", "sse4.2", "avx2", "avx512".
const char* simd_level_name(SimdLevel level);

// N directions as three arrays.
struct BatchDirections {
    const float* x = nullptr;
    const float* y = nullptr;
    const float* z = nullptr;
};
// One RGB value per query as three arrays.
struct BatchColors {
    float* r = nullptr;
    float* g = nullptr;
    float* b = nullptr;
};
// The three lobes per query; a lobe whose arrays are null is not written.
struct BatchLobes {
    BatchColors surface;
    BatchColors retro;
    BatchColors diffuse;
};
// Where sample() writes: directions, lobes, pdf and the sampled lobe (-1 for an empty sample).
struct BatchSamples {
    float* x = nullptr;
    float* y = nullptr;
    float* z = nullptr;
    BatchLobes f;
    float* pdf = nullptr;
    int* lobe = nullptr;
};

struct BatchOptions {
    // Threads for one call (0: one per core). Batches shorter than `grain` per thread stay on
    // the calling thread.
    int threads = 1;
    std::size_t grain = 4096;
    // The kernels' instruction set: the best supported one by default; a level above it is
    // lowered to it.
    SimdLevel level = simd_level_supported();
};

class BatchEvaluator {
  public:
    explicit BatchEvaluator(const Params& params = Params());

    // f per lobe and, when pdf is not null, the mixture pdf of n queries.
    void eval(std::size_t n, BatchDirections wi, BatchDirections wo, BatchLobes f, float* pdf,
              const BatchOptions& options = BatchOptions()) const;
    // The mixture pdf alone.
    void pdf(std::size_t n, BatchDirections wi, BatchDirections wo, float* pdf,
             const BatchOptions& options = BatchOptions()) const;
    // One sample per query from u in [0, 1)^3 (u.z chooses the lobe), as the node's sample().
    void sample(std::size_t n, BatchDirections wi, BatchDirections u, BatchSamples out,
                const BatchOptions& options = BatchOptions()) const;

    const PrismaticRetroreflector<float>& node() const { return node_; }

  private:
    PrismaticRetroreflector<float> node_;
    f32::vec3 n_, t_, b_;
};

} // namespace retroprism
