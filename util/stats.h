// stats.h: small statistics shared by the libraries.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace retroprism {

// The median of v (the upper one of an even count: v[n / 2] in sorted order); 0 when empty.
inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

} // namespace retroprism
