#pragma once
/// \file MeshModel<BV, M>: a triangle mesh of scalar M (shared, never copied by queries) with its BVH.

#include "cdkit/bvh/build.hpp"
#include "cdkit/bvh/refit.hpp"

#include <memory>
#include <string>
#include <type_traits>

namespace cdkit {

/// M is the mesh's scalar, by default the BV's. Float BVs over a double mesh (MeshModel<Obb<float>, double>)
/// halve the tree's bytes; queries then run in double on the triangles and in float on the BVs, which are
/// rounded outward so that culling stays conservative (bv/narrow_outward.hpp).
template <class BV, class M = typename BV::Scalar> class MeshModel {
    static_assert(detail::bv_fits_mesh_v<BV, M>, "a BV is stored in the mesh's scalar type, or in float over a double mesh");

public:
    using Scalar = M;  ///< the mesh's scalar: poses and results use it
    using BoundingVolume = BV;

    /// Validates the mesh (throws cdkit::Error naming mesh->source on bad data) and builds the tree.
    explicit MeshModel(std::shared_ptr<const TriangleMesh<Scalar>> mesh, const BuildOptions& options = {})
        : mesh_(checked(std::move(mesh))), bvh_(build_bvh<BV>(*mesh_, options)), options_(options),
          built_ratio_(surface_ratio(bvh_, *mesh_)) {}
    explicit MeshModel(TriangleMesh<Scalar> mesh, const BuildOptions& options = {})
        : MeshModel(std::make_shared<const TriangleMesh<Scalar>>(std::move(mesh)), options) {}

    [[nodiscard]] const TriangleMesh<Scalar>& mesh() const noexcept { return *mesh_; }
    [[nodiscard]] const std::shared_ptr<const TriangleMesh<Scalar>>& mesh_ptr() const noexcept { return mesh_; }
    [[nodiscard]] const Bvh<BV>& bvh() const noexcept { return bvh_; }
    /// Bytes of the tree alone (the mesh is the caller's and shared).
    [[nodiscard]] std::size_t memory_bytes() const noexcept { return bvh_.memory_bytes(); }
    /// Checks the tree against the mesh; throws cdkit::Error on a broken invariant.
    void validate() const { bvh_.validate(*mesh_); }

    /// Deformation: takes `moved`, the same mesh with moved vertices (same vertex count, same triangles in
    /// the same order), and refits the tree to it in O(n) (see bvh/refit.hpp for how loose each BV gets).
    /// Throws cdkit::Error naming moved->source when the topology differs or a vertex is not finite; the
    /// model is unchanged then. Not thread-safe against concurrent queries on this model.
    void refit(std::shared_ptr<const TriangleMesh<Scalar>> moved) {
        if (!moved) throw Error("<mesh>", "", "refit: null mesh");
        check_bv_range(*moved);
        if (moved->vertices.size() != mesh_->vertices.size())
            throw Error(moved->source, "", "refit: vertex count " + std::to_string(moved->vertices.size()) +
                                               " differs from the model's " + std::to_string(mesh_->vertices.size()));
        if (moved->triangles.size() != mesh_->triangles.size())
            throw Error(moved->source, "", "refit: triangle count differs from the model's");
        for (std::size_t i = 0; i < moved->triangles.size(); ++i)
            if (moved->triangles[i] != mesh_->triangles[i])
                throw Error(moved->source, "triangle " + std::to_string(i), "refit: differs from the model's (topology changed)");
        cdkit::refit(bvh_, *moved);  // validates the coordinates before touching the tree
        mesh_ = std::move(moved);
    }
    /// Rebuilds the tree from scratch on the current mesh (with the options it was built with).
    void rebuild() {
        bvh_ = build_bvh<BV>(*mesh_, options_);
        built_ratio_ = surface_ratio(bvh_, *mesh_);
    }
    /// How much refits have loosened the tree: surface_ratio() now over surface_ratio() after the last build
    /// (1 right after a build; scale invariant). O(n) plus one fit of the whole mesh.
    [[nodiscard]] double degradation() const {
        return built_ratio_ > 0 ? surface_ratio(bvh_, *mesh_) / built_ratio_ : 1.0;
    }
    /// True when degradation() exceeds `threshold`: the refitted tree's volumes then overlap so much more than
    /// a fresh tree's that a rebuild (O(n log n)) is likely to pay off within a few queries.
    [[nodiscard]] bool should_rebuild(double threshold = 1.5) const { return degradation() > threshold; }

private:
    static std::shared_ptr<const TriangleMesh<Scalar>> checked(std::shared_ptr<const TriangleMesh<Scalar>> m) {
        if (!m) throw Error("<mesh>", "", "null mesh");
        cdkit::validate(*m);
        check_bv_range(*m);
        return m;
    }
    /// Float BVs over a double mesh: every coordinate must stay far enough inside float's range that the
    /// BV tests' squares do not overflow (|x|² < 2^128).
    static void check_bv_range(const TriangleMesh<Scalar>& m) {
        if constexpr (!std::is_same_v<typename BV::Scalar, Scalar>) {
            constexpr double limit = 0x1p60;
            for (std::size_t i = 0; i < m.vertices.size(); ++i)
                if (!(m.vertices[i].cwiseAbs().maxCoeff() <= limit))
                    throw Error(m.source, "vertex " + std::to_string(i),
                                "coordinate beyond 2^60: too large for the float bounding volumes of this model");
        }
    }
    std::shared_ptr<const TriangleMesh<Scalar>> mesh_;
    Bvh<BV> bvh_;
    BuildOptions options_;
    double built_ratio_ = 1;
};

}  // namespace cdkit
