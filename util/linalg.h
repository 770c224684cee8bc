// linalg.h: the small dense linear systems of the fitters (a few unknowns, solved many times).
#pragma once

namespace retroprism {

// Solves A X = B for X by Gaussian elimination with partial pivoting (rows exchanged through a
// permutation) and back substitution. A is n x n, B and X are n x m, all row-major, n <= 8.
// A and B are overwritten. Returns false, leaving X unspecified, when a pivot's magnitude is
// not above 1e-300 (A singular to working precision).
bool solve_linear(int n, int m, double* A, double* B, double* X);

} // namespace retroprism
