#pragma once
// Internal to solver/contact*.cpp: the contact surface's device data and the search grid
// over its elements (solver/contact_geometry.cpp).
#include <vector>

#include "solver/contact.hpp"
#include "solver/system_internal.hpp"

namespace iga::contact_detail {

// The device data of a contact surface (a chain of patch sides as one curve) and the global
// control point ids of its control points.
CurveData make_curve(const System& sys, const ContactSurface& s, const SurfaceChain& ch, std::vector<GO>& gids);
/// Search grid over the master element boxes (convex hull of their current control points).
SearchGrid build_search_grid(const CurveData& m);

}  // namespace iga::contact_detail
