// stress_table.h: the table of the adversarial sweep (`retroprism check --stress`): a line on
// the generator, one row per backend as its sweep ends, then notes (share of non-zero values,
// round-trip differences, samples with u outside the contract, every failure by cause with its
// first examples) and the verdict.
#pragma once

#include <cstdio>
#include <vector>

#include "stress_tally.h"

namespace retroprism {

class StressTable {
  public:
    // Prints the generator's line and the column heads.
    StressTable(const stress::Coverage& coverage, std::FILE* out);
    // Prints the row of one backend (and flushes: a sweep takes seconds to minutes).
    void add(const stress::Tally& t);
    // Prints the notes and "stress: pass" or "stress: FAIL"; true when every backend passed.
    bool finish();

  private:
    std::FILE* out_;
    std::vector<stress::Tally> tallies_;
};

} // namespace retroprism
