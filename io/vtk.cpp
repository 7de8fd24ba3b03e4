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

int vtk_hex_point_index(int i, int j, int k, int p0, int p1, int p2) {
  const bool ib = (i == 0 || i == p0), jb = (j == 0 || j == p1), kb = (k == 0 || k == p2);
  const int n0 = p0 - 1, n1 = p1 - 1, n2 = p2 - 1;   // interior points per edge direction
  const int corner = i ? (j ? 2 : 1) : (j ? 3 : 0);    // of the bottom face, counter-clockwise
  if (ib && jb && kb) return corner + (k ? 4 : 0);
  int off = 8;
  if (jb && kb) return off + (i - 1) + (j ? n0 + n1 : 0) + (k ? 2 * (n0 + n1) : 0);            // edges along i
  if (ib && kb) return off + (j - 1) + (i ? n0 : 2 * n0 + n1) + (k ? 2 * (n0 + n1) : 0);        // edges along j
  off += 4 * (n0 + n1);
  if (ib && jb) return off + (k - 1) + n2 * corner;                                             // edges along k
  off += 4 * n2;
  if (ib) return off + (j - 1) + n1 * (k - 1) + (i ? n1 * n2 : 0);                              // faces i = 0, p0
  off += 2 * n1 * n2;
  if (jb) return off + (i - 1) + n0 * (k - 1) + (j ? n0 * n2 : 0);                              // faces j = 0, p1
  off += 2 * n0 * n2;
  if (kb) return off + (i - 1) + n0 * (j - 1) + (k ? n0 * n1 : 0);                              // faces k = 0, p2
  off += 2 * n0 * n1;
  return off + (i - 1) + n0 * ((j - 1) + n1 * (k - 1));                                         // interior
}

std::vector<std::array<double, 2>> fit_points(int p0, int p1) {
  std::vector<std::array<double, 2>> t;
  for (int j1 = 0; j1 <= p1; ++j1)
    for (int j0 = 0; j0 <= p0; ++j0) t.push_back({static_cast<double>(j0) / p0, static_cast<double>(j1) / p1});
  return t;
}

namespace {

// The Bernstein collocation matrix of one direction, A[j][k] = B_k(j / p), j, k = 0..p, in LU
// form (partial pivoting); apply() multiplies and solve() solves one line of a tensor-product
// array in place (values x[m * stride], m = 0..p).
class Collocation1D {
 public:
  explicit Collocation1D(int p) : n_(p + 1), A_(static_cast<size_t>(n_) * n_), LU_(A_.size()), piv_(n_) {
    for (int j = 0; j < n_; ++j) bernstein(p, static_cast<double>(j) / p, &A_[static_cast<size_t>(j) * n_]);
    LU_ = A_;
    for (int c = 0; c < n_; ++c) {
      int q = c;
      for (int r = c + 1; r < n_; ++r)
        if (std::abs(LU_[r * n_ + c]) > std::abs(LU_[q * n_ + c])) q = r;
      if (LU_[q * n_ + c] == 0.0) throw std::logic_error("fit_rational_bezier: singular collocation matrix");
      piv_[c] = q;
      if (q != c)
        for (int k = 0; k < n_; ++k) std::swap(LU_[c * n_ + k], LU_[q * n_ + k]);
      for (int r = c + 1; r < n_; ++r) {
        LU_[r * n_ + c] /= LU_[c * n_ + c];
        for (int k = c + 1; k < n_; ++k) LU_[r * n_ + k] -= LU_[r * n_ + c] * LU_[c * n_ + k];
      }
    }
  }
  void apply(double* x, size_t stride) const {
    double t[kMaxBasis1D];
    for (int j = 0; j < n_; ++j) {
      t[j] = 0;
      for (int k = 0; k < n_; ++k) t[j] += A_[j * n_ + k] * x[k * stride];
    }
    for (int j = 0; j < n_; ++j) x[j * stride] = t[j];
  }
  void solve(double* x, size_t stride) const {
    double t[kMaxBasis1D];
    for (int j = 0; j < n_; ++j) t[j] = x[j * stride];
    for (int c = 0; c < n_; ++c) std::swap(t[c], t[piv_[c]]);
    for (int r = 1; r < n_; ++r)
      for (int k = 0; k < r; ++k) t[r] -= LU_[r * n_ + k] * t[k];
    for (int r = n_ - 1; r >= 0; --r) {
      for (int k = r + 1; k < n_; ++k) t[r] -= LU_[r * n_ + k] * t[k];
      t[r] /= LU_[r * n_ + r];
    }
    for (int j = 0; j < n_; ++j) x[j * stride] = t[j];
  }

