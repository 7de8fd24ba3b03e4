#pragma once
// GPU check only (tests/gpu): see Teuchos_SerialDenseMatrix.hpp beside this file.
#include <cmath>
#include <memory>
#include <utility>

#include "Teuchos_SerialDenseMatrix.hpp"

namespace Teuchos {

template <class O, class S>
class SerialDenseSolver {
 public:
  void setMatrix(std::shared_ptr<SerialDenseMatrix<O, S>> A) { A_ = A; }
  void setVectors(std::shared_ptr<SerialDenseMatrix<O, S>> X, std::shared_ptr<SerialDenseMatrix<O, S>> B) {
    X_ = X;
    B_ = B;
  }
  void factorWithEquilibration(bool) {}
  int solve() {
    SerialDenseMatrix<O, S> A = *A_, B = *B_;
    const O n = A.numRows(), m = B.numCols();
    for (O k = 0; k < n; ++k) {
      O piv = k;
      for (O i = k + 1; i < n; ++i)
        if (std::abs(A(i, k)) > std::abs(A(piv, k))) piv = i;
      if (A(piv, k) == S(0)) return 1;
      for (O j = 0; j < n; ++j) std::swap(A(k, j), A(piv, j));
      for (O j = 0; j < m; ++j) std::swap(B(k, j), B(piv, j));
      for (O i = k + 1; i < n; ++i) {
        const S f = A(i, k) / A(k, k);
        for (O j = k; j < n; ++j) A(i, j) -= f * A(k, j);
        for (O j = 0; j < m; ++j) B(i, j) -= f * B(k, j);
      }
    }
    for (O j = 0; j < m; ++j)
      for (O i = n - 1; i >= 0; --i) {
        S s = B(i, j);
        for (O c = i + 1; c < n; ++c) s -= A(i, c) * (*X_)(c, j);
        (*X_)(i, j) = s / A(i, i);
      }
    return 0;
  }

 private:
  std::shared_ptr<SerialDenseMatrix<O, S>> A_, X_, B_;
};

}  // namespace Teuchos
