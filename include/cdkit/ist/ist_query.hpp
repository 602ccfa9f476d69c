#pragma once
/// \file Proximity and penetration queries on two inner sphere trees (Weller, Zachmann, "Inner sphere
/// trees for proximity and penetration queries", RSS 2009).
///
/// penetration_volume(): simultaneous descent of both trees (B's nodes carried into A's frame by the
/// relative transform pose_a⁻¹·pose_b), pruning node pairs whose bounding spheres are disjoint, splitting
/// the larger node, depth first with the deepest-overlapping children first. At two leaves the intersection (lens) volume of the two inner spheres is added. The
/// penetration volume is Σ lens volumes over all overlapping inner-sphere pairs, which equals the volume
/// of (∪ inner spheres of A) ∩ (∪ inner spheres of B) since the spheres of one object do not overlap.
/// It underestimates the mesh intersection volume by the empty space of the packings; `calibrated` corrects
/// for it: over the same overlapping pairs it sums the lens volumes of the two spheres' cell spheres (each
/// sphere grown to the volume of its cell, radius r·∛w with w its cell weight: inner_sphere_tree.hpp), which
/// puts the empty space back where it is, around the spheres and towards the surface.
///
/// Time-critical mode (max_node_tests > 0): the pairs are expanded best first, largest bound first, and
/// the query stops at the budget. Every unexpanded pair (a, b) contributes at most
/// min(vol(a), vol(b), lens(bounding spheres)) — inner spheres of one object are disjoint, so their
/// overlap with the other's is at most either side's sphere volume and lies in both bounding spheres —
/// giving a guaranteed interval [volume_lower, volume_upper] and an estimate in between (the bounding
/// spheres' lens scaled by both subtrees' fill ratios). volume_upper is the least such sum over the
/// expansion, so the interval never widens as the budget grows. `calibrated` adds that estimate of the pairs
/// left times (Σcalibrated + rest/(c_A c_B)) / (Σvolume + rest), c the coverages: the prior 1/(c_A c_B) while
/// little is done, the ratio seen so far once the pairs done outweigh the rest.
///
/// sphere_distance(): branch and bound on |c_a − c_b| − r_a − r_b, nearer pairs first; the distance
/// between the two inner sphere sets (≥ the meshes' distance, by at most the packings' gap at the
/// surface), with closest points on the two spheres.
///
/// ist_query(): both in one simultaneous descent. It follows every pair of overlapping bounding spheres (the
/// volume traversal, in the same order, so volume, calibrated volume and pairs are bit for bit those of
/// penetration_volume()) and, while no inner spheres overlap yet, also the pairs whose distance bound beats
/// the best inner-sphere distance so far (sphere_distance()'s pruning, nearest first); the first overlapping
/// inner-sphere pair ends the distance search. With a node budget it is one pass too, over one budget: the
/// time-critical volume traversal keeps the pairs apart while no inner spheres overlap, and the distance
/// search goes on from them with what is left of the budget.
///
/// All queries are const, thread-safe and noexcept apart from std::bad_alloc when collecting pairs.

#include "cdkit/core/math.hpp"
#include "cdkit/ist/inner_sphere_tree.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace cdkit {

/// Intersection volume of two balls of radii ra, rb whose centres are d apart (0 when disjoint or
/// touching, the smaller ball's volume when one holds the other).
[[nodiscard]] inline double sphere_intersection_volume(double ra, double rb, double d) noexcept {
    constexpr double pi = 3.14159265358979323846;
    if (d >= ra + rb) return 0;
    const double rmin = std::min(ra, rb);
    if (d <= std::abs(ra - rb)) return 4.0 / 3.0 * pi * rmin * rmin * rmin;
    const double s = ra + rb - d;
    return pi * s * s * (d * d + 2 * d * (ra + rb) - 3 * (ra - rb) * (ra - rb)) / (12 * d);
}

