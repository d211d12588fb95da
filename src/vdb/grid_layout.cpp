#include "vdb/grid_layout.h"

#include "vdb/tree_order.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>

namespace yv {
namespace {

/// Leaf records are indexed for the output's chunks in pieces of about this size.
constexpr std::uint64_t kRecordPieceBytes = 4ull << 20;

template <openvdb::Index Log2Dim> std::uint8_t* putMask(std::uint8_t* out, const openvdb::util::NodeMask<Log2Dim>& mask) {
    for (openvdb::Index w = 0; w < openvdb::util::NodeMask<Log2Dim>::WORD_COUNT; ++w) {
        const std::uint64_t word = mask.template getWord<std::uint64_t>(w);
        std::memcpy(out, &word, sizeof word);
        out += sizeof word;
    }
    return out;
}

std::uint8_t* putBytes(std::uint8_t* out, const void* p, std::size_t n) {
    std::memcpy(out, p, n);
    return out + n;
}

} // namespace

TopologyBytes topologyBytes(const std::vector<LeafRecord>& leaves, const GridEncoding& encoding) {
    const ByteVector upperValues = internalNodeValues(encoding, 5);
    const ByteVector lowerValues = internalNodeValues(encoding, 4);
    constexpr std::size_t kUpperMaskBytes = openvdb::util::NodeMask<5>::WORD_COUNT * 8;
    constexpr std::size_t kLowerMaskBytes = openvdb::util::NodeMask<4>::WORD_COUNT * 8;
    // [begin, end) of the leaves under each root child and each 16^3 node, and where its bytes start.
    struct Node {
        std::size_t begin, end;
        std::uint64_t at;
    };
    std::vector<Node> upper, lower;
    std::uint64_t at = 0;
    for (std::size_t i = 0; i < leaves.size();) {
        const std::uint64_t root = rootChildOfOrder(leaves[i].order);
        Node u{i, i, at};
        at += 12 + 2 * kUpperMaskBytes + upperValues.size();
        while (u.end < leaves.size() && rootChildOfOrder(leaves[u.end].order) == root) {
            const std::uint64_t node = lowerNodeOfOrder(leaves[u.end].order);
            Node l{u.end, u.end, at};
            while (l.end < leaves.size() && lowerNodeOfOrder(leaves[l.end].order) == node) ++l.end;
            at += 2 * kLowerMaskBytes + lowerValues.size() + (l.end - l.begin) * sizeof(LeafRecord::mask);
            lower.push_back(l);
            u.end = l.end;
        }
        upper.push_back(u);
        i = u.end;
    }
    const ByteVector header = treeTopologyHeader(encoding, std::uint32_t(upper.size()));
    TopologyBytes out(header.size() + at);
    std::memcpy(out.data(), header.data(), header.size());
    std::uint8_t* const body = out.data() + header.size();
    tbb::parallel_for(std::size_t(0), upper.size(), [&](std::size_t n) {
        const Node& u = upper[n];
        openvdb::util::NodeMask<5> upperChildren;
        for (std::size_t i = u.begin; i < u.end; ++i) upperChildren.setOn(upperIndexOfOrder(leaves[i].order));
        const glm::ivec3 b = treeOrderCoord(leaves[u.begin].order);
        const std::int32_t origin[3] = {(b.x >> 9) << 12, (b.y >> 9) << 12, (b.z >> 9) << 12};
        std::uint8_t* p = putBytes(body + u.at, origin, sizeof origin);
        p = putMask(p, upperChildren);
        p = putMask(p, openvdb::util::NodeMask<5>());
        putBytes(p, upperValues.data(), upperValues.size());
    });
    tbb::parallel_for(std::size_t(0), lower.size(), [&](std::size_t n) {
        const Node& l = lower[n];
        openvdb::util::NodeMask<4> lowerChildren;
        for (std::size_t k = l.begin; k < l.end; ++k) lowerChildren.setOn(lowerIndexOfOrder(leaves[k].order));
        std::uint8_t* p = putMask(body + l.at, lowerChildren);
        p = putMask(p, openvdb::util::NodeMask<4>());
        p = putBytes(p, lowerValues.data(), lowerValues.size());
        for (std::size_t k = l.begin; k < l.end; ++k) p = putBytes(p, leaves[k].mask.data(), sizeof leaves[k].mask);
    });
    return out;
}

void addRecordPieces(const std::vector<LeafRecord>& leaves, int grid, std::uint64_t at, std::vector<RecordPiece>& out,
                     std::size_t begin) {
    for (std::size_t i = begin; i < leaves.size();) {
        RecordPiece p{&leaves, grid, i, i, at, 0};
        while (p.end < leaves.size() && (p.bytes == 0 || p.bytes + leaves[p.end].bytes[grid] <= kRecordPieceBytes))
            p.bytes += leaves[p.end++].bytes[grid];
        at += p.bytes;
        i = p.end;
        out.push_back(p);
    }
}

void fillFromRecords(const std::vector<RecordPiece>& pieces, const SpillFile& spill, std::uint64_t at,
                     std::span<std::uint8_t> out) {
    const std::uint64_t end = at + out.size();
    auto piece = std::partition_point(pieces.begin(), pieces.end(),
                                      [&](const RecordPiece& p) { return p.at + p.bytes <= at; });
    for (; piece != pieces.end() && piece->at < end; ++piece) {
        const std::vector<LeafRecord>& leaves = *piece->leaves;
        const int g = piece->grid;
        std::uint64_t fileAt = piece->at;
        for (std::size_t i = piece->begin; i < piece->end && fileAt < end;) {
            // A run: records contiguous in the scratch file as in the output.
            const std::uint64_t from = leaves[i].at[g];
            std::uint64_t run = leaves[i].bytes[g];
            std::size_t j = i + 1;
            for (; j < piece->end && leaves[j].at[g] == from + run; ++j) run += leaves[j].bytes[g];
            const std::uint64_t lo = std::max(fileAt, at), hi = std::min(fileAt + run, end);
            if (lo < hi) spill.read(from + (lo - fileAt), out.subspan(lo - at, hi - lo));
            fileAt += run;
            i = j;
        }
    }
}

} // namespace yv
