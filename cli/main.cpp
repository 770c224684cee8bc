// main.cpp: `retroprism COMMAND [options]`: the table of commands and the one place errors are
// turned into messages and exit statuses. Each command lives in cmd_<name>.cpp.
#include <cstdio>
#include <cstring>
#include <string>

#include "commands.h"
#include "error.h"

using namespace retroprism;

namespace {

struct Command {
    const char* name;
    int (*run)(int argc, const char** argv);
    const char* synopsis; // options after the name; a second line starts with '\n'
    const char* summary;
};

const Command kCommands[] = {
    {"eval", cmd_eval, "[--backend NAME] QUERY.json|-",
     "evaluate a batch of direction pairs (JSON answer)"},
    {"era", cmd_era, "--theta-t DEG [--phi DEG] [--mode averaged|matched_pair|oriented]\n",
     "effective retroreflective area of an inner direction"},
    {"albedo", cmd_albedo, "[--material FILE.json] --theta-i DEG...\n",
     "per-lobe and total directional albedo"},
    {"demo", cmd_demo, "[--out DIR] [--materials DIR]",
     "BRDF slice plots of the bundled example materials"},
    {"params", cmd_params, "[--json]", "the node's inputs as a Markdown table or JSON"},
    {"render", cmd_render, "DOC.mtlx -o OUT.exr [--material NAME] [--fill] ...\n",
     "night preview (EXR per lobe + PNG) and R_A table"},
    {"ra", cmd_ra,
     "[--material FILE.json | --document DOC.mtlx [--name NAME]] [--rotation DEG] [--csv]\n",
     "coefficient of retroreflection table"},
    {"fit", cmd_fit, "DATA.dat | --ra TABLE.csv [--json] [--plot OUT.png] [--mtlx OUT.mtlx]\n",
     "fit the node and the MaterialX retro GGX to measurements or an R_A table"},
    {"approach", cmd_approach, "DOC.mtlx --table TABLE.csv --out DIR\n",
     "a preset against the GGX fitted to its table: night previews, luminance on approach"},
    {"lidar", cmd_lidar,
     "[[LABEL=]FILE.json|DOC.mtlx ...] [--wavelength NM,...] [--range M,...] [--csv]\n",
     "LiDAR return of flat targets against range, beside a Lambertian target"},
    {"simulate", cmd_simulate,
     "--theta-i DEG... [--material FILE.json] [--rays N] [--out PREFIX]\n",
     "microgeometry Monte Carlo: the ground-truth BRDF"},
    {"check", cmd_check, "[--backend NAME] [--stress [--quick | --evaluations N]]",
     "cross-check backends against cpp-double"},
    {"export", cmd_export, "--out DIR", "the MaterialX library and GLSL for other pipelines"},
    {"view", cmd_view, "[DOC.mtlx] [--port N] [--no-open]",
     "the look-dev page: the node in WebGL2, served on localhost"},
    {"bench", cmd_bench, "[--json] [--plot OUT.png]", "the speed/accuracy trade table"},
};

// The usage text: each command with its synopsis and, in a column of its own (or on the next
// line when the synopsis is long), its summary.
std::string usage() {
    std::string u = "usage: retroprism COMMAND [options]\n\ncommands:\n";
    const size_t column = 38;
    for (const Command& c : kCommands) {
        std::string line = "  " + std::string(c.name);
        std::string synopsis = c.synopsis;
        const bool ownLine = !synopsis.empty() && synopsis.back() == '\n';
        if (ownLine) synopsis.pop_back();
        if (!synopsis.empty()) line += " " + synopsis;
        if (ownLine) {
            u += line + "\n" + std::string(column, ' ') + c.summary + "\n";
        } else {
            line.resize(std::max(line.size() + 1, column), ' ');
            u += line + c.summary + "\n";
        }
    }
    return u + "\n`retroprism COMMAND --help` describes a command.\n";
}

} // namespace

int main(int argc, const char** argv) {
    if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
        std::fputs(usage().c_str(), argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const std::string cmd = argv[1];
    for (const Command& c : kCommands) {
        if (cmd != c.name) continue;
        try {
            return c.run(argc - 1, argv + 1);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "retroprism %s: error: %s\n", cmd.c_str(), e.what());
            return 1;
        }
    }
    std::fprintf(stderr, "retroprism: unknown command '%s'\n\n%s", cmd.c_str(), usage().c_str());
    return 2;
}
