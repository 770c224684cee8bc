#include "linalg.h"

#include <cmath>
#include <utility>

namespace retroprism {

bool solve_linear(int n, int m, double* A, double* B, double* X) {
    int perm[8];
    for (int i = 0; i < n; ++i)
        perm[i] = i;
    auto a = [&](int row, int col) -> double& { return A[perm[row] * n + col]; };
    auto b = [&](int row, int col) -> double& { return B[perm[row] * m + col]; };
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i)
            if (std::abs(a(i, k)) > std::abs(a(p, k))) p = i;
        std::swap(perm[k], perm[p]);
        const double pivot = a(k, k);
        if (!(std::abs(pivot) > 1e-300)) return false;
        for (int i = k + 1; i < n; ++i) {
            const double f = a(i, k) / pivot;
            for (int j = k; j < n; ++j)
                a(i, j) -= f * a(k, j);
            for (int c = 0; c < m; ++c)
                b(i, c) -= f * b(k, c);
        }
    }
    for (int c = 0; c < m; ++c)
        for (int k = n - 1; k >= 0; --k) {
            double s = b(k, c);
            for (int j = k + 1; j < n; ++j)
                s -= a(k, j) * X[j * m + c];
            X[k * m + c] = s / a(k, k);
        }
    return true;
}

} // namespace retroprism
