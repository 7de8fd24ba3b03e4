// Rational Bezier cells of all bodies as VTK XML (.vtu) and the .pvd collection: see
// io/vtk.hpp for what is computed, the point order and the array shapes.
#include "io/vtk.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <sstream>
#include <type_traits>
#include <stdexcept>

#include "io/fields.hpp"
#include "kernels/nurbs_basis.hpp"
#include "model/bezier.hpp"

namespace iga {

int vtk_quad_point_index(int i, int j, int p0, int p1) {
  const bool ib = (i == 0 || i == p0), jb = (j == 0 || j == p1);
  if (ib && jb) return i ? (j ? 2 : 1) : (j ? 3 : 0);  // corners, counter-clockwise
  if (jb) return 4 + (i - 1) + (j ? (p0 - 1) + (p1 - 1) : 0);          // edges j = 0, j = p1
  if (ib) return 4 + (j - 1) + (i ? (p0 - 1) : 2 * (p0 - 1) + (p1 - 1));  // edges i = p0, i = 0
  return 4 + 2 * (p0 - 1 + p1 - 1) + (i - 1) + (p0 - 1) * (j - 1);    // face, i fastest
}

std::vector<std::array<double, 2>> fit_points(int p0, int p1) {
  std::vector<std::array<double, 2>> t;
  for (int j1 = 0; j1 <= p1; ++j1)
    for (int j0 = 0; j0 <= p0; ++j0) t.push_back({static_cast<double>(j0) / p0, static_cast<double>(j1) / p1});
  return t;
}

void fit_rational_bezier(int p0, int p1, const double* w, int ncomp, const double* values, double* coef) {
  const int n0 = p0 + 1, n1 = p1 + 1, n = n0 * n1;
  const auto t = fit_points(p0, p1);
  // M[j][k] = B_k0(t_j0) B_k1(t_j1) w_k / W(t_j), the rational basis at the fit points
  std::vector<double> M(static_cast<size_t>(n) * n), rhs(values, values + static_cast<size_t>(n) * ncomp);
  for (int j = 0; j < n; ++j) {
    double b0[kMaxBasis1D], b1[kMaxBasis1D], W = 0;
    bernstein(p0, t[j][0], b0);
    bernstein(p1, t[j][1], b1);
    for (int k1 = 0; k1 < n1; ++k1)
      for (int k0 = 0; k0 < n0; ++k0) {
        const int k = k0 + k1 * n0;
        M[j * n + k] = b0[k0] * b1[k1] * w[k];
        W += M[j * n + k];
      }
    for (int k = 0; k < n; ++k) M[j * n + k] /= W;
  }
  // Gaussian elimination with partial pivoting on all right-hand sides at once
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(M[r * n + c]) > std::abs(M[piv * n + c])) piv = r;
    if (M[piv * n + c] == 0.0) throw std::logic_error("fit_rational_bezier: singular collocation matrix");
    if (piv != c) {
      for (int k = 0; k < n; ++k) std::swap(M[c * n + k], M[piv * n + k]);
      for (int q = 0; q < ncomp; ++q) std::swap(rhs[c * ncomp + q], rhs[piv * ncomp + q]);
    }
    for (int r = c + 1; r < n; ++r) {
      const double f = M[r * n + c] / M[c * n + c];
      if (f == 0.0) continue;
      for (int k = c; k < n; ++k) M[r * n + k] -= f * M[c * n + k];
      for (int q = 0; q < ncomp; ++q) rhs[r * ncomp + q] -= f * rhs[c * ncomp + q];
    }
  }
  for (int r = n - 1; r >= 0; --r)
    for (int q = 0; q < ncomp; ++q) {
      double s = rhs[r * ncomp + q];
      for (int k = r + 1; k < n; ++k) s -= M[r * n + k] * coef[k * ncomp + q];
      coef[r * ncomp + q] = s / M[r * n + r];
    }
}

