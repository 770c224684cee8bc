// progress.h: a progress bar on a terminal (stderr), nothing when stderr is not a terminal.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace retroprism {

class ProgressBar {
  public:
    // `unit` names what is counted in the rate ("rays").
    explicit ProgressBar(std::string label, std::string unit = "rays");
    // Shows done of total; clears the line when done reaches total.
    void operator()(std::uint64_t done, std::uint64_t total);

  private:
    std::string label_;
    std::string unit_;
    bool tty_;
    std::chrono::steady_clock::time_point t0_;
};

} // namespace retroprism
