#pragma once
/// \file World: objects with a shape and a pose, and step(), which runs the whole pipeline
///   broad phase (SAP, grid, dynamic AABB tree or brute force) → interest matrix (group / pair filters, a
///   per-pair cache (GJK's warm start, the manifold's ids) that lives while the pair's boxes overlap) → narrow phase (dispatch by
///   shape kinds, world/narrow_phase.hpp) → contacts, sorted by (a, b).
///
/// The narrow phase runs over the candidate pairs in parallel with TBB when `WorldOptions::parallel` is set
/// and the library was built with TBB (CDKIT_HAS_TBB); each pair reads and writes only its own cache and
/// result slot, so the contacts are identical to the sequential run. Without TBB `parallel` is ignored.
///
/// Every pair of shape kinds is supported (sphere, box, capsule, cylinder, cone, ellipsoid, triangle, convex hull,
/// mesh); see
/// world/narrow_phase.hpp for what a mesh contact means. Bad input (a non-rigid or non-finite pose, an
/// unknown id, a group ≥ 64) raises cdkit::Error where it enters; step() does not throw except
/// std::bad_alloc. Thread safety: const members may run concurrently; add / remove / set_pose / step and
/// the filter setters must not run concurrently with anything else on the same World.

#include "cdkit/broadphase/brute_force.hpp"
#include "cdkit/broadphase/dynamic_aabb_tree.hpp"
#include "cdkit/broadphase/interest_matrix.hpp"
#include "cdkit/broadphase/sorted_cell_grid.hpp"
#include "cdkit/broadphase/sweep_and_prune.hpp"
#include "cdkit/broadphase/uniform_grid.hpp"
#include "cdkit/world/narrow_phase.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>
#include <vector>

#if defined(CDKIT_HAS_TBB)
#include <tbb/parallel_for.h>
#endif

