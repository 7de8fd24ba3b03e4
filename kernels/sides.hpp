#pragma once
// Sides of a patch as (direction, end), one rule in 2-D and 3-D.
//
// A side (a face in 3-D) is where parametric direction `direction` is fixed at its start
// (end 0) or at its end (end 1). Sides are numbered s = 2 direction + end:
//   0 west (xi = 0), 1 east (xi = 1), 2 south (eta = 0), 3 north (eta = 1)
//   [3-D: 4 front (zeta = 0), 5 back (zeta = 1)],
// G+Smo's and GeoPDEs' 1-based side numbers minus one (direction = (s - 1) / 2,
// end = (s - 1) % 2 for their s = 1 .. 2 dim).
//
// Outward normal, one sign rule: take the tangents dx/dxi_a of the side's free directions in
// increasing a; in 2-D turn the one tangent t clockwise, (t_y, -t_x); in 3-D take the cross
// product a_i x a_j (i < j). That vector times side_normal_sign(s) times the patch
// orientation (the sign of det dx/dxi) is outward.
//   side_normal_sign = (end ? +1 : -1) (direction even ? +1 : -1):  west -1, east +1,
//   south +1, north -1 [, front -1, back +1].
//
// Kokkos-only and header-only, so kernels and the host (model/nurbs.hpp) share it.
#include <Kokkos_Macros.hpp>

#include "kernels/numbering.hpp"

namespace iga {

/// The parametric direction that is fixed on side s.
KOKKOS_INLINE_FUNCTION constexpr int side_direction(int s) { return s / 2; }
/// 0: the side lies at the start of its direction, 1: at its end.
KOKKOS_INLINE_FUNCTION constexpr int side_end(int s) { return s % 2; }
/// The side number of (direction, end).
KOKKOS_INLINE_FUNCTION constexpr int side_number(int direction, int end) { return 2 * direction + end; }
/// Sides of a patch of dimension dim (4 in 2-D, 6 in 3-D).
KOKKOS_INLINE_FUNCTION constexpr int num_sides(int dim) { return 2 * dim; }
/// +1 or -1: see the header (outward normal = sign x orientation x the tangents' normal).
KOKKOS_INLINE_FUNCTION constexpr int side_normal_sign(int s) {
  return (side_end(s) == 1 ? 1 : -1) * (side_direction(s) % 2 == 0 ? 1 : -1);
}
/// 2-D: the parametric direction along side s (the free one).
KOKKOS_INLINE_FUNCTION constexpr int side_tangent_direction(int s) { return 1 - side_direction(s); }

/// Flat tensor index (numbering.hpp: first direction fastest) over counts n[0..dim) of the
/// entry of side s at position k[0..dim-1) along the side's free directions, in increasing
/// order: the fixed direction's index is 0 at end 0 and n - 1 at end 1. Serves control points
/// (n = control points per direction) and elements (n = elements per direction).
KOKKOS_INLINE_FUNCTION int side_tensor_index(int s, const int* k, const int* n, int dim) {
  int ij[3] = {0, 0, 0};
  const int d = side_direction(s);
  for (int a = 0, f = 0; a < dim; ++a) ij[a] = a == d ? (side_end(s) == 1 ? n[a] - 1 : 0) : k[f++];
  return tensor_index(ij, n, dim);
}

}  // namespace iga
