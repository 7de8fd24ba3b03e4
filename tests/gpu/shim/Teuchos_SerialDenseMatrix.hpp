#pragma once
// GPU check only (tests/gpu): the device machine has no Trilinos and no LAPACK. model/nurbs.cpp
// solves one small dense system per degree elevation with Teuchos::SerialDenseSolver (LAPACK);
// these two headers stand in for it in the GPU check's host code, with Gaussian elimination
// with partial pivoting (the collocation matrices are banded and well conditioned, n < 40).
// Every other build uses Teuchos.
#include <memory>
#include <vector>

namespace Teuchos {

template <class T>
std::shared_ptr<T> rcpFromRef(T& t) { return std::shared_ptr<T>(&t, [](T*) {}); }

template <class O, class S>
class SerialDenseMatrix {
 public:
  SerialDenseMatrix(O m, O n) : m_(m), n_(n), a_(static_cast<size_t>(m) * n, S(0)) {}
  S& operator()(O i, O j) { return a_[i + static_cast<size_t>(m_) * j]; }
  const S& operator()(O i, O j) const { return a_[i + static_cast<size_t>(m_) * j]; }
  O numRows() const { return m_; }
  O numCols() const { return n_; }

 private:
  O m_, n_;
  std::vector<S> a_;
};

}  // namespace Teuchos
