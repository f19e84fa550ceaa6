// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/osdStencils.h"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include <memory>
#include <stdexcept>

namespace principled::subdiv {

namespace {

/// A symbolic primvar value: "1 x element i". Limit() combines these into masks.
struct Symbol {
    int index;
};

/// Source buffer whose element i is the symbol i.
struct SymbolicSource {
    Symbol operator[](int i) const { return {i}; }
};

/// Destination buffer for PrimvarRefiner that records each row as a stencil. PrimvarRefiner
/// writes a row as Clear() followed by AddWithWeight() calls, one row at a time, so rows stream
/// into a StencilsBuilder; rows written out of order are permuted at the end. Interpolate()
/// also adds finished destination rows into later ones (face points into edge and vertex
/// points); those are expanded from the rows already recorded.
class RowRecorder {
  public:
    struct Row {
        RowRecorder* owner;
        int row;
        void Clear() { owner->clear(row); }
        void AddWithWeight(const Symbol& s, float w) { owner->add(row, s.index, w); }
        void AddWithWeight(const Row& finished, float w) { owner->addRow(row, finished.row, w); }
    };
    Row operator[](int i) { return {this, i}; }

    /// weightsPerRow: expected weights per row (after merging), to reserve the table once.
    RowRecorder(size_t rowCount, size_t weightsPerRow) : _rowCount(rowCount), _slot(rowCount, -1) {
        _order.reserve(rowCount);
        _builder.reserve(rowCount, rowCount * weightsPerRow);
    }

    Stencils finish() {
        Stencils built = _builder.finish();
        if (_broken) throw std::runtime_error("stencil rows were interleaved or written twice");
        bool inOrder = _order.size() == _rowCount;
        for (size_t k = 0; inOrder && k < _order.size(); ++k) inOrder = _order[k] == int(k);
        if (inOrder) return built;
        // Permute (rows never written stay empty, i.e. evaluate to zero).
        StencilsBuilder b;
        b.reserve(_rowCount, built.entries());
        for (size_t r = 0; r < _rowCount; ++r) {
            b.beginRow();
            if (_slot[r] >= 0) {
                for (int k = built.offsets[_slot[r]]; k < built.offsets[_slot[r] + 1]; ++k)
                    b.add(built.indices[k], built.weights[k]);
            }
            b.endRow();
        }
        return b.finish();
    }

  private:
    void clear(int row) {
        if (row < 0 || size_t(row) >= _rowCount || _slot[size_t(row)] >= 0) {
            _broken = true;
            return;
        }
        if (_current >= 0) _builder.endRow();
        _builder.beginRow();
        _current = row;
        _slot[size_t(row)] = int(_order.size());
        _order.push_back(row);
    }
    void add(int row, int index, float w) {
        if (row != _current) {
            _broken = true;
            return;
        }
        _builder.add(index, w);
    }
    void addRow(int row, int finished, float w) {
        if (row != _current || finished == _current || finished < 0 ||
            size_t(finished) >= _rowCount || _slot[size_t(finished)] < 0) {
            _broken = true;
            return;
        }
        // Copy first: adding may reallocate the arrays being read.
        const Stencils& done = _builder.partial();
        const int slot = _slot[size_t(finished)];
        _scratch.assign(done.offsets[slot + 1] - done.offsets[slot], {});
        for (int k = done.offsets[slot], i = 0; k < done.offsets[slot + 1]; ++k, ++i)
            _scratch[size_t(i)] = {done.indices[k], done.weights[k] * w};
        for (const auto& [index, weight] : _scratch) _builder.add(index, weight);
    }