/// Options of the IST queries.
struct IstRequest {
    /// Node-pair budget (bounding-sphere tests); 0 = unlimited (exact). With a budget the answer is an
    /// estimate with guaranteed bounds (volume) or a lower bound (distance), and `complete` is false when
    /// the budget ran out.
    std::uint64_t max_node_tests = 0;
    bool collect_pairs = true;  ///< fill PenetrationVolumeResult::pairs
};

/// Two overlapping inner spheres (indices into each tree's spheres()) and their intersection volume.
struct OverlappingSpheres {
    std::uint32_t a = 0, b = 0;
    double volume = 0;
};

/// Work counters of one query.
struct IstQueryStats {
    std::uint64_t node_tests = 0;  ///< bounding-sphere pair tests
    std::uint64_t leaf_pairs = 0;  ///< inner-sphere pairs evaluated
};

/// Result of penetration_volume(). Volumes in model units³.
struct PenetrationVolumeResult {
    QueryStatus status = QueryStatus::ok;  ///< invalid_pose: a pose was not a rigid motion; nothing computed
    bool complete = true;        ///< false: stopped at the node budget, `volume` is an estimate
    double volume = 0;           ///< Σ intersection volumes of overlapping inner-sphere pairs (estimate if incomplete)
    double volume_lower = 0;     ///< guaranteed lower bound of the exact (full-traversal) volume
    double volume_upper = 0;     ///< guaranteed upper bound of it
    double calibrated = 0;       ///< Σ lens(cell sphere a, cell sphere b) over the pairs: estimate of the meshes' intersection volume
    std::vector<OverlappingSpheres> pairs;  ///< every overlapping pair found (all of them when complete)
    IstQueryStats stats;
    bool colliding = false;      ///< volume_upper > 0: some inner spheres may overlap
};

/// Result of sphere_distance(). Points in the world frame.
struct IstDistanceResult {
    QueryStatus status = QueryStatus::ok;
    bool complete = true;                                      ///< false: budget ran out
    double distance = std::numeric_limits<double>::infinity(); ///< 0 when inner spheres overlap
    double lower_bound = 0;                                    ///< ≤ the exact sphere-set distance (= distance when complete)
    Vec3<double> point_a = Vec3<double>::Zero();               ///< on sphere_a's surface
    Vec3<double> point_b = Vec3<double>::Zero();               ///< on sphere_b's surface
    std::uint32_t sphere_a = 0, sphere_b = 0;
    IstQueryStats stats;
};

/// Penetration volume of A and B at world poses pose_a, pose_b (model → world). Empty trees give 0.
[[nodiscard]] PenetrationVolumeResult penetration_volume(const InnerSphereTree& a, const Transform<double>& pose_a,
                                                         const InnerSphereTree& b, const Transform<double>& pose_b,
                                                         const IstRequest& request = {});

/// Smallest distance between the inner spheres of A and of B (0 with a witness pair when some overlap).
[[nodiscard]] IstDistanceResult sphere_distance(const InnerSphereTree& a, const Transform<double>& pose_a,
                                                const InnerSphereTree& b, const Transform<double>& pose_b,
                                                const IstRequest& request = {});

/// Combined query: the volume when the objects' inner spheres overlap, the distance when they are apart.
/// Without a node budget: one descent (see the file comment), and `volume` and `distance` (when apart) both
/// carry its counters in `stats`. With a budget: one pass over that budget (the volume part is
/// penetration_volume()'s with the same budget; the distance, when no inner spheres overlap, is searched
/// with what is left: `distance.lower_bound` holds whatever the budget allowed, `distance.complete` says
/// whether it is exact).
struct IstQueryResult {
    QueryStatus status = QueryStatus::ok;
    bool colliding = false;          ///< some inner spheres overlap (volume > 0)
    PenetrationVolumeResult volume;  ///< always filled
    IstDistanceResult distance;      ///< filled only when !colliding (distance 0 otherwise)
    IstQueryStats stats;             ///< total work of the query
};
[[nodiscard]] IstQueryResult ist_query(const InnerSphereTree& a, const Transform<double>& pose_a,
                                       const InnerSphereTree& b, const Transform<double>& pose_b,
                                       const IstRequest& request = {});

}  // namespace cdkit
