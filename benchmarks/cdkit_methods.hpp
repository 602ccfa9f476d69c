#pragma once
/// \file The cdkit methods: one MeshModel<BV> per bounding-volume type in `CdkitBvs`, then the restricted
/// boxtrees (`RestrictedBoxtree<double>`, `<float>`), which are not a BV in a Bvh but a tree of their own.
/// Adding a BV type to the benchmark is one entry in that list.

#include "bench.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/rss.hpp"
#include "cdkit/bv/sphere.hpp"
#include "cdkit/bvh/boxtree.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/bvh/mixed_descent.hpp"
#include "cdkit/query.hpp"

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <functional>
#include <tuple>
#include <type_traits>

namespace cdbench {

/// Every cdkit BV type measured, in output order. The first is the reference for correctness counts and
/// the model that P2's bisection uses.
/// Kdop<6> (culls less than Aabb's 15-axis test) and the float DOPs are left out of the default list to keep
/// the main job short; add them here to measure them.
using CdkitBvs = std::tuple<cdkit::Obb<double>, cdkit::Aabb<double>, cdkit::Rss<double>, cdkit::Obb<float>, cdkit::Aabb<float>,
                            cdkit::Kdop<double, 14>, cdkit::Kdop<double, 18>, cdkit::Kdop<double, 26>,
                            cdkit::BoundingSphere<double>, cdkit::BoundingSphere<float>>;
/// Float BVs over the double mesh (MeshModel<BV, double>): half the node bytes, the double mesh's answers.
using CdkitFloatOverDoubleBvs = std::tuple<cdkit::Obb<float>, cdkit::Aabb<float>>;

/// "cdkit_obb_d" for Obb<double>: the BV's own name, lower case, and the scalar's initial; "_fd" for float
/// BVs over a double mesh.
template <class BV, class M = typename BV::Scalar> [[nodiscard]] std::string cdkit_method_name() {
    std::string n = "cdkit_";
    for (const char* c = BV::name; *c; ++c) n += char(std::tolower(static_cast<unsigned char>(*c)));
    if constexpr (!std::is_same_v<typename BV::Scalar, M>) n += "_fd";
    else n += std::is_same_v<typename BV::Scalar, float> ? "_f" : "_d";
    return n;
}

/// Two models over one mesh with trees of different volumes: collide(a, b) on mixed trees (bvh/mixed_descent.hpp),
/// A's tree for the first copy, B's for the second.
template <class BVA, class BVB> struct MixedModels {
    cdkit::MeshModel<BVA> a;
    cdkit::MeshModel<BVB> b;
    [[nodiscard]] const auto& mesh() const noexcept { return a.mesh(); }
    [[nodiscard]] std::size_t memory_bytes() const noexcept { return a.memory_bytes() + b.memory_bytes(); }
    [[nodiscard]] std::size_t node_count() const noexcept { return a.bvh().nodes().size() + b.bvh().nodes().size(); }
};
/// The model of the first and of the second copy: one model for both, or a mixed pair's two.
template <class Model> [[nodiscard]] const Model& first_copy(const Model& m) noexcept { return m; }
template <class Model> [[nodiscard]] const Model& second_copy(const Model& m) noexcept { return m; }
template <class A, class B> [[nodiscard]] const auto& first_copy(const MixedModels<A, B>& m) noexcept { return m.a; }
template <class A, class B> [[nodiscard]] const auto& second_copy(const MixedModels<A, B>& m) noexcept { return m.b; }

/// A cdkit model timed through cdkit::collide (a MeshModel, a RestrictedBoxtree or MixedModels); S is its mesh's
/// scalar. `build` constructs the model and fills the BuildInfo; it is timed here.
template <class Model, class S> class CollideMethod final : public Method {
public:
    template <class Build>
    CollideMethod(std::string name, Build&& build, const char* bytes_note)
        : name_(std::move(name)), model_(timed(std::forward<Build>(build), bytes_note)) {}

    const std::string& name() const noexcept override { return name_; }
    const std::string& family() const noexcept override { return family_; }
    const BuildInfo& build_info() const noexcept override { return info_; }

    Outcome probe(const Pose& pose, Mode mode) override {
        const auto r = cdkit::collide(first_copy(model_), cdkit::Transform<S>::identity(), second_copy(model_), cast(pose),
                                      request(mode));
        return {r.colliding, r.contacts.size(), r.stats.bv_tests, r.stats.primitive_tests};
    }

    Timed time(const Pose& pose, Mode mode, std::size_t reps) override {
        // The pose is converted before the clock starts: a float user holds float poses.
        const cdkit::Transform<S> pa = cdkit::Transform<S>::identity();
        const cdkit::Transform<S> pb = cast(pose);
        const cdkit::CollisionRequest req = request(mode);
        return time_batch(reps, [&] {
            const auto r = cdkit::collide(first_copy(model_), pa, second_copy(model_), pb, req);
            return std::pair<bool, std::size_t>(r.colliding, r.contacts.size());
        });
    }

private:
    static cdkit::CollisionRequest request(Mode mode) noexcept {
        cdkit::CollisionRequest r;
        r.mode = mode == Mode::first ? cdkit::ContactMode::first : cdkit::ContactMode::all;
        return r;
    }
    static cdkit::Transform<S> cast(const Pose& p) { return cdkit::Transform<double>(p.R, p.t).template cast<S>(); }

    template <class Build> Model timed(Build&& build, const char* bytes_note) {
        const auto t0 = Clock::now();
        Model m = build();
        info_.build_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        info_.tree_bytes = m.memory_bytes();
        info_.tree_bytes_note = bytes_note;
        info_.mesh_bytes = m.mesh().memory_bytes();
        if constexpr (requires { m.node_count(); }) info_.nodes = m.node_count();
        else if constexpr (requires { m.bvh(); }) info_.nodes = m.bvh().nodes().size();
        else info_.nodes = m.nodes().size();
        info_.single_precision = std::is_same_v<S, float>;
        return m;
    }

    std::string name_;
    std::string family_ = "cdkit";
    BuildInfo info_;  // filled by timed(), which runs in model_'s initialiser: declared before model_
    Model model_;
};

/// A MeshModel<BV, M> with the run's build options.
template <class BV, class M = typename BV::Scalar>
[[nodiscard]] std::unique_ptr<Method> make_mesh_model_method(std::shared_ptr<const cdkit::TriangleMesh<M>> mesh,
                                                             const cdkit::BuildOptions& options) {
    return std::make_unique<CollideMethod<cdkit::MeshModel<BV, M>, M>>(
        cdkit_method_name<BV, M>(), [&] { return cdkit::MeshModel<BV, M>(mesh, options); }, "MeshModel::memory_bytes()");
}

/// The restricted boxtree of one scalar type (default build options: implied-box SAH split, one-child
/// nodes where a face cuts off ≥ 25 % of a box's area).
template <class S> [[nodiscard]] std::string boxtree_method_name() {
    return std::is_same_v<S, float> ? "cdkit_boxtree_f" : "cdkit_boxtree_d";
}
template <class S>
[[nodiscard]] std::unique_ptr<Method> make_boxtree_method(std::shared_ptr<const cdkit::TriangleMesh<S>> mesh) {
    return std::make_unique<CollideMethod<cdkit::RestrictedBoxtree<S>, S>>(
        boxtree_method_name<S>(), [&] { return cdkit::RestrictedBoxtree<S>(mesh); }, "RestrictedBoxtree::memory_bytes()");
}

/// Mixed trees: an Obb tree against an Rss tree (a moving part's tree for collide() against an environment's built
/// for distance()); FCL has no mixed pair to compare.
inline const std::string mixed_method_name = "cdkit_obb_x_rss";
[[nodiscard]] inline std::unique_ptr<Method> make_mixed_method(std::shared_ptr<const cdkit::TriangleMesh<double>> mesh,
                                                               const cdkit::BuildOptions& options) {
    using Pair = MixedModels<cdkit::Obb<double>, cdkit::Rss<double>>;
    return std::make_unique<CollideMethod<Pair, double>>(
        mixed_method_name,
        [&] {
            return Pair{cdkit::MeshModel<cdkit::Obb<double>>(mesh, options),
                        cdkit::MeshModel<cdkit::Rss<double>>(mesh, options)};
        },
        "MeshModel::memory_bytes() of both trees");
}

/// Names of all cdkit methods, in CdkitBvs order, then the float-over-double models, the mixed pair, the boxtrees.
[[nodiscard]] inline std::vector<std::string> cdkit_method_names() {
    auto names = std::apply([](auto... bv) { return std::vector<std::string>{cdkit_method_name<decltype(bv)>()...}; },
                            CdkitBvs{});
    std::apply([&](auto... bv) { (names.push_back(cdkit_method_name<decltype(bv), double>()), ...); },
               CdkitFloatOverDoubleBvs{});
    names.push_back(mixed_method_name);
    names.push_back(boxtree_method_name<double>());
    names.push_back(boxtree_method_name<float>());
    return names;
}

/// Builds the cdkit methods for which `wanted(name)` is true, on the (already normalised) double mesh;
/// float methods get a float copy, shared among them.
[[nodiscard]] inline std::vector<std::unique_ptr<Method>> make_cdkit_methods(
    const cdkit::TriangleMesh<double>& mesh, const cdkit::BuildOptions& options,
    const std::function<bool(const std::string&)>& wanted) {
    auto md = std::make_shared<const cdkit::TriangleMesh<double>>(mesh);
    auto mf = std::make_shared<const cdkit::TriangleMesh<float>>(mesh.cast<float>());
    std::vector<std::unique_ptr<Method>> out;
    auto add = [&]<class BV>(BV*) {
        if (!wanted(cdkit_method_name<BV>())) return;
        if constexpr (std::is_same_v<typename BV::Scalar, float>) out.push_back(make_mesh_model_method<BV>(mf, options));
        else out.push_back(make_mesh_model_method<BV>(md, options));
    };
    std::apply([&](auto... bv) { (add(static_cast<decltype(bv)*>(nullptr)), ...); }, CdkitBvs{});
    auto add_over_double = [&]<class BV>(BV*) {
        if (wanted(cdkit_method_name<BV, double>())) out.push_back(make_mesh_model_method<BV, double>(md, options));
    };
    std::apply([&](auto... bv) { (add_over_double(static_cast<decltype(bv)*>(nullptr)), ...); }, CdkitFloatOverDoubleBvs{});
    if (wanted(mixed_method_name)) out.push_back(make_mixed_method(md, options));
    if (wanted(boxtree_method_name<double>())) out.push_back(make_boxtree_method(md));
    if (wanted(boxtree_method_name<float>())) out.push_back(make_boxtree_method(mf));
    return out;
}

}  // namespace cdbench