namespace cdkit {

/// The broad phase a World uses (docs/broadphase.md: how to choose).
enum class BroadPhaseKind { dynamic_aabb_tree, sweep_and_prune, uniform_grid, brute_force, sorted_cell_grid };

struct WorldOptions {
    BroadPhaseKind broad_phase = BroadPhaseKind::dynamic_aabb_tree;
    /// Run the narrow phase with TBB (when built with it) once there are at least `parallel_min_pairs`.
    bool parallel = false;
    std::size_t parallel_min_pairs = 32;
    /// Convex pairs get contact manifolds (up to four points, manifold/contact_manifold.hpp); off: EPA's single point.
    bool manifolds = true;
    /// Contacts with a mesh get a depth and normal (docs/world.md); off: a witness point only (has_depth false).
    bool mesh_depth = true;
    /// Speculative contacts: pairs apart by at most this much (≥ 0, finite) are reported too, with `colliding`
    /// false and their distance. Broad-phase boxes grow by it.
    double contact_margin = 0;
};

/// Counters of one step, to explain its time.
struct WorldStepStats {
    std::size_t broad_pairs = 0;   ///< pairs whose world boxes overlap
    std::size_t tested_pairs = 0;  ///< of those, pairs the interest matrix lets through (narrow-phase calls)
    std::size_t contacts = 0;
    std::size_t gjk_iterations = 0;  ///< summed over the convex–convex contacts
    bool ran_parallel = false;
};

/// Result of World::step(): contacts sorted by (a, b) (and by child for compounds), and statistics.
template <class S = double> struct WorldStepResult {
    std::vector<WorldContact<S>> contacts;
    WorldStepStats stats;
};

template <class S = double> class World {
public:
    using Scalar = S;

    /// Throws cdkit::Error for a negative or non-finite contact margin.
    explicit World(const WorldOptions& options = {}) : options_(options) {
        if (!(options.contact_margin >= 0) || !std::isfinite(options.contact_margin))
            throw Error("<world>", "WorldOptions::contact_margin", "must be finite and >= 0, got " +
                                                                  std::to_string(options.contact_margin));
        request_.margin = options.contact_margin;
        request_.single_point = !options.manifolds;
        request_.mesh_depth = options.mesh_depth;
        switch (options.broad_phase) {
            case BroadPhaseKind::dynamic_aabb_tree: bp_.template emplace<DynamicAabbTree<S>>(); break;
            case BroadPhaseKind::sweep_and_prune: bp_.template emplace<SweepAndPrune<S>>(); break;
            case BroadPhaseKind::uniform_grid: bp_.template emplace<UniformGrid<S>>(); break;
            case BroadPhaseKind::brute_force: bp_.template emplace<BruteForceBroadPhase<S>>(); break;
            case BroadPhaseKind::sorted_cell_grid: bp_.template emplace<SortedCellGrid<S>>(); break;
        }
        interest_.on_begin = [this](ObjectPair p, PairCache<S>& c) { candidates_.push_back({p, &c}); };
        interest_.on_persist = interest_.on_begin;
    }
    World(const World&) = delete;  // the interest-matrix callbacks point at this World
    World& operator=(const World&) = delete;

    /// Adds an object with `shape` at `pose` (model frame → world); returns its id (stable until removed,
    /// reused afterwards). Throws cdkit::Error for a pose that is not a finite rigid motion.
    ObjectId add(Shape<S> shape, const Transform<S>& pose) {
        check_pose(pose, "add");
        const BroadBox<S> box = padded(shape.world_box(pose));
        const ObjectId id = std::visit([&](auto& bp) { return bp.insert(box); }, bp_);
        if (id >= objects_.size()) objects_.resize(std::size_t(id) + 1);
        objects_[id] = Object{std::move(shape), pose, true, false, pose};
        return id;
    }
    /// Removes an object (ends its interest-matrix pairs and drops its filters). Throws for an unknown id.
    void remove(ObjectId id) {
        check_id(id, "remove");
        std::visit([&](auto& bp) { bp.remove(id); }, bp_);
        interest_.forget(id);
        objects_[id] = Object{};
    }
    /// Moves an object. Throws cdkit::Error for an unknown id or a pose that is not a finite rigid motion.
    void set_pose(ObjectId id, const Transform<S>& pose) {
        check_id(id, "set_pose");
        check_pose(pose, "set_pose");
        objects_[id].pose = pose;
        std::visit([&](auto& bp) { bp.move(id, broad_box(objects_[id])); }, bp_);
    }
    /// Continuous collision for this object (double only): step() then tests its pairs over the whole motion
    /// from its pose at the previous step() (or at add) to its current one, and reports the first contact with
    /// its time `toi` < 1 — so a small fast object cannot pass through a thin one between two steps. Its broad-
    /// phase box covers the motion. Convex pairs use conservative advancement (convex_toi), a convex shape and a
    /// mesh mesh_convex_toi, two meshes mesh_ccd when neither turns and mesh_toi (which follows the arcs) when one
    /// does. Throws for an unknown id.
    void set_ccd(ObjectId id, bool on) {
        static_assert(std::is_same_v<S, double>, "continuous collision runs in double");
        check_id(id, "set_ccd");
        objects_[id].ccd = on;
        std::visit([&](auto& bp) { bp.move(id, broad_box(objects_[id])); }, bp_);
    }
    [[nodiscard]] bool ccd(ObjectId id) const { check_id(id, "ccd"); return objects_[id].ccd; }
    [[nodiscard]] bool contains(ObjectId id) const noexcept { return id < objects_.size() && objects_[id].alive; }
    [[nodiscard]] const Transform<S>& pose(ObjectId id) const { check_id(id, "pose"); return objects_[id].pose; }
    [[nodiscard]] const Shape<S>& shape(ObjectId id) const { check_id(id, "shape"); return *objects_[id].shape; }
    [[nodiscard]] std::size_t size() const noexcept {
        return std::visit([](const auto& bp) { return bp.size(); }, bp_);
    }
    [[nodiscard]] const WorldOptions& options() const noexcept { return options_; }
    /// Switches the TBB narrow phase on or off.
    void set_parallel(bool on) noexcept { options_.parallel = on; }

    /// Interest matrix: object groups (0..63, default 0), which groups are tested, per-pair overrides.
    void set_group(ObjectId id, std::uint8_t group) { check_id(id, "set_group"); interest_.set_group(id, group); }
    void set_groups_tested(std::uint8_t g, std::uint8_t h, bool tested) { interest_.set_groups_tested(g, h, tested); }
    void set_pair_tested(ObjectId a, ObjectId b, bool tested) {
        check_id(a, "set_pair_tested");
        check_id(b, "set_pair_tested");
        interest_.set_pair_tested(a, b, tested);
    }
    [[nodiscard]] bool pair_tested(ObjectId a, ObjectId b) const noexcept { return interest_.tested(a, b); }

    /// One pass of the pipeline at the current poses: the contacts of all tested pairs, sorted by (a, b).
    [[nodiscard]] WorldStepResult<S> step() {
        WorldStepResult<S> out;
        candidates_.clear();
        interest_.begin_frame();
        std::visit([&](auto& bp) {
            bp.for_each_pair([&](ObjectId a, ObjectId b) {
                ++out.stats.broad_pairs;
                interest_.report(a, b);  // tested pairs land in candidates_ through on_begin / on_persist
            });
        }, bp_);
        interest_.finish_frame();  // erases only pairs not reported this frame: the cache pointers stay valid
        out.stats.tested_pairs = candidates_.size();

        results_.resize(candidates_.size());
        auto run = [&](std::size_t i) {
            const ObjectPair p = candidates_[i].pair;
            const Object& a = objects_[p.a];
            const Object& b = objects_[p.b];
            std::vector<WorldContact<S>>& out = results_[i];
            out.clear();
            if constexpr (std::is_same_v<S, double>) {
                if (a.ccd || b.ccd) {
                    if (auto c = continuous_collide_shapes(p.a, *a.shape, a.step_start, a.pose, p.b, *b.shape, b.step_start,
                                                           b.pose, &candidates_[i].cache->manifold.gjk))
                        out.push_back(*c);
                    return;
                }
            }
            collide_shapes_all(p.a, *a.shape, a.pose, p.b, *b.shape, b.pose, candidates_[i].cache, request_, out);
        };
#if defined(CDKIT_HAS_TBB)
        if (options_.parallel && candidates_.size() >= options_.parallel_min_pairs) {
            out.stats.ran_parallel = true;
            tbb::parallel_for(std::size_t(0), candidates_.size(), run);
        } else {
            for (std::size_t i = 0; i < candidates_.size(); ++i) run(i);
        }
#else
        for (std::size_t i = 0; i < candidates_.size(); ++i) run(i);
#endif
        for (std::size_t i = 0; i < candidates_.size(); ++i)
            for (const WorldContact<S>& c : results_[i]) {
                out.stats.gjk_iterations += std::size_t(c.gjk_iterations);
                out.contacts.push_back(c);
            }
        std::sort(out.contacts.begin(), out.contacts.end());
        out.stats.contacts = out.contacts.size();
        // The next step's motions start here; CCD objects' boxes shrink back to their current pose.
        for (std::size_t id = 0; id < objects_.size(); ++id) {
            Object& o = objects_[id];
            if (!o.alive) continue;
            const bool moved_ccd = o.ccd && !(o.step_start.R == o.pose.R && o.step_start.t == o.pose.t);
            o.step_start = o.pose;
            if (moved_ccd) std::visit([&](auto& bp) { bp.move(ObjectId(id), broad_box(o)); }, bp_);
        }
        return out;
    }

private:
    struct Object {
        std::optional<Shape<S>> shape;
        Transform<S> pose{};
        bool alive = false;
        bool ccd = false;
        Transform<S> step_start{};  ///< the pose at the previous step(): where a CCD object's motion starts
    };
    /// The object's broad-phase box: at its pose, or for a CCD object over its motion since the last step().
    /// A translation, and a mesh's motion (each vertex on a segment), stay in the box of the two end boxes; a
    /// convex shape that turns sweeps arcs that can leave it, so it gets the box of the ball about its frame's
    /// origin (radius: detail::radius_about_origin) along the origin's path.
    BroadBox<S> padded(BroadBox<S> box) const noexcept {
        const S m = S(options_.contact_margin);
        box.lo.array() -= m;
        box.hi.array() += m;
        return box;
    }
    BroadBox<S> broad_box(const Object& o) const {
        BroadBox<S> box = padded(o.shape->world_box(o.pose));
        if (!o.ccd) return box;
        const BroadBox<S> from = o.shape->world_box(o.step_start);
        box.lo = box.lo.cwiseMin(from.lo);
        box.hi = box.hi.cwiseMax(from.hi);
        if constexpr (std::is_same_v<S, double>) {
            if (!(o.step_start.R == o.pose.R)) {
                // A turning object sweeps arcs: a ball about its origin's path covers them. A mesh's radius from
                // its local box (its corners' farthest), a convex shape's from its support map.
                const Aabb<S>& lb = o.shape->local_bounds();
                const double r = o.shape->is_convex()
                                     ? o.shape->visit_convex([](const auto& c) { return detail::radius_about_origin(c); }) +
                                           double(o.shape->rounding())
                                     : (lb.center.cwiseAbs() + lb.half).norm() * (1 + 1e-12);
                const Vec3<S> c0 = o.shape->placed(o.step_start).t, c1 = o.shape->placed(o.pose).t;
                box.lo = box.lo.cwiseMin(Vec3<S>(c0.cwiseMin(c1).array() - r));
                box.hi = box.hi.cwiseMax(Vec3<S>(c0.cwiseMax(c1).array() + r));
            }
        }
        return box;
    }
    struct Candidate {
        ObjectPair pair;
        PairCache<S>* cache;
    };
    static void check_pose(const Transform<S>& pose, const char* op) {
        if (!pose_is_usable(pose))
            throw Error("<world>", std::string(op) + " pose", "not a finite rigid motion (rotation must be orthonormal, det +1)");
    }
    void check_id(ObjectId id, const char* op) const {
        if (!contains(id))
            throw Error("<world>", std::string(op) + " object " + std::to_string(id),
                        id < objects_.size() ? "already removed" : "unknown id");
    }

    WorldOptions options_;
    ManifoldRequest request_;
    std::variant<DynamicAabbTree<S>, SweepAndPrune<S>, UniformGrid<S>, BruteForceBroadPhase<S>, SortedCellGrid<S>> bp_;
    InterestMatrix<PairCache<S>> interest_;
    std::vector<Object> objects_;
    std::vector<Candidate> candidates_;
    std::vector<std::vector<WorldContact<S>>> results_;  ///< per candidate pair; kept between steps (capacity)
};

}  // namespace cdkit