 private:
  int n_;
  std::vector<double> A_, LU_;
  std::vector<int> piv_;
};

// f(x + base, stride) for every line along direction d of an array with counts n[0..dim) and
// ncomp values per entry, laid out c + ncomp (k0 + n0 (k1 + n1 k2)).
template <class F>
void for_each_line(int dim, const int* n, int ncomp, int d, double* x, F f) {
  size_t stride = static_cast<size_t>(ncomp), outer = 1;
  for (int e = 0; e < d; ++e) stride *= static_cast<size_t>(n[e]);
  for (int e = d + 1; e < dim; ++e) outer *= static_cast<size_t>(n[e]);
  for (size_t o = 0; o < outer; ++o)
    for (size_t in = 0; in < stride; ++in) f(x + o * stride * static_cast<size_t>(n[d]) + in, stride);
}

}  // namespace

// The interpolant sum_k B_k(t) w_k c_k / W(t) = v at the tensor grid t_j of fit points means
// (A_0 x .. x A_{D-1}) (w c) = W v with W = (A_0 x .. x A_{D-1}) w, A_d the Bernstein
// collocation matrix of direction d: one small solve per line and direction, O(p^{D+1}) per
// element instead of O(p^{3D}) for the dense system (216 x 216 for a 3-D element at p = 5).
void fit_rational_bezier(int dim, const int* p, const double* w, int ncomp, const double* values, double* coef) {
  int n[3] = {1, 1, 1};
  size_t N = 1;
  std::vector<Collocation1D> A;
  for (int d = 0; d < dim; ++d) {
    n[d] = p[d] + 1;
    N *= static_cast<size_t>(n[d]);
    A.emplace_back(p[d]);
  }
  std::vector<double> W(w, w + N);
  for (int d = 0; d < dim; ++d)
    for_each_line(dim, n, 1, d, W.data(), [&](double* x, size_t s) { A[d].apply(x, s); });
  for (size_t j = 0; j < N; ++j)
    for (int q = 0; q < ncomp; ++q) coef[j * ncomp + q] = W[j] * values[j * ncomp + q];
  for (int d = 0; d < dim; ++d)
    for_each_line(dim, n, ncomp, d, coef, [&](double* x, size_t s) { A[d].solve(x, s); });
  for (size_t k = 0; k < N; ++k)
    for (int q = 0; q < ncomp; ++q) coef[k * ncomp + q] /= w[k];
}

void fit_rational_bezier(int p0, int p1, const double* w, int ncomp, const double* values, double* coef) {
  const int p[2] = {p0, p1};
  fit_rational_bezier(2, p, w, ncomp, values, coef);
}

void clamp_coefficients(int n, int ncomp, const double* lo, const double* hi, double* coef) {
  for (int k = 0; k < n; ++k)
    for (int q = 0; q < ncomp; ++q) coef[k * ncomp + q] = std::clamp(coef[k * ncomp + q], lo[q], hi[q]);
}

namespace {

// First shared Bezier point of each element of one direction, and the number of points. Two
// adjacent elements share their boundary Bezier points where the knot between them has a
// multiplicity below p: the displacement is C^1 there, so the stress is continuous and the
// two elements' stress fits agree on the shared edge. At a C^0 knot (multiplicity p, and
// every knot at p = 1) each element keeps its own points and the stress may jump.
std::vector<int> shared_offsets(const std::vector<double>& U, const std::vector<int>& spans, int p, int& count) {
  std::vector<int> off(spans.size(), 0);
  for (size_t k = 1; k < spans.size(); ++k) {
    const double u = U[spans[k]];
    const auto mult = std::count(U.begin(), U.end(), u);
    off[k] = off[k - 1] + p + (mult < p ? 0 : 1);
  }
  count = spans.empty() ? 0 : off.back() + p + 1;
  return off;
}

}  // namespace

