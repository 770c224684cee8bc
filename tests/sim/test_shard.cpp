// test_shard.cpp: the accuracy study in shards (sim/study.h): the work units and their
// assignment, and `retroprism simulate --study --shard K/N` run as separate processes and merged
// with --merge into the single run's results, bit for bit; the merge's and --shard's errors.
// Every TEST_CASE is tagged [sim].
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "error.h"
#include "study.h"
#include "study_results.h"
#include "test_support.h"

namespace fs = std::filesystem;
namespace sim = retroprism::sim;
using rptest::contains;
using rptest::run_cli;
using rptest::run_command;

namespace {

std::string read_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// An archive's numbers without the run metadata (sim::without_metadata), as save_study writes
// them.
std::string archive_without_metadata(const fs::path& p, const fs::path& scratch) {
    sim::save_study(scratch.string(), sim::without_metadata(sim::load_study(p.string(), true)));
    return read_file(scratch);
}

// The document without its two lines of run metadata (date and machine; rays per second and
// minutes).
std::string doc_without_metadata(const fs::path& p) {
    std::istringstream in(read_file(p));
    std::string line, out;
    while (std::getline(in, line))
        if (line.rfind("- Date:", 0) != 0 && line.rfind("- Rays:", 0) != 0) out += line + "\n";
    return out;
}

// A copy of shard file `from` with its line `lineNo` (1-based) replaced by `text`.
void edit_line(const fs::path& from, const fs::path& to, size_t lineNo, const std::string& text) {
    std::istringstream in(read_file(from));
    std::ofstream out(to);
    size_t n = 0;
    for (std::string line; std::getline(in, line);)
        out << (++n == lineNo ? text : line) << "\n";
}

} // namespace

TEST_CASE("A study's units keep the single run's seeds; shards split them by rays", "[sim]") {
    sim::StudyOptions so;
    so.seed = 11;
    const std::vector<sim::StudyUnit> units = sim::study_units(so);
    const size_t configs = sim::study_grid(false).size();
    REQUIRE(units.size() == configs + 24 + 16);
    // Configuration k: seed + k; the paper's way up counts on (seed + 100000 + k); reciprocity
    // runs of material m: seed + 200000 + 100 m.
    CHECK(units[0].seed == 11);
    CHECK(units[configs - 1].seed == 11 + configs - 1);
    CHECK(units[configs].kind == sim::UnitKind::Direct);
    CHECK(units[configs].seed == 11 + 100000 + configs);
    CHECK(units[configs + 24].kind == sim::UnitKind::Reciprocity);
    CHECK(units[configs + 25].seed == 11 + 200000 + 100);

    std::uint64_t largest = 0;
    for (const sim::StudyUnit& u : units)
        largest = std::max(largest, u.rays);
    for (int n : {1, 2, 3, 7, 50, int(units.size())}) {
        const std::vector<int> owner = sim::shard_assignment(units, n);
        std::vector<std::uint64_t> load(size_t(n), 0);
        for (size_t i = 0; i < units.size(); ++i) {
            REQUIRE(owner[i] >= 1);
            REQUIRE(owner[i] <= n);
            load[size_t(owner[i] - 1)] += units[i].rays;
        }
        // Every shard has work, and none has more than one unit's rays more than another.
        const auto [lo, hi] = std::minmax_element(load.begin(), load.end());
        INFO(n << " shards: " << *lo << " to " << *hi << " rays");
        CHECK(*lo > 0);
        CHECK(*hi - *lo <= largest);
    }
}

TEST_CASE("--shard K/N must be whole numbers with 1 <= K <= N <= the study's units", "[sim]") {
    const sim::ShardSpec s = sim::parse_shard("2/3", "--shard", 5);
    CHECK(s.k == 2);
    CHECK(s.n == 3);
    CHECK(sim::parse_shard("5/5", "--shard", 5).k == 5);
    for (const char* bad :
         {"0/3", "4/3", "a/b", "3", "1/0", "1/6", "1.5/3", "-1/3", "1/3/3", "/3", "1/", ""}) {
        INFO(bad);
        try {
            sim::parse_shard(bad, "--shard", 5);
            FAIL("accepted");
        } catch (const retroprism::InputError& e) {
            CHECK(contains(e.what(), std::string("--shard ") + bad + ": expected K/N"));
            CHECK(contains(e.what(), "1 <= K <= N <= 5"));
        }
    }
}

