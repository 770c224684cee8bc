#include "progress.h"

#include <cstdio>

#include <unistd.h>

namespace retroprism {

ProgressBar::ProgressBar(std::string label, std::string unit)
    : label_(std::move(label)), unit_(std::move(unit)), tty_(isatty(fileno(stderr)) != 0),
      t0_(std::chrono::steady_clock::now()) {}

void ProgressBar::operator()(std::uint64_t done, std::uint64_t total) {
    if (!tty_ || total == 0) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    const int width = 30, fill = int(double(width) * double(done) / double(total));
    std::string bar(size_t(fill), '#');
    bar.resize(size_t(width), '.');
    std::fprintf(stderr, "\r%s [%s] %3.0f%%  %.3g %s/s   ", label_.c_str(), bar.c_str(),
                 100.0 * double(done) / double(total), s > 0 ? double(done) / s : 0.0,
                 unit_.c_str());
    if (done >= total) std::fprintf(stderr, "\r%*s\r", int(label_.size()) + width + 40, "");
    std::fflush(stderr);
}

} // namespace retroprism
