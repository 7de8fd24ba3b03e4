#pragma once
// Internal to solver/contact*.cpp: the contact surface's device data and the search grid
// over its elements (solver/contact_geometry.cpp).
#include <string>
#include <type_traits>
#include <vector>

#include "solver/contact.hpp"
#include "solver/system_internal.hpp"

namespace iga::contact_detail {

// The device data of a contact surface (a chain of patch sides as one curve) and the global
// control point ids of its control points.
CurveData make_curve(const System& sys, const ContactSurface& s, const SurfaceChain& ch, std::vector<GO>& gids);
/// Search grid over the master element boxes (convex hull of their current control points).
SearchGrid build_search_grid(const CurveData& m);

/// History: dst <- src, (re)allocated to src's extent (label "<src>_committed"); an empty src
/// keeps nothing.
template <class V>
void keep_copy(V& dst, const V& src) {
  if (!src.data()) return;
  if (dst.extent(0) != src.extent(0)) dst = V(std::string(src.label()) + "_committed", src.extent(0));
  Kokkos::deep_copy(dst, src);
}

}  // namespace iga::contact_detail