void clamp_coefficients(int n, int ncomp, const double* lo, const double* hi, double* coef) {
  for (int k = 0; k < n; ++k)
    for (int q = 0; q < ncomp; ++q) coef[k * ncomp + q] = std::clamp(coef[k * ncomp + q], lo[q], hi[q]);
}

BezierMesh bezier_mesh(const Problem& P, const std::vector<std::vector<double>>& cp_displacement) {
  if (cp_displacement.size() != P.bodies.size())
    throw std::invalid_argument("bezier_mesh: one displacement vector per body expected");
  BezierMesh m;
  for (size_t b = 0; b < P.bodies.size(); ++b) {
    if (cp_displacement[b].size() != 2 * static_cast<size_t>(P.bodies[b].num_cps))
      throw std::invalid_argument("bezier_mesh: body " + P.bodies[b].name + ": 2 displacements per control point expected");
    m.body_names.push_back(P.bodies[b].name);
  }
  // cells patch after patch of each body
  for (size_t b = 0; b < P.bodies.size(); ++b)
    for (size_t k = 0; k < P.bodies[b].patches.size(); ++k) {
      const Patch& pt = P.bodies[b].patches[k];
      const BezierPatch B(pt);
      const BodyField field(P, static_cast<int>(b), cp_displacement[b], static_cast<int>(k));
      const std::vector<double> ucp = P.bodies[b].patch_values(static_cast<int>(k), cp_displacement[b]);
      const int p0 = B.degree()[0], p1 = B.degree()[1], n0 = p0 + 1, n = B.points_per_element();
      const auto t = fit_points(p0, p1);
      // the bounds of each cell's fit: the fit points and the output sample grid of the cell
      // (the points result.xdmf shows, s per element and direction, ends included)
      const int s = std::max(1, P.output.samples_per_element);
      std::vector<std::array<double, 2>> tb(t);
      for (int j1 = 0; j1 <= s; ++j1)
        for (int j0 = 0; j0 <= s; ++j0) tb.push_back({static_cast<double>(j0) / s, static_cast<double>(j1) / s});
      std::vector<ControlPoint> pts(n);
      std::vector<double> u(2 * n), w(n), vals(5 * n), coef(5 * n), lo(5), hi(5);
      for (int e = 0; e < B.num_elements(); ++e) {
        B.element_points(e, pts.data());
        B.element_field(e, ucp.data(), 2, u.data());
        const auto r0 = B.range(e, 0), r1 = B.range(e, 1);
        const int s0 = B.span(e, 0), s1 = B.span(e, 1);
        std::fill(lo.begin(), lo.end(), std::numeric_limits<double>::infinity());
        std::fill(hi.begin(), hi.end(), -std::numeric_limits<double>::infinity());
        for (size_t j = 0; j < tb.size(); ++j) {
          const FieldPoint f = field.eval(r0[0] + tb[j][0] * (r0[1] - r0[0]), r1[0] + tb[j][1] * (r1[1] - r1[0]), s0, s1);
          const double v[5] = {f.sxx, f.syy, f.szz, f.sxy, f.von_mises()};
          for (int q = 0; q < 5; ++q) {
            lo[q] = std::min(lo[q], v[q]);
            hi[q] = std::max(hi[q], v[q]);
          }
          if (j < static_cast<size_t>(n)) {
            w[j] = pts[j].w;
            std::copy(v, v + 5, &vals[5 * j]);
          }
        }
        fit_rational_bezier(p0, p1, w.data(), 5, vals.data(), coef.data());
        clamp_coefficients(n, 5, lo.data(), hi.data(), coef.data());
        // scatter into VTK order
        const size_t base = m.weights.size();
        m.points.resize(3 * (base + n));
        m.weights.resize(base + n);
        m.displacement.resize(3 * (base + n));
        m.stress.resize(6 * (base + n));
        m.von_mises.resize(base + n);
        for (int k = 0; k < n; ++k) {
          const size_t q = base + vtk_quad_point_index(k % n0, k / n0, p0, p1);
          m.points[3 * q] = pts[k].x[0];
          m.points[3 * q + 1] = pts[k].x[1];
          m.points[3 * q + 2] = 0.0;
          m.weights[q] = pts[k].w;
          m.displacement[3 * q] = u[2 * k];
          m.displacement[3 * q + 1] = u[2 * k + 1];
          m.displacement[3 * q + 2] = 0.0;
          const double* c = &coef[5 * k];
          const double s[6] = {c[0], c[1], c[2], c[3], 0.0, 0.0};
          std::copy(s, s + 6, &m.stress[6 * q]);
          m.von_mises[q] = c[4];
        }
        m.offsets.push_back(static_cast<std::int64_t>(base + n));
        m.degrees.insert(m.degrees.end(), {p0, p1, 0});
        m.body.push_back(static_cast<int>(b));
        m.patch.push_back(static_cast<int>(k));
        m.element.push_back(e);
        m.element_ij.insert(m.element_ij.end(), {e % B.num_elements(0), e / B.num_elements(0)});
        m.knot_span.insert(m.knot_span.end(), {s0, s1});
        m.range.insert(m.range.end(), {r0[0], r0[1], r1[0], r1[1]});
      }
    }
  return m;
}

