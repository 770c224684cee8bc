// batch_sample.cpp: see batch_sample.h.
#include "batch_sample.h"

namespace retroprism::batch_detail {

void sample_block(const f32::rp_material& m, const f32::vec3& n, const f32::vec3& t,
                  const f32::vec3& b, const float* const wi[3], const float* const u[3],
                  float* const out[13], int* lobe, std::size_t count) {
    for (std::size_t k = 0; k < count; ++k) {
        f32::vec3 wiLocal, wo;
        f32::rp_lobes r;
        float pdf = 0.0f;
        int chosen = -1;
        // A direction the frame rejects comes back as 0: no sample.
        f32::rp_to_local(n, t, b, f32::vec3(wi[0][k], wi[1][k], wi[2][k]), wiLocal);
        f32::rp_sample(m, wiLocal, f32::vec3(u[0][k], u[1][k], u[2][k]), wo, r, pdf, chosen);
        const f32::vec3 w = wo.x * t + wo.y * b + wo.z * n;
        const float values[13] = {r.surface.x, r.surface.y, r.surface.z, r.retro.x,   r.retro.y,
                                  r.retro.z,   r.diffuse.x, r.diffuse.y, r.diffuse.z, pdf,
                                  w.x,         w.y,         w.z};
        for (int c = 0; c < 13; ++c)
            out[c][k] = values[c];
        lobe[k] = chosen;
    }
}

} // namespace retroprism::batch_detail
