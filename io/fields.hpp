#pragma once
// Displacement and stress of a body at parametric points, evaluated on the host with the
// same basis code the kernels use. For output sampling, probes and error norms in tests.
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
  double von_mises() const;
};

class BodyField {
 public:
  /// `u` holds the body's control point displacements, 2 per (merged) control point; the
  /// field is that of one of its patches.
  BodyField(const Problem& P, int body, const std::vector<double>& u, int patch = 0);
  /// Field at (u, v) in the patch's knot range; (s0, s1) the spans to use (-1: find them).
  FieldPoint eval(double u, double v, int s0 = -1, int s1 = -1) const;
  const Patch& patch() const { return *patch_; }

 private:
  const Patch* patch_;
  HostPatchData pd_;
  Material mat_;         // the body's material without thickness
  bool plane_strain_;
  double nu_;
  std::vector<double> u_;
};

}  // namespace iga
