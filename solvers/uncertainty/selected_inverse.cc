#include "solvers/uncertainty/selected_inverse.h"

#include <glog/logging.h>

#include <algorithm>
#include <vector>

namespace nrsfm {

SelectedInverse::SelectedInverse(
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& ldlt) {
  CHECK_EQ(ldlt.info(), Eigen::Success);
  // Strictly lower L, each column's rows ascending (compressed copy).
  Eigen::SparseMatrix<double> l = ldlt.matrixL().nestedExpression();
  l.makeCompressed();
  const int n = static_cast<int>(l.cols());
  const Eigen::VectorXd d = ldlt.vectorD();
  lower_ = l;  // the same pattern, values overwritten with Z below
  diagonal_.resize(n);
  const int* start = l.outerIndexPtr();
  const int* row = l.innerIndexPtr();
  const double* value = l.valuePtr();
  double* z = lower_.valuePtr();
  for (int j = n - 1; j >= 0; --j) {
    const int begin = start[j], end = start[j + 1];
    for (int a = begin; a < end; ++a) {
      const int i = row[a];
      double sum = 0.0;
      for (int b = begin; b < end; ++b) {
        const int k = row[b];
        const double zik = i == k ? diagonal_(i) : Lookup(i, k);
        sum += value[b] * zik;
      }
      z[a] = -sum;
    }
    double sum = 0.0;
    for (int a = begin; a < end; ++a) sum += value[a] * z[a];
    diagonal_(j) = 1.0 / d(j) - sum;
  }
  permutation_ = ldlt.permutationP().indices();
}

double SelectedInverse::Lookup(int i, int j) const {
  if (i < j) std::swap(i, j);
  const int* start = lower_.outerIndexPtr();
  const int* row = lower_.innerIndexPtr();
  const int* first = row + start[j];
  const int* last = row + start[j + 1];
  const int* it = std::lower_bound(first, last, i);
  CHECK(it != last && *it == i)
      << "entry (" << i << ", " << j << ") is outside the factor's pattern";
  return lower_.valuePtr()[it - row];
}

double SelectedInverse::operator()(int i, int j) const {
  const int pi = permutation_(i), pj = permutation_(j);
  return pi == pj ? diagonal_(pi) : Lookup(pi, pj);
}

}  // namespace nrsfm
