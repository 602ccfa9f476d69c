#pragma once
/// \file MeshModel<BV>: a triangle mesh (shared, never copied by queries) with its BVH.

#include "cdkit/bvh/build.hpp"

#include <memory>

namespace cdkit {

template <class BV> class MeshModel {
public:
    using Scalar = typename BV::Scalar;
    using BoundingVolume = BV;

    /// Validates the mesh (throws cdkit::Error naming mesh->source on bad data) and builds the tree.
    explicit MeshModel(std::shared_ptr<const TriangleMesh<Scalar>> mesh, const BuildOptions& options = {})
        : mesh_(checked(std::move(mesh))), bvh_(build_bvh<BV>(*mesh_, options)) {}
    explicit MeshModel(TriangleMesh<Scalar> mesh, const BuildOptions& options = {})
        : MeshModel(std::make_shared<const TriangleMesh<Scalar>>(std::move(mesh)), options) {}

    [[nodiscard]] const TriangleMesh<Scalar>& mesh() const noexcept { return *mesh_; }
    [[nodiscard]] const std::shared_ptr<const TriangleMesh<Scalar>>& mesh_ptr() const noexcept { return mesh_; }
    [[nodiscard]] const Bvh<BV>& bvh() const noexcept { return bvh_; }
    /// Bytes of the tree alone (the mesh is the caller's and shared).
    [[nodiscard]] std::size_t memory_bytes() const noexcept { return bvh_.memory_bytes(); }
    /// Checks the tree against the mesh; throws cdkit::Error on a broken invariant.
    void validate() const { bvh_.validate(*mesh_); }

private:
    static std::shared_ptr<const TriangleMesh<Scalar>> checked(std::shared_ptr<const TriangleMesh<Scalar>> m) {
        if (!m) throw Error("<mesh>", "", "null mesh");
        cdkit::validate(*m);
        return m;
    }
    std::shared_ptr<const TriangleMesh<Scalar>> mesh_;
    Bvh<BV> bvh_;
};

}  // namespace cdkit
