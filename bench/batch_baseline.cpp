// batch_baseline.cpp: the batched MaterialX-style GGX (batch_baseline.h), compiled with the flags
// of nodes/batch.cpp (bench/CMakeLists.txt).
#include "batch_baseline.h"

#include <algorithm>

namespace retroprism::bench {

namespace {

using f32::vec3;

struct Job {
    const baselines::RetroreflectiveGGXT<float>* model;
    const float* __restrict wi[3];
    const float* __restrict wo[3];
    float* __restrict f[3];
};

// One query; its locals here rather than in the vector loop's body (see nodes/batch.cpp).
inline __attribute__((always_inline)) void one_query(const Job& job, std::size_t i) {
    const baselines::RetroreflectiveGGXT<float>& m = *job.model;
    const vec3 wi(job.wi[0][i], job.wi[1][i], job.wi[2][i]);
    const vec3 wo(job.wo[0][i], job.wo[1][i], job.wo[2][i]);
    vec3 s, d;
    f32::rp_mrm_lobes(m.roughness, m.ior, m.specular, m.tint, m.color, wi, wo, s, d);
    for (int c = 0; c < 3; ++c)
        job.f[c][i] = s[c] + d[c];
}

inline __attribute__((always_inline)) void run(const Job& job, std::size_t n) {
#pragma omp simd
    for (std::size_t i = 0; i < n; ++i)
        one_query(job, i);
}

#define RP_MRM_ISA(NAME, ...)                                                                      \
    __VA_ARGS__ __attribute__((flatten, noinline)) void NAME(const Job& job, std::size_t n) {      \
        run(job, n);                                                                               \
    }
RP_MRM_ISA(mrm_baseline, )
RP_MRM_ISA(mrm_sse42, RP_TARGET_SSE42)
RP_MRM_ISA(mrm_avx2, RP_TARGET_AVX2)
RP_MRM_ISA(mrm_avx512, RP_TARGET_AVX512)
#undef RP_MRM_ISA

} // namespace

void mrm_batch_f(const baselines::RetroreflectiveGGXT<float>& model, std::size_t n,
                 BatchDirections wi, BatchDirections wo, BatchColors f, SimdLevel level) {
    const Job job{&model, {wi.x, wi.y, wi.z}, {wo.x, wo.y, wo.z}, {f.r, f.g, f.b}};
    switch (std::min(level, simd_level_supported())) {
    case SimdLevel::Avx512:
        return mrm_avx512(job, n);
    case SimdLevel::Avx2:
        return mrm_avx2(job, n);
    case SimdLevel::Sse42:
        return mrm_sse42(job, n);
    default:
        return mrm_baseline(job, n);
    }
}

} // namespace retroprism::bench
