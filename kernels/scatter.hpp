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
// Cost: (2 n)^2 atomic additions for an element of n control points, each at a position found
// from the last one (the next column of the same control point) or, where that misses, by
// bisection in a row with ascending columns (sorted_A / sorted_G; the System checks its
// graphs once), else by a linear search from the row's start.
#include "kernels/types.hpp"

namespace iga {

template <class LocalMatrix>
struct ElementScatter {
  LocalMatrix A = {};
  LocalMatrix G = {};
  Kokkos::View<const int*, MemSpace> orow = {}, ocol = {}, grow = {};
  bool sorted_A = false, sorted_G = false;   // the matrices' rows hold ascending column indices

  /// Adds Ke (2 n x 2 n, row r at Ke + r * ld) of the control points cps[0..n) (patch
  /// numbering) with overlap numbering lid.
  template <int MaxN>
  KOKKOS_INLINE_FUNCTION void add(const Kokkos::View<const int*, MemSpace>& lid, const int* cps, int n, const double* Ke,
                                  int ld) const {
    int cols[2 * MaxN], gcols[2 * MaxN];
    const bool split = orow.extent(0) > 0;
    for (int a = 0; a < n; ++a) {
      const int l = lid(cps[a]), o = split ? ocol(cps[a]) : l;
      cols[2 * a] = 2 * o;
      cols[2 * a + 1] = 2 * o + 1;
      gcols[2 * a] = 2 * l;
      gcols[2 * a + 1] = 2 * l + 1;
    }
    for (int r = 0; r < 2 * n; ++r) {
      const int cp = cps[r / 2];
      if (!split) A.sumIntoValues(cols[r], cols, 2 * n, Ke + r * ld, sorted_A, true);
      else if (orow(cp) >= 0) A.sumIntoValues(2 * orow(cp) + r % 2, cols, 2 * n, Ke + r * ld, sorted_A, true);
      else G.sumIntoValues(2 * grow(cp) + r % 2, gcols, 2 * n, Ke + r * ld, sorted_G, true);
    }
  }

  /// Adds one matrix row, dof (cp, comp), against the dofs of control points cps[0..n) (patch
  /// numbering), both components: v[2 j + c] for column (cps[j], c). The row-wise formation's
  /// write (kernels/elasticity_sf.hpp); atomic, since rows are shared with mirrored writes.
  template <int MaxN>
  KOKKOS_INLINE_FUNCTION void add_row(const Kokkos::View<const int*, MemSpace>& lid, int cp, int comp, const int* cps,
                                      int n, const double* v) const {
    int cols[2 * MaxN];
    const bool split = orow.extent(0) > 0;
    const bool own = !split || orow(cp) >= 0;
    for (int j = 0; j < n; ++j) {
      const int o = !split || !own ? lid(cps[j]) : ocol(cps[j]);
      cols[2 * j] = 2 * o;
      cols[2 * j + 1] = 2 * o + 1;
    }
    if (!split) A.sumIntoValues(2 * lid(cp) + comp, cols, 2 * n, v, sorted_A, true);
    else if (own) A.sumIntoValues(2 * orow(cp) + comp, cols, 2 * n, v, sorted_A, true);
    else G.sumIntoValues(2 * grow(cp) + comp, cols, 2 * n, v, sorted_G, true);
  }
};

}  // namespace iga
