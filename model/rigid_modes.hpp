#pragma once
// Rigid-body modes of linear elasticity in dim = 2 or 3: the dim translations e_c, then the
// rotations about each pair of axes (i, j), i < j, in the order (0, 1), (0, 2), (1, 2):
// r_ij(x) = x_i e_j - x_j e_i (in 2-D the one rotation (-y, x)). Used by the rigid-body check
// of a problem (model/problem_checks.cpp), the Newton core (bodies held only by contact) and the null space handed to the AMG
// (solver/nullspace.cpp), so that both count the same modes in either dimension.
namespace iga {

constexpr int kMaxRigidModes = 6;

/// dim translations + dim (dim - 1) / 2 rotations: 3 in 2-D, 6 in 3-D.
constexpr int num_rigid_modes(int dim) { return dim * (dim + 1) / 2; }

/// Component c of rigid mode m at the point x (dim coordinates).
inline double rigid_mode(int m, int c, const double* x, int dim) {
  if (m < dim) return c == m ? 1.0 : 0.0;
  int k = m - dim;
  for (int i = 0; i < dim; ++i)
    for (int j = i + 1; j < dim; ++j, --k)
      if (k == 0) return c == i ? -x[j] : c == j ? x[i] : 0.0;
  return 0.0;
}

struct Body;
namespace detail {
/// Rank of the rigid-body modes restricted to a body's constrained dofs (its Dirichlet
/// supports): num_rigid_modes(dim) when no rigid motion is left free; less where only contact
/// holds the body (model/problem_checks.cpp; the Newton core's close_gaps).
int rigid_rank(const Body& b);
}  // namespace detail

}  // namespace iga
