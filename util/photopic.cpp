#include "photopic.h"

#include <algorithm>
#include <cmath>

namespace retroprism {

double illuminant_a(double lambdaNm) {
    const double c = 1.435e7 / 2848.0;
    return 100.0 * std::pow(560.0 / lambdaNm, 5.0) * std::expm1(c / 560.0) /
           std::expm1(c / lambdaNm);
}

namespace {

// CIE 1924 photopic V(lambda), 380 to 780 nm in 10-nm steps (CIE 018:2019 / CIE S 017, the
// table of the CIE 1931 standard observer's y-bar).
constexpr double kV[41] = {0.000039, 0.000120, 0.000396, 0.001210, 0.004000, 0.011600, 0.023000,
                           0.038000, 0.060000, 0.090980, 0.139020, 0.208020, 0.323000, 0.503000,
                           0.710000, 0.862000, 0.954000, 0.994950, 0.995000, 0.952000, 0.870000,
                           0.757000, 0.631000, 0.503000, 0.381000, 0.265000, 0.175000, 0.107000,
                           0.061000, 0.032000, 0.017000, 0.008210, 0.004102, 0.002091, 0.001047,
                           0.000520, 0.000249, 0.000120, 0.000060, 0.000030, 0.000015};

} // namespace

double photopic_v(double lambdaNm) {
    if (!(lambdaNm >= 380.0 && lambdaNm <= 780.0)) return 0.0;
    const double x = (lambdaNm - 380.0) / 10.0;
    const int i = std::min(39, int(x));
    const double f = x - i;
    return kV[i] + f * (kV[i + 1] - kV[i]);
}

const std::vector<double>& photopic_wavelengths_nm() {
    static const std::vector<double> list = [] {
        std::vector<double> l;
        for (int j = 0; j < 15; ++j)
            l.push_back(410.0 + 20.0 * j);
        return l;
    }();
    return list;
}

const std::vector<double>& photopic_weights() {
    static const std::vector<double> weights = [] {
        std::vector<double> w;
        double sum = 0;
        for (double l : photopic_wavelengths_nm()) {
            w.push_back(illuminant_a(l) * photopic_v(l));
            sum += w.back();
        }
        for (double& x : w)
            x /= sum;
        return w;
    }();
    return weights;
}

} // namespace retroprism
