// batch.cpp: the node of main.cpp's material over a batch of queries in float, as a wavefront
// renderer or a sensor simulation would call it (structure-of-arrays directions, per-lobe
// results); prints the f of the first query, which `retroprism eval --backend cpp-float
// query.json` answers within the batch kernels' rounding (glibc's vector exp and erfc).
#include <cstdio>
#include <vector>

#include <retroprism/batch.h>

int main() {
    using namespace retroprism;
    Params p;
    p.roughness = 0.1;
    p.ior = 1.586;
    p.prism_reflection = enum_index(*find_param("prism_reflection"), "tir");
    p.diffuse_color = {0.9, 0.8, 0.1};
    const BatchEvaluator batch(p);
    // 1000 queries: the pair of main.cpp, then the viewer moving away from the light.
    const size_t n = 1000;
    std::vector<float> wix(n, 0.3f), wiy(n, 0.1f), wiz(n, 0.9f), wox(n), woy(n, 0.1f), woz(n, 0.9f);
    for (size_t i = 0; i < n; ++i)
        wox[i] = 0.32f + 0.001f * float(i);
    std::vector<float> lobe[9];
    for (auto& v : lobe)
        v.assign(n, 0.0f);
    const BatchLobes f{{lobe[0].data(), lobe[1].data(), lobe[2].data()},
                       {lobe[3].data(), lobe[4].data(), lobe[5].data()},
                       {lobe[6].data(), lobe[7].data(), lobe[8].data()}};
    batch.eval(n, {wix.data(), wiy.data(), wiz.data()}, {wox.data(), woy.data(), woz.data()}, f,
               nullptr);
    std::printf("f %.9g %.9g %.9g\n", double(lobe[0][0] + lobe[3][0] + lobe[6][0]),
                double(lobe[1][0] + lobe[4][0] + lobe[7][0]),
                double(lobe[2][0] + lobe[5][0] + lobe[8][0]));
    return 0;
}
