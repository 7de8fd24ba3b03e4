#pragma once
// One numbering for dofs and for tensor-product indices, the same in 2-D and 3-D.
//
// Dofs: control point g (a global id, or a local index into a view) carries the dofs
//   dof = dim g + c,  c = 0 .. dim - 1,
// interleaved by point: the x, y (and z) dofs of one point are adjacent rows.
//
// Tensor-product indices (elements of a patch, control points of a patch):
//   e = i0 + n0 (i1 + n1 i2),
// the first parametric direction fastest, as control points a = i + ncp0 (j + ncp1 k).
//
// Kokkos-only and header-only, so kernels, the solver and the output share it.
#include <Kokkos_Macros.hpp>

namespace iga {

/// Dof of component c of control point g in dimension dim.
template <class I>
KOKKOS_INLINE_FUNCTION constexpr I dof_of(I g, int c, int dim) {
  return static_cast<I>(dim) * g + static_cast<I>(c);
}
/// Control point of a dof.
template <class I>
KOKKOS_INLINE_FUNCTION constexpr I point_of_dof(I dof, int dim) {
  return dof / static_cast<I>(dim);
}
/// Component (0 = x, 1 = y, 2 = z) of a dof.
template <class I>
KOKKOS_INLINE_FUNCTION constexpr int component_of_dof(I dof, int dim) {
  return static_cast<int>(dof % static_cast<I>(dim));
}

/// The tensor index (i0, i1[, i2]) of flat index e over counts n[0..dim): first direction fastest.
KOKKOS_INLINE_FUNCTION void tensor_ij(int e, const int* n, int dim, int* ij) {
  for (int d = 0; d < dim; ++d) {
    ij[d] = e % n[d];
    e /= n[d];
  }
}
/// The flat index of the tensor index ij over counts n[0..dim): the inverse of tensor_ij.
KOKKOS_INLINE_FUNCTION int tensor_index(const int* ij, const int* n, int dim) {
  int e = 0;
  for (int d = dim - 1; d >= 0; --d) e = e * n[d] + ij[d];
  return e;
}

}  // namespace iga
