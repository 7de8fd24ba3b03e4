#pragma once
// Summing an element matrix into the local matrices of this rank (atomics: correct on
// threaded and GPU backends where elements share control points). Shared by the element
// kernels (elasticity.hpp: internal force and tangent; boundary_load.hpp: follower pressure).
//
// One matrix (orow empty): rows and columns are the overlap numbering pd.lid.
// Owned + ghost (several ranks): the row of control point a goes to A, the owned rows'
// matrix, at local row orow(a) with columns ocol(.), when a is owned here; otherwise to G,
// the few shared rows, at row grow(a) with columns pd.lid(.). (An owned control point couples
// with every control point of its elements, so ocol is defined wherever it is used.)
// Dofs: D per control point, D l + c (D = 2 by default; kernels/numbering.hpp).
// Cost: (D n)^2 atomic additions for an element of n control points, each at a position found
// from the last one (the next column of the same control point) or, where that misses, by
// bisection in a row with ascending columns (sorted_A / sorted_G; the System checks its
// graphs once), else by a linear search from the row's start.
#include "kernels/numbering.hpp"
#include "kernels/types.hpp"

namespace iga {

template <class LocalMatrix>
struct ElementScatter {
  LocalMatrix A = {};
  LocalMatrix G = {};
  Kokkos::View<const int*, MemSpace> orow = {}, ocol = {}, grow = {};
  bool sorted_A = false, sorted_G = false;   // the matrices' rows hold ascending column indices

  /// Adds Ke (D n x D n, row r at Ke + r * ld) of the control points cps[0..n) (patch
  /// numbering) with overlap numbering lid; dofs D l + c (kernels/numbering.hpp).
  template <int MaxN, int D = 2>
  KOKKOS_INLINE_FUNCTION void add(const Kokkos::View<const int*, MemSpace>& lid, const int* cps, int n, const double* Ke,
                                  int ld) const {
    int cols[D * MaxN], gcols[D * MaxN];
    const bool split = orow.extent(0) > 0;
    for (int a = 0; a < n; ++a) {
      const int l = lid(cps[a]), o = split ? ocol(cps[a]) : l;
      for (int c = 0; c < D; ++c) {
        cols[D * a + c] = dof_of(o, c, D);
        gcols[D * a + c] = dof_of(l, c, D);
      }
    }
    for (int r = 0; r < D * n; ++r) {
      const int cp = cps[point_of_dof(r, D)], c = component_of_dof(r, D);
      if (!split) A.sumIntoValues(cols[r], cols, D * n, Ke + r * ld, sorted_A, true);
      else if (orow(cp) >= 0) A.sumIntoValues(dof_of(orow(cp), c, D), cols, D * n, Ke + r * ld, sorted_A, true);
      else G.sumIntoValues(dof_of(grow(cp), c, D), gcols, D * n, Ke + r * ld, sorted_G, true);
    }
  }

  /// Adds one matrix row, dof (cp, comp), against the dofs of control points cps[0..n) (patch
  /// numbering), all D components: v[D j + c] for column (cps[j], c). The row-wise formation's
  /// write (kernels/elasticity_sf.hpp); atomic, since rows are shared with mirrored writes.
  template <int MaxN, int D = 2>
  KOKKOS_INLINE_FUNCTION void add_row(const Kokkos::View<const int*, MemSpace>& lid, int cp, int comp, const int* cps,
                                      int n, const double* v) const {
    int cols[D * MaxN];
    const bool split = orow.extent(0) > 0;
    const bool own = !split || orow(cp) >= 0;
    for (int j = 0; j < n; ++j) {
      const int o = !split || !own ? lid(cps[j]) : ocol(cps[j]);
      for (int c = 0; c < D; ++c) cols[D * j + c] = dof_of(o, c, D);
    }
    if (!split) A.sumIntoValues(dof_of(lid(cp), comp, D), cols, D * n, v, sorted_A, true);
    else if (own) A.sumIntoValues(dof_of(orow(cp), comp, D), cols, D * n, v, sorted_A, true);
    else G.sumIntoValues(dof_of(grow(cp), comp, D), cols, D * n, v, sorted_G, true);
  }
};

}  // namespace iga
