// stress.h: adversarial sweeps of every backend (`retroprism check --stress`).
#pragma once

#include <string>
#include <vector>

namespace retroprism {

// Runs the adversarial sweep through each backend, prints the counts; returns the exit status
// (0 when every count that must be zero is zero).
int run_stress(const std::vector<std::string>& backends);

} // namespace retroprism
