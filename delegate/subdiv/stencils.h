// SPDX-License-Identifier: Apache-2.0
// Stencils: a sparse row table (CSR) that maps source values to refined values by weighted sums.
#pragma once

#include <cstddef>
#include <vector>

namespace principled::subdiv {

/// Row r of the table computes dst[r] = sum_k weights[k] * src[indices[k]] for k in
/// [offsets[r], offsets[r+1]). Values are flat float arrays with `components` floats per
/// element, so the same table refines points (3), st (2), colors (3 or 4) or scalars (1).
/// An empty table (no rows) means "no table"; callers decide what that stands for.
/// Immutable after construction; apply() is const and may run concurrently.
struct Stencils {
    std::vector<int> offsets{0};  ///< rows + 1 entries; offsets[0] == 0
    std::vector<int> indices;     ///< source element of each weight
    std::vector<float> weights;

    size_t rows() const { return offsets.size() - 1; }
    bool empty() const { return rows() == 0; }
    size_t entries() const { return weights.size(); }
    size_t bytes() const;  ///< memory held by the three arrays

    /// Largest source index + 1 (0 for an empty table): the source array must be this long.
    size_t sourceCount() const;

    /// dst must hold rows() * components floats; src sourceCount() * components floats.
    /// Runs in parallel over rows (TBB) for large tables.
    void apply(const float* src, int components, float* dst) const;
};

/// Tables applied one after the other (e.g. one per subdivision level).
using StencilChain = std::vector<Stencils>;

/// Incrementally builds a Stencils table row by row (rows appended in order).
class StencilsBuilder {
  public:
    /// Capacity for `rows` rows and `entries` weights: a table built without it grows by
    /// doubling, copying (and faulting in) its arrays about once more.
    void reserve(size_t rows, size_t entries) {
        _table.offsets.reserve(rows + 1);
        _table.indices.reserve(entries);
        _table.weights.reserve(entries);
    }
    void beginRow() { _open = true; }
    void add(int index, float weight);
    void endRow();  ///< merges duplicate indices, drops exact zeros
    Stencils finish();
    /// The rows ended so far (for reading back finished rows while building).
    const Stencils& partial() const { return _table; }

  private:
    Stencils _table;
    bool _open = false;
};

/// Applies a chain of tables (table k maps the output of table k-1): src has
/// chain.front().sourceCount() elements, dst receives chain.back().rows(). An empty chain
/// copies `count` elements. Intermediate levels live in per-thread scratch buffers.
void applyChain(const std::vector<Stencils>& chain, const float* src, size_t count, int components,
                float* dst);

/// Rows of the last table of a chain (`count` for an empty chain).
inline size_t chainRows(const std::vector<Stencils>& chain, size_t count) {
    return chain.empty() ? count : chain.back().rows();
}

}  // namespace principled::subdiv
