#pragma once
/// \file Request, statistics and result of a primitive continuous collision query (vertex–face, edge–edge):
/// four points moving linearly from their positions at t = 0 to those at t = 1.

#include "cdkit/core/math.hpp"

#include <cstdint>
#include <initializer_list>

namespace cdkit {

/// What a primitive CCD query is asked. Distances are absolute, in the units of the coordinates.
struct CcdRequest {
    /// Contact means a Euclidean distance ≤ min_separation (0: touching). Simulators that keep a gap set it > 0.
    double min_separation = 0;
    /// A region of the (t, u, v) domain whose values of the gap function all lie within `tolerance` of each
    /// other (per axis) and do not exclude contact is reported as a contact: the query may report pairs that come
    /// closer than about `tolerance` without touching (false positives), never misses one that touches.
    double tolerance = 1e-6;
    /// A contact that is proven (CcdResult::proven) has its first time narrowed to within time_tolerance.
    double time_tolerance = 1e-6;
    /// Only contacts at t ≤ t_max are searched (a mesh query passes its best time of impact so far).
    double t_max = 1;
    /// Work cap: after this many domain boxes the query stops and reports a conservative contact at the
    /// earliest time still undecided (stats.capped). It bounds the worst case; see docs/ccd.md for its effect.
    std::uint32_t max_boxes = 4096;
};

/// Work done by one query, so that its time can be explained.
struct CcdStats {
    std::uint32_t boxes = 0;         ///< domain boxes examined (each: 8 corner evaluations and the exclusion tests)
    std::uint32_t subdivisions = 0;  ///< boxes split in two
    std::uint32_t newton_steps = 0;  ///< Krawczyk steps tried (each about the cost of a box)
    bool capped = false;             ///< max_boxes reached: `colliding` is the conservative answer, not a finding
};

/// Answer of a primitive CCD query.
struct CcdResult {
    QueryStatus status = QueryStatus::ok;  ///< invalid_input: a coordinate or setting was not finite; no answer
    bool colliding = false;                ///< contact (distance ≤ min_separation, see CcdRequest) at some t ∈ [0, t_max]
    /// With colliding: true when the contact is proven to exist (an interval Newton test found the zero of the
    /// gap function); false when the features only came within about the tolerance (possibly a near miss) or
    /// the work cap was reached. Never set with min_separation > 0.
    bool proven = false;
    /// Certified lower bound of the first time of contact: no contact happens in [0, toi). With colliding,
    /// the contact (proven) or near-contact region found lies in [toi, toi_upper]; proven contacts have
    /// toi_upper − toi ≤ time_tolerance unless Newton stalled first; toi_upper = t_max when capped.
    double toi = 1;
    double toi_upper = 1;
    /// Feature parameters at the contact: vertex–face: barycentric (u, v) of the face point a + u(b − a) + v(c − a);
    /// edge–edge: u along edge A (a0 → a1), v along edge B (b0 → b1). Midpoints of the region found.
    double u = 0, v = 0;
    Vec3<double> point = Vec3<double>::Zero();   ///< contact point at t = toi (on the face, or on edge A)
    Vec3<double> normal = Vec3<double>::Zero();  ///< unit normal at t = toi, pointing from the face (edge B)
                                                 ///< towards the vertex (edge A) as they were at t = 0
    CcdStats stats;
};

namespace detail {
/// The check every continuous query makes of the poses that start and end its motions.
[[nodiscard]] inline bool motion_poses_usable(std::initializer_list<const Transform<double>*> poses) noexcept {
    for (const auto* p : poses)
        if (!pose_is_usable(*p)) return false;
    return true;
}
}  // namespace detail

}  // namespace cdkit
