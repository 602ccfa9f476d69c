#pragma once
/// \file The restricted boxtree's node format (8 bytes: one float plane and a packed word) and build
/// parameters, with the outward rounding of planes to float and the implied box of a node. The tree is
/// bvh/boxtree.hpp; its builder bvh/detail/boxtree_builder.hpp.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace cdkit {

/// One node of a restricted boxtree: 8 bytes. Its box is its parent's box with the face (axis, side) moved
/// to `plane` (for the root, and for `axis() == no_axis`, the parent's box unchanged).
struct BoxtreeNode {
    enum class Kind : std::uint32_t {
        leaf = 0,          ///< index() is a triangle of the mesh
        one_child = 1,     ///< a further restriction of the same triangles: the child is at index()
        two_children = 2,  ///< children at index() and index() + 1
    };
    static constexpr std::uint32_t no_axis = 3;
    static constexpr std::uint32_t index_bits = 27;
    static constexpr std::uint32_t max_index = (std::uint32_t(1) << index_bits) - 1;

    float plane = 0;          ///< the moved face's coordinate, in the tree's local frame
    std::uint32_t bits = no_axis;  ///< axis (2 bits) | upper side (1) | kind (2) | index (27)

    [[nodiscard]] std::uint32_t axis() const noexcept { return bits & 3u; }
    /// True: the node's box max along axis() is `plane`; false: its min.
    [[nodiscard]] bool upper() const noexcept { return (bits >> 2) & 1u; }
    [[nodiscard]] Kind kind() const noexcept { return Kind((bits >> 3) & 3u); }
    [[nodiscard]] bool is_leaf() const noexcept { return kind() == Kind::leaf; }
    [[nodiscard]] std::uint32_t index() const noexcept { return bits >> 5; }

    void set_restriction(std::uint32_t axis, bool upper_side, float value) noexcept {
        plane = value;
        bits = (bits & ~7u) | (axis & 3u) | (std::uint32_t(upper_side) << 2);
    }
    void set_link(Kind k, std::uint32_t index) noexcept {
        bits = (bits & 7u) | (std::uint32_t(k) << 3) | (index << 5);
    }
};
static_assert(sizeof(BoxtreeNode) == 8, "a restricted boxtree node is one float and one packed 32-bit word");

/// An axis-aligned box as six floats: lo x, y, z, then hi x, y, z. The implied boxes of a boxtree.
using FloatBox = std::array<float, 6>;

/// How a boxtree build splits a node's triangles.
enum class BoxtreeSplit {
    median,       ///< object median of the centroids along the longest axis of the node's tight box (balanced)
    /// Binned surface area heuristic on the boxes the children will actually have: for 16 centroid bins on
    /// each axis, each side's tight box, the implied box that its one-face restriction (and one-child nodes)
    /// leaves of the parent's box, and cost area(implied L)·n_L + area(implied R)·n_R. Not balanced.
    implied_sah,
};

/// Build parameters. One-child nodes cost 8 bytes each and tighten the boxes where a single face is not
/// enough. The defaults keep the tree under the bytes of a double mesh (the bunny: 0.92×, 22.2 B per
/// triangle); `max_extra_restrictions = 0` gives the plain binary tree, 2n − 1 nodes (16 B per triangle,
/// under a float mesh's bytes too).
struct BoxtreeOptions {
    BoxtreeSplit split = BoxtreeSplit::implied_sah;
    /// At most this many one-child nodes before each node (0: a plain binary tree of 2n − 1 nodes).
    std::uint32_t max_extra_restrictions = 1;
    /// A one-child node is added only when its face cuts off at least this fraction of the box's surface area.
    float min_extra_gain = 0.25f;
};

/// Statistics of a built boxtree.
struct BoxtreeStats {
    std::size_t nodes = 0;
    std::size_t leaves = 0;
    std::size_t one_child_nodes = 0;
    std::size_t depth = 0;         ///< number of levels on the longest root-to-leaf path (one-child nodes count)
    std::size_t memory_bytes = 0;  ///< nodes + root box + centre
};

namespace detail {
/// The float nearest to x on the side that keeps a box conservative (±infinity beyond float's range, which
/// the build then rejects; the range is checked first because an out-of-range conversion is undefined).
[[nodiscard]] inline float boxtree_round_down(double x) noexcept {
    constexpr double top = double(std::numeric_limits<float>::max());
    if (x < -top) return -std::numeric_limits<float>::infinity();
    if (x > top) return std::numeric_limits<float>::max();
    float f = static_cast<float>(x);
    if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}
[[nodiscard]] inline float boxtree_round_up(double x) noexcept {
    constexpr double top = double(std::numeric_limits<float>::max());
    if (x > top) return std::numeric_limits<float>::infinity();
    if (x < -top) return -std::numeric_limits<float>::max();
    float f = static_cast<float>(x);
    if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}
/// The box of `parent` with `node`'s restriction applied.
[[nodiscard]] inline FloatBox restrict_box(FloatBox box, const BoxtreeNode& node) noexcept {
    const std::uint32_t k = node.axis();
    if (k != BoxtreeNode::no_axis) box[node.upper() ? k + 3 : k] = node.plane;
    return box;
}
}  // namespace detail

}  // namespace cdkit
