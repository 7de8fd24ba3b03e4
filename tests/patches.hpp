#pragma once
// Small patches shared by the geometry tests.
#include <cmath>

#include "model/nurbs.hpp"

namespace iga::test {

/// The exact quarter annulus of radii ri < ro about the origin: degree [2, 1], xi along the
/// arc from (r, 0) to (0, r), eta from the inner to the outer radius.
inline Patch annulus(double ri, double ro) {
  Patch P;
  P.degree = {2, 1};
  P.knots = {uniform_open_knots(2, 1), uniform_open_knots(1, 1)};
  const double w = std::sqrt(0.5);
  for (double r : {ri, ro}) P.cp.insert(P.cp.end(), {{{r, 0}, 1}, {{r, r}, w}, {{0, r}, 1}});
  return P;
}

}  // namespace iga::test