namespace {

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      case '\'': o += "&apos;"; break;
      default: o += c;
    }
  }
  return o;
}

bool little_endian() {
  const std::uint16_t one = 1;
  unsigned char c;
  std::memcpy(&c, &one, 1);
  return c == 1;
}

// VTK XML string array values in ascii: the bytes of each string as integers, each string
// followed by 0.
std::string ascii_strings(const std::vector<std::string>& v) {
  std::string o;
  for (const std::string& s : v) {
    for (unsigned char c : s) o += std::to_string(static_cast<int>(c)) + " ";
    o += "0 ";
  }
  return o;
}

// Writes the DataArray elements either inline (ascii) or into the appended block.
class ArrayWriter {
 public:
  ArrayWriter(std::ostringstream& xml, VtkEncoding enc) : xml_(xml), enc_(enc) {}

  template <class T>
  void array(const char* type, const std::string& name, int ncomp, const std::vector<T>& v, const std::string& indent) {
    xml_ << indent << "<DataArray type=\"" << type << "\"";
    if (!name.empty()) xml_ << " Name=\"" << xml_escape(name) << "\"";
    if (ncomp > 0) xml_ << " NumberOfComponents=\"" << ncomp << "\"";
    if (enc_ == VtkEncoding::Ascii) {
      xml_ << " format=\"ascii\">\n" << indent << " ";
      std::ostringstream line;
      if constexpr (std::is_floating_point_v<T>) line << std::setprecision(std::numeric_limits<T>::max_digits10);
      for (size_t k = 0; k < v.size(); ++k) {
        if constexpr (sizeof(T) == 1)
          line << static_cast<int>(v[k]);
        else
          line << v[k];
        line << ((k + 1) % 12 == 0 && k + 1 < v.size() ? "\n " + indent : " ");
      }
      xml_ << line.str() << "\n" << indent << "</DataArray>\n";
    } else {
      xml_ << " format=\"appended\" offset=\"" << appended_.size() << "\"/>\n";
      const std::uint64_t bytes = v.size() * sizeof(T);
      appended_.append(reinterpret_cast<const char*>(&bytes), sizeof(bytes));
      if (bytes) appended_.append(reinterpret_cast<const char*>(v.data()), bytes);
    }
  }
  const std::string& appended() const { return appended_; }

 private:
  std::ostringstream& xml_;
  VtkEncoding enc_;
  std::string appended_;
};

}  // namespace

