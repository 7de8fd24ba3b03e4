#pragma once
// Displacement and stress of a body at parametric points, evaluated on the host with the
// same basis code the kernels use. For output sampling, probes and error norms in tests.
// 2-D (bivariate patches, plane strain / plane stress) and 3-D (trivariate patches,
// Analysis::Solid): one FieldPoint, whose z, uz, syz and sxz stay 0 in 2-D.
#include <array>
#include <vector>

#include "kernels/types.hpp"
#include "model/problem.hpp"

namespace iga {

struct FieldPoint {
  double x = 0, y = 0;                  // reference position
  double ux = 0, uy = 0;
  double sxx = 0, syy = 0, sxy = 0, szz = 0;   // Cauchy stress (finite kinematics: on the deformed configuration)
  double detJ = 0;                      // det(dx/dxi) at the point
  // 3-D only (0 in 2-D): the reference z, the displacement uz and the shear stresses
  double z = 0, uz = 0, syz = 0, sxz = 0;
  double von_mises() const;
};

class BodyField {
 public:
  /// `u` holds the body's control point displacements, dim per (merged) control point
  /// (dim = P.dim()); the field is that of one of its patches.
  BodyField(const Problem& P, int body, const std::vector<double>& u, int patch = 0);
  /// 2-D: field at (u, v) in the patch's knot range; (s0, s1) the spans to use (-1: find them).
  FieldPoint eval(double u, double v, int s0 = -1, int s1 = -1) const;
  /// 2-D or 3-D: field at the parameters t[0 .. dim()) in the patch's knot ranges; s (null or
  /// dim() entries) the spans to use, an entry -1 (or s null): found.
  FieldPoint eval(const double* t, const int* s = nullptr) const;
  /// The field at the tensor grid of n[d] parameters t[d][0 .. n[d]) per direction d < dim(),
  /// all in the element of spans s (given): out[i0 + n0 (i1 + n1 i2)]. The same numbers as eval
  /// at each point; the element's control points and each parameter's 1-D basis are taken once
  /// (the output's fit points: (p + 1)^dim points an element).
  void eval_grid(const int* s, const int* n, const double* const* t, FieldPoint* out) const;
  const Patch& patch() const { return *patch_; }
  int dim() const { return dim_; }

 private:
  template <int D, class PD>
  void grid(const PD& pd, const int* s, const int* n, const double* const* t, FieldPoint* out) const;
  const Patch* patch_;
  int dim_;
  HostPatchData pd_;     // 2-D
  HostPatchData3 pd3_;   // 3-D
  Material mat_;         // the body's material without thickness
  bool plane_strain_;
  double nu_;
  std::vector<double> u_;
};

}  // namespace iga
