#pragma once
/// \file InnerSphereTree: a hierarchy of bounding spheres over an object's inner spheres (Weller, Zachmann,
/// "Inner sphere trees for proximity and penetration queries", RSS 2009; "Inner sphere trees and their
/// application to collision detection", Virtual Realities, Springer 2011).
///
/// Build: top down. A node's spheres are split into at most `out_degree` clusters by batch neural gas
/// (Cottrell, Hammer, Hasenfuß, Villmann, "Batch and median neural gas", Neural Networks 19, 2006) with
/// magnification control as in the paper: each sphere's pull on the prototypes is weighted by its volume,
/// so large spheres get clusters of their own and small ones gather. Each inner node's sphere bounds its
/// children's spheres (a Bădoiu–Clarkson iteration from the volume-weighted centroid, radius taken as the
/// exact maximum). Leaves are single inner spheres.
///
/// Storage is one flat node array; the children of a node are contiguous. A built tree is immutable and
/// every query on it is const and thread-safe.
///
/// Cell spheres: each inner sphere also stands for its cell (the part of the mesh nearest to it, whose volume
/// is its cell weight times its own): the ball of that volume about the same centre, radius r·∛w, is its cell
/// sphere. The penetration-volume estimate (`calibrated`, ist_query.hpp) sums the lens volumes of the cell
/// spheres of overlapping inner-sphere pairs. The radii are derived from the spheres and weights (not stored).

#include "cdkit/ist/sphere_packing.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace cdkit {

/// One node. Inner node: `count` (≥ 1) children at nodes[first .. first + count). Leaf (`count == 0`):
/// the inner sphere spheres()[first], whose centre and radius the node repeats.
struct IstNode {
    Vec3<double> center = Vec3<double>::Zero();
    double radius = 0;
    double volume = 0;          ///< Σ volumes of the inner spheres below (an upper bound of any overlap with them)
    std::uint32_t first = 0;
    std::uint32_t count = 0;
    [[nodiscard]] bool is_leaf() const noexcept { return count == 0; }
};
static_assert(sizeof(IstNode) == 48, "IstNode: 3+1+1 doubles and two 32-bit links");

/// Parameters of the hierarchy build.
struct IstBuildOptions {
    int out_degree = 8;     ///< children per inner node, in [2, 16]; 8 answers faster than 4 (docs/ist.md)
    int iterations = 12;    ///< batch neural gas iterations per split
    std::uint64_t seed = 1; ///< initial prototypes
};

/// Statistics of a built tree.
struct IstStats {
    std::size_t spheres = 0;
    std::size_t nodes = 0;
    std::size_t depth = 0;          ///< levels (a single leaf: 1)
    std::size_t memory_bytes = 0;   ///< nodes + spheres + weights + cell radii
    double seconds_build = 0;       ///< hierarchy build alone
};

class InnerSphereTree {
public:
    InnerSphereTree() = default;
    /// Builds the hierarchy over a packing (which must hold at least one sphere; throws cdkit::Error
    /// otherwise, or for options out of range).
    explicit InnerSphereTree(SpherePacking packing, const IstBuildOptions& options = {});

    /// Assembles a tree from stored parts (deserialisation) and validate()s it; throws cdkit::Error naming
    /// `source` on any inconsistency.
    [[nodiscard]] static InnerSphereTree from_parts(std::vector<InnerSphere> spheres, std::vector<double> cell_weights,
                                                    std::vector<IstNode> nodes, double mesh_volume, int out_degree,
                                                    const std::string& source);

    [[nodiscard]] const std::vector<InnerSphere>& spheres() const noexcept { return spheres_; }
    [[nodiscard]] const std::vector<double>& cell_weights() const noexcept { return weights_; }
    [[nodiscard]] const std::vector<IstNode>& nodes() const noexcept { return nodes_; }
    /// Per sphere: the radius r·∛w of its cell sphere (see the file comment); ≥ its radius.
    [[nodiscard]] const std::vector<double>& cell_radii() const noexcept { return cell_radii_; }
    [[nodiscard]] bool empty() const noexcept { return nodes_.empty(); }
    [[nodiscard]] double mesh_volume() const noexcept { return mesh_volume_; }
    [[nodiscard]] double sphere_volume() const noexcept { return nodes_.empty() ? 0 : nodes_[0].volume; }
    /// Σ sphere volumes / mesh volume.
    [[nodiscard]] double coverage() const noexcept { return mesh_volume_ > 0 ? sphere_volume() / mesh_volume_ : 0; }
    [[nodiscard]] int out_degree() const noexcept { return out_degree_; }
    [[nodiscard]] IstStats stats() const noexcept { return stats_; }

    /// Checks the invariants and throws cdkit::Error (naming `source`) on the first broken one: finite
    /// values, child ranges in bounds and after their parent, every sphere in exactly one leaf, each node's
    /// sphere containing its children's (relative tolerance 1e-9), node volumes equal to their sums.
    void validate(const std::string& source = "<inner sphere tree>") const;

private:
    void derive_cell_spheres();  // fills cell_radii_ and stats_.memory_bytes
    std::vector<InnerSphere> spheres_;
    std::vector<double> weights_;
    std::vector<IstNode> nodes_;
    std::vector<double> cell_radii_;  // derived from spheres_ and weights_ (derive_cell_spheres)
    double mesh_volume_ = 0;
    int out_degree_ = 8;
    IstStats stats_;
};

/// Packs `mesh` and builds the tree over the packing: pack_spheres() then InnerSphereTree(). Throws like both.
[[nodiscard]] InnerSphereTree build_inner_sphere_tree(const TriangleMesh<double>& mesh,
                                                      const PackingOptions& packing = {},
                                                      const IstBuildOptions& options = {});

}  // namespace cdkit