std::string vtu_text(const BezierMesh& m, double load_factor, const std::string& run_id, VtkEncoding enc) {
  const size_t np = m.num_points(), nc = m.num_cells();
  std::ostringstream x;
  x << "<?xml version=\"1.0\"?>\n"
    << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"" << (little_endian() ? "LittleEndian" : "BigEndian")
    << "\" header_type=\"UInt64\">\n"
    << " <UnstructuredGrid>\n"
    << "  <FieldData>\n"
    << "   <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">"
    << std::setprecision(17) << load_factor << "</DataArray>\n"
    << "   <Array type=\"String\" Name=\"run_id\" NumberOfTuples=\"1\" format=\"ascii\">" << ascii_strings({run_id})
    << "</Array>\n"
    << "   <Array type=\"String\" Name=\"body_names\" NumberOfTuples=\"" << m.body_names.size() << "\" format=\"ascii\">"
    << ascii_strings(m.body_names) << "</Array>\n"
    << "  </FieldData>\n"
    << "  <Piece NumberOfPoints=\"" << np << "\" NumberOfCells=\"" << nc << "\">\n";
  ArrayWriter w(x, enc);
  const std::string in = "    ";
  x << "   <PointData Scalars=\"von_mises\" Vectors=\"displacement\" Tensors=\"stress\" RationalWeights=\"RationalWeights\">\n";
  w.array("Float64", "RationalWeights", 0, m.weights, in);
  w.array("Float64", "displacement", 3, m.displacement, in);
  w.array("Float64", "stress", 6, m.stress, in);
  w.array("Float64", "von_mises", 0, m.von_mises, in);
  x << "   </PointData>\n"
    << "   <CellData Scalars=\"body\" HigherOrderDegrees=\"HigherOrderDegrees\">\n";
  w.array("Int32", "HigherOrderDegrees", 3, m.degrees, in);
  w.array("Int32", "body", 0, m.body, in);
  w.array("Int32", "patch", 0, m.patch, in);
  w.array("Int32", "element", 0, m.element, in);
  w.array("Int32", "element_ij", 2, m.element_ij, in);
  w.array("Int32", "knot_span", 2, m.knot_span, in);
  w.array("Float64", "parametric_range", 4, m.range, in);
  x << "   </CellData>\n   <Points>\n";
  w.array("Float64", "Points", 3, m.points, in);
  x << "   </Points>\n   <Cells>\n";
  std::vector<std::int64_t> conn(np);
  for (size_t k = 0; k < np; ++k) conn[k] = static_cast<std::int64_t>(k);
  const std::vector<std::uint8_t> types(nc, 77);  // VTK_BEZIER_QUADRILATERAL
  w.array("Int64", "connectivity", 0, conn, in);
  w.array("Int64", "offsets", 0, m.offsets, in);
  w.array("UInt8", "types", 0, types, in);
  x << "   </Cells>\n  </Piece>\n </UnstructuredGrid>\n";
  if (enc == VtkEncoding::AppendedRaw) x << " <AppendedData encoding=\"raw\">\n  _" << w.appended() << "\n </AppendedData>\n";
  x << "</VTKFile>\n";
  return x.str();
}

std::string bezier_vtu(const Problem& P, const std::vector<std::vector<double>>& cp_displacement, double load_factor,
                       const std::string& run_id, VtkEncoding encoding) {
  return vtu_text(bezier_mesh(P, cp_displacement), load_factor, run_id, encoding);
}

std::string pvd_collection(const std::vector<std::pair<double, std::string>>& steps) {
  std::ostringstream x;
  x << std::setprecision(17);
  x << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\""
    << (little_endian() ? "LittleEndian" : "BigEndian") << "\">\n <Collection>\n";
  for (const auto& s : steps)
    x << "  <DataSet timestep=\"" << s.first << "\" group=\"\" part=\"0\" file=\"" << xml_escape(s.second) << "\"/>\n";
  x << " </Collection>\n</VTKFile>\n";
  return x.str();
}

}  // namespace iga
