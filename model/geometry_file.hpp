#pragma once
// Geometry files IGA users already have: the G+Smo XML format (read and written) and the
// GeoPDEs multipatch text format v2.1 (read and written). See docs/geometry-files.md.
#include <string>
#include <vector>

#include "model/multipatch.hpp"

namespace iga {

/// Reads a geometry file by its extension: .xml (G+Smo) or .txt (GeoPDEs). Patches come in the
/// file's order, sides in igacontact's numbering (West, East, South, North [, Front, Back]).
/// Bivariate (TensorNurbs2 / TensorBSpline2, ndim 2) or trivariate (TensorNurbs3 /
/// TensorBSpline3, ndim 3) patches, one kind per file (Patch::dim()); 3-D interfaces carry
/// their face orientation (Interface::face_map / face_flip). Throws InputError, one line:
/// "<file>:<line>: <what is wrong>" (the line where the format lets us know it).
MultiPatch read_geometry_file(const std::string& path);
MultiPatch read_gismo_xml(const std::string& path);
MultiPatch read_geopdes(const std::string& path);

/// Multipatches as one G+Smo XML file's text: their patches as consecutive <Geometry>
/// elements (TensorNurbs2, or TensorBSpline2 where every weight is 1; TensorNurbs3 /
/// TensorBSpline3 with geoDim 3 for trivariate patches) and one <MultiPatch> per entry (its
/// parDim that of its patches) with its interfaces (3-D: G+Smo's 10 numbers) and boundary, in
/// that order; read_gismo_xml reads the first back. Throws std::runtime_error on a multipatch it cannot write. (Files are written by
/// io/files.hpp's write_file_atomic: `igacontact export` and every run's geometry_<body>.xml.)
std::string gismo_xml_text(const std::vector<const MultiPatch*>& multipatches);
/// One multipatch as GeoPDEs v2.1 text (homogeneous coordinate rows, 1-based patches, sides
/// 1..4, 3-D 1..6; interfaces with orientation 1 or -1, 3-D "flag ornt1 ornt2"; each boundary side once, under its first named
/// group, the rest as one block); read_geopdes reads it back (std::runtime_error if it cannot
/// be written).
std::string geopdes_text(const MultiPatch& mp);

}  // namespace iga
