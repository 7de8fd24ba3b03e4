#pragma once
// GPU check only (tests/gpu): the part of KokkosKernels' KokkosSparse::CrsMatrix that the
// kernels and tests/patches3d.hpp use (graph.row_map, graph.entries, values, numRows,
// sumIntoValues with atomic adds), so that the kernels build against a bare Kokkos with CUDA,
// where no KokkosKernels is installed. The real class is used by every other build.
#include <Kokkos_Core.hpp>

namespace KokkosSparse {

template <class Scalar, class Ordinal, class Device, class MemoryTraits = void, class Size = size_t>
class CrsMatrix {
 public:
  using memory_space = typename Device::memory_space;
  struct Graph {
    Kokkos::View<const Size*, memory_space> row_map;
    Kokkos::View<const Ordinal*, memory_space> entries;
  };
  Graph graph;
  Kokkos::View<Scalar*, memory_space> values;
  Ordinal nrows = 0, ncols = 0;

  CrsMatrix() = default;
  template <class V, class R, class E>
  CrsMatrix(const char*, Ordinal nr, Ordinal nc, Size, const V& val, const R& rm, const E& en)
      : graph{rm, en}, values(val), nrows(nr), ncols(nc) {}

  KOKKOS_INLINE_FUNCTION Ordinal numRows() const { return nrows; }
  KOKKOS_INLINE_FUNCTION Ordinal numCols() const { return ncols; }

  /// vals[i] added to (row, cols[i]) where that entry exists; returns how many were found.
  /// Linear search (the real class searches sorted rows by bisection: the same sums).
  KOKKOS_INLINE_FUNCTION Ordinal sumIntoValues(Ordinal row, const Ordinal* cols, Ordinal n, const Scalar* vals,
                                               bool /*is_sorted*/ = false, bool force_atomic = false) const {
    const Size b = graph.row_map(row), e = graph.row_map(row + 1);
    Ordinal found = 0;
    for (Ordinal i = 0; i < n; ++i)
      for (Size k = b; k < e; ++k)
        if (graph.entries(k) == cols[i]) {
          if (force_atomic) Kokkos::atomic_add(&values(k), vals[i]);
          else values(k) += vals[i];
          ++found;
          break;
        }
    return found;
  }
};

}  // namespace KokkosSparse
