// main.cpp: the node of one material evaluated at one direction pair, as a renderer would call
// it; prints the BRDF (1/sr, no cosine) in RGB. `retroprism eval query.json` answers the same
// material and directions (query.json beside this file) with the same "f".
#include <cstdio>

#include <retroprism/prismatic_retroreflector.h>

int main() {
    using namespace retroprism;
    Params p; // every input at its default, then:
    p.roughness = 0.1;
    p.ior = 1.586;
    p.prism_reflection = enum_index(*find_param("prism_reflection"), "tir");
    p.diffuse_color = {0.9, 0.8, 0.1};
    const PrismaticRetroreflector<double> node(p);
    // Light and viewer 1.13 degrees apart, near the retroreflection peak (need not be unit).
    const glm::dvec3 wi(0.3, 0.1, 0.9), wo(0.32, 0.1, 0.9);
    const PrismaticRetroreflector<double>::Eval e = node.eval(wi, wo);
    const glm::dvec3 f = e.f.total();
    std::printf("f %.17g %.17g %.17g\n", f.x, f.y, f.z);
    return 0;
}
