// ra.cpp: a pipeline's use of the readers and the photometry: the R_A table (luminance Y,
// cd lx^-1 m^-2) of a JSON material at the standard angles, one "observation,entrance,Y" line per
// entry, the values of `retroprism ra --csv --material FILE`.
#include <cstdio>

#include <retroprism/photometry.h>
#include <retroprism/query.h>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: consumer_ra MATERIAL.json\n");
        return 2;
    }
    try {
        using namespace retroprism;
        const Params p = params_from_json(read_json(argv[1]), argv[1]);
        const RaTable t = ra_table(p, 0.0);
        for (size_t r = 0; r < t.observation.size(); ++r)
            for (size_t c = 0; c < t.entrance.size(); ++c)
                std::printf("%g,%g,%.9g\n", t.observation[r], t.entrance[c],
                            luminance_709(t.rgb[r][c]));
    } catch (const retroprism::InputError& e) {
        std::fprintf(stderr, "consumer_ra: %s\n", e.what());
        return 1;
    }
    return 0;
}