    size_t _rowCount;
    StencilsBuilder _builder;
    std::vector<int> _order;  ///< rows in recording order
    std::vector<int> _slot;   ///< recording position of each row, -1 before its Clear()
    std::vector<std::pair<int, float>> _scratch;
    int _current = -1;
    bool _broken = false;
};

// The float wrappers Far::StencilTableFactory / Far::StencilTable static_cast a
// StencilTableReal<float> to the derived StencilTable (UBSan: bad downcast), so the Real
// templates are used directly.
using FactoryReal = Far::StencilTableFactoryReal<float>;
using TableReal = Far::StencilTableReal<float>;

Stencils fromFar(const TableReal& table) {
    Stencils s;
    const int n = table.GetNumStencils();
    const auto& sizes = table.GetSizes();
    const auto& indices = table.GetControlIndices();
    const auto& weights = table.GetWeights();
    s.offsets.resize(static_cast<size_t>(n) + 1);
    s.offsets[0] = 0;
    for (int i = 0; i < n; ++i) s.offsets[i + 1] = s.offsets[i] + sizes[i];
    s.indices.assign(indices.begin(), indices.end());
    s.weights.assign(weights.begin(), weights.end());
    return s;
}

}  // namespace

Stencils refinementStencils(const Far::TopologyRefiner& refiner, Interpolation mode, int channel) {
    FactoryReal::Options o;
    o.interpolationMode = mode == Interpolation::Vertex    ? FactoryReal::INTERPOLATE_VERTEX
                          : mode == Interpolation::Varying ? FactoryReal::INTERPOLATE_VARYING
                                                           : FactoryReal::INTERPOLATE_FACE_VARYING;
    o.fvarChannel = static_cast<unsigned>(channel);
    o.generateOffsets = false;
    o.generateControlVerts = false;
    o.generateIntermediateLevels = false;  // last level only
    o.factorizeIntermediateLevels = true;  // each level's stencils built from the previous ones
    o.maxLevel = static_cast<unsigned>(refiner.GetMaxLevel());
    std::unique_ptr<const TableReal> table(FactoryReal::Create(refiner, o));
    return table ? fromFar(*table) : Stencils();
}

std::vector<Stencils> levelStencils(const Far::TopologyRefiner& refiner, Interpolation mode,
                                    int channel) {
    const Far::PrimvarRefiner primvars(refiner);
    const SymbolicSource src;
    std::vector<Stencils> chain;
    for (int level = 1; level <= refiner.GetMaxLevel(); ++level) {
        const Far::TopologyLevel& child = refiner.GetLevel(level);
        const size_t rows = mode == Interpolation::FaceVarying
                                ? size_t(child.GetNumFVarValues(channel))
                                : size_t(child.GetNumVertices());
        // Catmull-Clark face, edge and vertex points of quads take 4, 6 and 9 weights, a
        // quarter, half and quarter of the rows; varying ones at most 4.
        RowRecorder dst(rows, mode == Interpolation::Varying ? 4 : 7);
        switch (mode) {
            case Interpolation::Vertex:
                primvars.Interpolate(level, src, dst);
                break;
            case Interpolation::Varying:
                primvars.InterpolateVarying(level, src, dst);
                break;
            case Interpolation::FaceVarying:
                primvars.InterpolateFaceVarying(level, src, dst, channel);
                break;
        }
        chain.push_back(dst.finish());
    }
    return chain;
}

LimitMasks vertexLimitMasks(const Far::TopologyRefiner& refiner) {
    const Far::PrimvarRefiner primvars(refiner);
    const SymbolicSource src;
    const size_t n = static_cast<size_t>(refiner.GetLevel(refiner.GetMaxLevel()).GetNumVertices());
    // One pass records all three masks: each recorder streams its rows, so memory is the
    // final tables only.
    // Regular quad-mesh vertices: 9 position weights, 6 per tangent.
    RowRecorder pos(n, 9), du(n, 6), dv(n, 6);
    primvars.Limit(src, pos, du, dv);
    LimitMasks masks;
    masks.position = pos.finish();
    masks.tangentU = du.finish();
    masks.tangentV = dv.finish();
    return masks;
}

Stencils faceVaryingLimitMasks(const Far::TopologyRefiner& refiner, int channel) {
    const Far::PrimvarRefiner primvars(refiner);
    const size_t n =
        static_cast<size_t>(refiner.GetLevel(refiner.GetMaxLevel()).GetNumFVarValues(channel));
    RowRecorder values(n, 9);
    primvars.LimitFaceVarying(SymbolicSource(), values, channel);
    return values.finish();
}

}  // namespace principled::subdiv