int output_samples(const OutputOptions& o, const Patch& pt) {
  return o.samples(static_cast<int>(pt.element_spans(0).size()), static_cast<int>(pt.element_spans(1).size()),
                   static_cast<long long>(pt.cp.size()));
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
  constexpr double inf = std::numeric_limits<double>::infinity();
  // cells patch after patch of each body; points shared within a patch (shared_offsets)
  for (size_t b = 0; b < P.bodies.size(); ++b)
    for (size_t k = 0; k < P.bodies[b].patches.size(); ++k) {
      const Patch& pt = P.bodies[b].patches[k];
      const BezierPatch B(pt);
      const BodyField field(P, static_cast<int>(b), cp_displacement[b], static_cast<int>(k));
      const std::vector<double> ucp = P.bodies[b].patch_values(static_cast<int>(k), cp_displacement[b]);
      const int p0 = B.degree()[0], p1 = B.degree()[1], n0 = p0 + 1, n = B.points_per_element();
      int N0 = 0, N1 = 0;
      const std::vector<int> off0 = shared_offsets(pt.knots[0], pt.element_spans(0), p0, N0);
      const std::vector<int> off1 = shared_offsets(pt.knots[1], pt.element_spans(1), p1, N1);
      const size_t base = m.weights.size(), np = static_cast<size_t>(N0) * N1;
      m.points.resize(3 * (base + np), 0.0);
      m.weights.resize(base + np);
      m.displacement.resize(3 * (base + np), 0.0);
      m.stress.resize(6 * (base + np), 0.0);
      m.von_mises.resize(base + np);
      // per shared point: the sum of the elements' fitted coefficients, their number, and the
      // union of the sampled ranges of the elements that share it
      std::vector<double> sum(5 * np, 0.0), lo(5 * np, inf), hi(5 * np, -inf);
      std::vector<int> count(np, 0);
      const auto t = fit_points(p0, p1);
      // the bounds of each cell's fit: the fit points and the output sample grid of the cell
      // (the points result.xdmf shows, s per element and direction, ends included)
      const int s = output_samples(P.output, pt);
      // (a grid point that is also a fit point, j0 / s = k0 / p0 and j1 / s = k1 / p1 (the
      // corners always), is the same double and was evaluated with the fit points already)
      std::vector<std::array<double, 2>> tb(t);
      for (int j1 = 0; j1 <= s; ++j1)
        for (int j0 = 0; j0 <= s; ++j0)
          if ((j0 * p0) % s != 0 || (j1 * p1) % s != 0)
            tb.push_back({static_cast<double>(j0) / s, static_cast<double>(j1) / s});
      std::vector<ControlPoint> pts(n);
      std::vector<double> u(2 * n), w(n), vals(5 * n), coef(5 * n), elo(5), ehi(5);
      for (int e = 0; e < B.num_elements(); ++e) {
        B.element_points(e, pts.data());
        B.element_field(e, ucp.data(), 2, u.data());
        const auto r0 = B.range(e, 0), r1 = B.range(e, 1);
        const int s0 = B.span(e, 0), s1 = B.span(e, 1);
        const int e0 = e % B.num_elements(0), e1 = e / B.num_elements(0);
        std::fill(elo.begin(), elo.end(), inf);
        std::fill(ehi.begin(), ehi.end(), -inf);
        for (size_t j = 0; j < tb.size(); ++j) {
          const FieldPoint f = field.eval(r0[0] + tb[j][0] * (r0[1] - r0[0]), r1[0] + tb[j][1] * (r1[1] - r1[0]), s0, s1);
          const double v[5] = {f.sxx, f.syy, f.szz, f.sxy, f.von_mises()};
          for (int q = 0; q < 5; ++q) {
            elo[q] = std::min(elo[q], v[q]);
            ehi[q] = std::max(ehi[q], v[q]);
          }
          if (j < static_cast<size_t>(n)) {
            w[j] = pts[j].w;
            std::copy(v, v + 5, &vals[5 * j]);
          }
        }
        fit_rational_bezier(p0, p1, w.data(), 5, vals.data(), coef.data());
        const size_t cbase = m.connectivity.size();
        m.connectivity.resize(cbase + n);
        for (int kk = 0; kk < n; ++kk) {
          const int i = kk % n0, j = kk / n0;
          const size_t g = static_cast<size_t>(off0[e0] + i) + static_cast<size_t>(N0) * (off1[e1] + j), q = base + g;
          m.connectivity[cbase + vtk_quad_point_index(i, j, p0, p1)] = static_cast<std::int64_t>(q);
          m.points[3 * q] = pts[kk].x[0];
          m.points[3 * q + 1] = pts[kk].x[1];
          m.weights[q] = pts[kk].w;
          m.displacement[3 * q] = u[2 * kk];
          m.displacement[3 * q + 1] = u[2 * kk + 1];
          ++count[g];
          for (int c = 0; c < 5; ++c) {
            sum[5 * g + c] += coef[5 * kk + c];
            lo[5 * g + c] = std::min(lo[5 * g + c], elo[c]);
            hi[5 * g + c] = std::max(hi[5 * g + c], ehi[c]);
          }
        }
        m.offsets.push_back(static_cast<std::int64_t>(cbase + n));
        m.degrees.insert(m.degrees.end(), {p0, p1, 0});
        m.body.push_back(static_cast<int>(b));
        m.patch.push_back(static_cast<int>(k));
        m.element.push_back(e);
        m.element_ij.insert(m.element_ij.end(), {e0, e1});
        m.knot_span.insert(m.knot_span.end(), {s0, s1});
        m.range.insert(m.range.end(), {r0[0], r0[1], r1[0], r1[1]});
      }
      // the shared coefficients: the mean of the elements' fits (equal to round-off where the
      // stress is continuous), clamped into the union of those elements' sampled ranges
      for (size_t g = 0; g < np; ++g) {
        double c[5];
        for (int q = 0; q < 5; ++q) c[q] = sum[5 * g + q] / count[g];
        clamp_coefficients(1, 5, &lo[5 * g], &hi[5 * g], c);
        const double st[6] = {c[0], c[1], c[2], c[3], 0.0, 0.0};
        std::copy(st, st + 6, &m.stress[6 * (base + g)]);
        m.von_mises[base + g] = c[4];
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
    << "<!-- igacontact run_id " << run_id << " -->\n"   // VTK writes string arrays as character codes
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
  // the stress fit is a picture of a field that is not in the spline space: Float32 (the
  // geometry and the displacement, exact, stay Float64)
  w.array("Float32", "stress", 6, std::vector<float>(m.stress.begin(), m.stress.end()), in);
  w.array("Float32", "von_mises", 0, std::vector<float>(m.von_mises.begin(), m.von_mises.end()), in);
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
  const std::vector<std::uint8_t> types(nc, 77);  // VTK_BEZIER_QUADRILATERAL
  if (m.connectivity.size() < static_cast<size_t>(std::numeric_limits<std::int32_t>::max())) {
    w.array("Int32", "connectivity", 0, std::vector<std::int32_t>(m.connectivity.begin(), m.connectivity.end()), in);
    w.array("Int32", "offsets", 0, std::vector<std::int32_t>(m.offsets.begin(), m.offsets.end()), in);
  } else {
    w.array("Int64", "connectivity", 0, m.connectivity, in);
    w.array("Int64", "offsets", 0, m.offsets, in);
  }
  w.array("UInt8", "types", 0, types, in);
  x << "   </Cells>\n  </Piece>\n </UnstructuredGrid>\n";
  if (enc != VtkEncoding::AppendedRaw) {
    x << "</VTKFile>\n";
    return x.str();
  }
  // the binary block appended once into a string of its final size (streaming it through
  // the ostringstream copied tens of MB twice, onto freshly zeroed pages)
  x << " <AppendedData encoding=\"raw\">\n  _";
  const char* tail = "\n </AppendedData>\n</VTKFile>\n";
  std::string out = x.str();
  out.reserve(out.size() + w.appended().size() + std::strlen(tail));
  out += w.appended();
  out += tail;
  return out;
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