TEST_CASE("The study run as 3 shard processes merges into the single run's results", "[sim]") {
    const fs::path dir = fs::temp_directory_path() / "retroprism_test_shard";
    fs::remove_all(dir);
    fs::create_directories(dir / "doc");
    // Both write the document to the same place (it names --doc), then it is moved aside.
    const std::string doc = (dir / "doc" / "accuracy.md").string();
    const std::string study =
        "simulate --study --quick --rays 20000 --diffuse-rays 5000 --recip-rays 2000 --seed 7";
    auto part = [&](int k) { return (dir / ("part" + std::to_string(k))).string(); };

    // The single run on 2 threads; the shards at once, as separate processes on 1 thread each.
    const rptest::CommandRun single = run_cli(study + " --threads 2 --doc " + doc + " --save " +
                                              (dir / "single.archive").string());
    INFO(single.output);
    REQUIRE(single.status == 0);
    fs::rename(dir / "doc", dir / "single");
    std::string shards;
    for (int k = 1; k <= 3; ++k)
        shards += std::string(RP_CLI_PATH) + " " + study + " --threads 1 --shard " +
                  std::to_string(k) + "/3 --save " + part(k) + " & p" + std::to_string(k) + "=$!; ";
    const rptest::CommandRun sharded = run_command(shards + "wait $p1 && wait $p2 && wait $p3");
    INFO(sharded.output);
    REQUIRE(sharded.status == 0);
    size_t units = 0;
    for (int k = 1; k <= 3; ++k) {
        const sim::StudyShard s = sim::load_study_shard(part(k));
        CHECK(s.shard.k == k);
        CHECK_FALSE(s.units.empty());
        units += s.units.size();
    }
    sim::StudyOptions quick;
    quick.quick = true;
    CHECK(units == sim::study_units(quick).size());

    // Merged in any order.
    const rptest::CommandRun merged =
        run_cli("simulate --study --merge " + part(3) + " " + part(1) + " " + part(2) + " --doc " +
                doc + " --save " + (dir / "merged.archive").string());
    INFO(merged.output);
    REQUIRE(merged.status == 0);
    fs::rename(dir / "doc", dir / "merged");

    // results.csv, the archive's numbers, the document and the plots are the single run's but
    // for the run metadata (timing, machine, date).
    // results.csv holds results only: byte for byte.
    const std::string csv = read_file(dir / "single" / "accuracy" / "results.csv");
    CHECK(std::count(csv.begin(), csv.end(), '\n') == 3);
    CHECK(csv == read_file(dir / "merged" / "accuracy" / "results.csv"));
    const std::string archive = archive_without_metadata(dir / "single.archive", dir / "a");
    CHECK(archive.size() > 10000);
    CHECK(archive == archive_without_metadata(dir / "merged.archive", dir / "b"));
    CHECK(doc_without_metadata(dir / "single" / "accuracy.md") ==
          doc_without_metadata(dir / "merged" / "accuracy.md"));
    int plots = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(dir / "single" / "accuracy"))
        if (e.path().extension() == ".png") {
            INFO(e.path().filename());
            CHECK(read_file(e.path()) ==
                  read_file(dir / "merged" / "accuracy" / e.path().filename()));
            ++plots;
        }
    CHECK(plots == 3);
    // The merged document says it ran in shards.
    CHECK(contains(read_file(dir / "merged" / "accuracy.md"), "shard 3/3: "));

    // The merge's errors name the offending file. Shard 1 of another seed; shard 2's units
    // under the name of shard 3.
    edit_line(part(1), part(4), 8, "8");
    edit_line(part(2), part(5), 9, "3");
    auto merge_error = [&](const std::vector<std::string>& files) {
        try {
            std::vector<sim::StudyShard> parts;
            for (const std::string& f : files)
                parts.push_back(sim::load_study_shard(f));
            sim::merge_study_shards(parts);
        } catch (const retroprism::InputError& e) {
            return std::string(e.what());
        }
        return std::string("merged");
    };
    struct BadMerge {
        std::vector<std::string> parts;
        std::string expect;
    };
    const std::vector<BadMerge> badMerges = {
        {{part(1), part(2)}, "shard 3/3 is missing (given: " + part(1) + " 1/3, "},
        {{part(1), part(2), part(2), part(3)},
         part(2) + ": shard 2/3 again (" + part(2) + " is shard 2/3)"},
        {{part(2), part(3), part(4)},
         part(4) +
             ": a shard of another study (--rays 20000 --diffuse-rays 5000 --recip-rays "
             "2000 --seed 8 --quick; " +
             part(2) + ": --rays 20000 --diffuse-rays 5000 --recip-rays 2000 --seed 7 --quick)"},
        {{part(1), part(2), part(5)},
         part(5) + ": shard 3/3 holds unit 0 (configuration 20 deg, alpha 0.1, eta 1.49, tir), "
                   "which is shard 2/3's"},
        {{(dir / "single.archive").string()},
         "--merge " + (dir / "single.archive").string() + ": not the partial results of a shard"},
        {{part(1), (dir / "nowhere").string()},
         "--merge " + (dir / "nowhere").string() + ": cannot open file"},
    };
    for (const BadMerge& b : badMerges) {
        const std::string error = merge_error(b.parts);
        INFO(error);
        CHECK(contains(error, b.expect));
    }

    // The command's: the merge's errors, and --shard's, --merge's and --load's options.
    struct Bad {
        std::string args, expect;
    };
    const std::string bad = "simulate --study --doc " + (dir / "bad" / "a.md").string();
    const std::string save = " --save " + part(6);
    for (const Bad& b : std::vector<Bad>{
             {bad + " --merge " + part(1) + " " + part(2), "shard 3/3 is missing"},
             {bad + " --merge", "--merge: expected the shards' files"},
             {bad + " --load " + part(1), "--load " + part(1) + ": the partial results of one"},
             {bad + " --quick --shard 1/3", "--shard 1/3: --save FILE is required"},
             {bad + " --quick --shard 0/3" + save,
              "--shard 0/3: expected K/N, whole numbers with 1 <= K <= N <= 5"},
             {bad + " --shard 1/137" + save, "--shard 1/137: expected K/N, whole numbers with "
                                             "1 <= K <= N <= 136"},
             {bad + " --quick --shard 1/3" + save + " --merge " + part(1),
              "--shard, --merge and --load exclude each other"},
             {bad + " --quick " + part(1), "unexpected argument " + part(1)},
         }) {
        const rptest::CommandRun r = run_cli(b.args);
        INFO(b.args << " -> " << r.output);
        CHECK(r.status != 0);
        CHECK(contains(r.output, b.expect));
        CHECK_FALSE(fs::exists(dir / "bad"));
        CHECK_FALSE(fs::exists(part(6)));
    }
}
