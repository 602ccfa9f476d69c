#pragma once
// A seeded corpus of convex pairs that are hard on purpose, for issue 5's robustness count (the test
// test_gjk_hard_cases.cpp and the benchmark cdkit_bench_convex_hard run the same generator).
//
// Shapes: boxes, cylinders, capsules, cones, ellipsoids, spheres, triangles, rounded boxes and qhull hulls, each
// drawn regular or degenerate (flat: a box with one extent 0 or 1e-9 of the others, an ellipsoid or a hull 1e-7
// thick; needle: a box, cylinder, cone, ellipsoid or hull 1e-7 wide or less, a capsule of radius 1e-9; a triangle
// 1e-9 wide or a segment; a rounded box's box as a box's, its radius 1, 1e-3 or 1e-9 of its size), B scaled by
// 10^k, k ∈ −6…6,
// so size ratios reach 1e6 either way. Placements: random (up to 2 sizes apart, A up to 100 sizes from the
// origin), touching (gap 0), near contact (±1e-9, ±1e-12 of the size), shallow (±1e-4, ±1e-2), nested (same
// pose: the smaller inside the larger, or a needle through it) and coincident (the same shape at the same pose);
// gaps are set by long-double GJK along its closest-point normal (near_contact_pose.hpp).
// Queries per case: cold boolean; boolean and distance warm-started from the cache their first call filled (a
// second call at the same pose); gjk_distance cold; the separating plane from an empty cache and from the plane
// (or GJK cache) of B half a size further out along the centre line; for hull pairs the closest-feature walk,
// cold and from the far pose's features; penetration() where either the reference or the cold boolean says the
// pair collides.
// Failures: a non-finite value in a result that reports it (distance, normal, points, depth), a status a query
// may not give on finite shapes (max_iterations, degenerate), a boolean or a distance status that contradicts
// long-double GJK where that is decisive (intersecting, or separated by more than 1e-9 of the size), a negative
// depth or a depth's normal that is not unit, a penetration() answering separated or touching where D reaches
// beyond 1e-9 of the size along its normal (h(n), long double). Counted, not failures: separation distances off
// the certified interval by more than 1e-9 relative, EPA's statuses (max_iterations and degenerate carry a finite
// best estimate), the width of its bracket [depth_lower, depth] and depths off h(n), the slowest case (a hang
// would never end: every query has an iteration cap).
// Exact judge (issue 37, independent oracles): given an ExactOracle (tests/oracles/exact_polytope.hpp, CGAL's exact
// QP/LP on the exactly posed vertices; linked only into the *_cgal test and the benchmark), every case whose shapes
// are both polytopes (boxes, triangles, hulls) is judged again exactly: each boolean answer against the exact
// sign (wrong booleans: a contradiction where the exact gap or L∞ depth exceeds the band; exactly touching pairs
// are undecided: either answer is right), each separation distance against the exact one (histogram), each
// EPA bracket against the exact L∞ depth's bounds.
// Curved judge (issue 37): given the curved referee (tests/oracles/curved_referee.hpp: support functions written
// afresh, in MPFR, sharing no code with cdkit's GJK), every case with a curved shape (sphere, capsule, cylinder,
// cone, ellipsoid, rounded box; against boxes and hulls too) is judged by its certificates: separated with a
// certified distance interval, intersecting with a certified depth lower bound, or undecided (counted, never
// dropped). A boolean answer contradicting a certificate is wrong where the certified distance exceeds the band
// (or the depth is certified beyond it: six points ±√3·band·size inside B − A); disagreements within the band, or
// whose depth the referee cannot place against it, are counted apart. Each separation distance is judged against
// the certified interval (histogram).
#include <cdkit/narrowphase/closest_features.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/epa.hpp>
#include <cdkit/narrowphase/separating_plane.hpp>

#include "convex_case_file.hpp"
#include "convex_reference.hpp"
#include "near_contact_pose.hpp"
#include "oracles/curved_referee.hpp"
#include "oracles/exact_polytope.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace cdkit::test::hard {

using LD = long double;
using Clock = std::chrono::steady_clock;

enum Placement { random_pose, touching, near_contact, shallow, nested, coincident, placements };
inline constexpr const char* placement_names[placements] = {"random",  "touching", "near",
                                                             "shallow", "nested",   "coincident"};

/// The exact referee's entry points (tests/oracles/exact_polytope.hpp), passed in so that this header needs no
/// CGAL: null members leave the exact judge out (the sanitizer build, which has no CGAL TU).
struct ExactOracle {
    decltype(&exact::exact_polytope_pair) pair = nullptr;
    /// The curved referee (tests/oracles/curved_referee_mpfr.cpp); null leaves the curved judge out.
    decltype(&curved::curved_referee) curved = nullptr;
    decltype(&curved::depth_exceeds) curved_depth = nullptr;
};

/// Exact boolean band: a boolean answer is wrong when it contradicts the exact answer and the exact gap (distance)
/// or L∞ depth exceeds band_rel·size; within the band it is counted, not failed; exactly touching pairs are
/// undecided. 1e-10 of the size is what docs/convex.md promises ("Certified separation": every pair apart by more
/// than 1e-10 of the size is answered separated); below it the queries' touching tolerance (256ε of the Minkowski
/// difference's size, which grows with |t_rel| and the larger shape) and the poses' rounding decide.
inline constexpr double band_rel = 1e-10;
/// Bins of the exact judge: disagreements by |exact gap| / size (≤ 1e-15, ≤ 1e-12, ≤ 1e-10, ≤ 1e-9, > 1e-9; the
/// gap is the exact distance, or the exact L∞ depth of an overlap) and distance errors |d − exact| / max(exact, 1e-9·size) (≤ 1e-15, ≤ 1e-12, ≤ 1e-9, ≤ 1e-6, ≤ 1e-3,
/// > 1e-3).
inline constexpr std::array<const char*, 5> gap_bin_names = {"<=1e-15", "<=1e-12", "<=1e-10", "<=1e-9", ">1e-9"};
inline constexpr std::array<const char*, 6> error_bin_names = {"<=1e-15", "<=1e-12", "<=1e-9",
                                                               "<=1e-6",  "<=1e-3",  ">1e-3"};
inline std::size_t error_bin(double e) {
    return e <= 1e-15 ? 0 : e <= 1e-12 ? 1 : e <= 1e-9 ? 2 : e <= 1e-6 ? 3 : e <= 1e-3 ? 4 : 5;
}

/// What both judges count over the cases they judge: a certified (or exact) side per case, each boolean answer
/// against it, each separation distance against the judge's distance (histograms).
struct JudgedCounts {
    long judged = 0;                           ///< cases given to the judge
    long separated = 0, overlapping = 0;       ///< judged apart / overlapping (with depth, or certified)
    long answers = 0;                          ///< boolean answers judged
    long wrong = 0;                            ///< answers contradicting the judge beyond the band (failures)
    long disagree_band = 0;                    ///< answers on the other side of an answer within the band
    std::array<long, 5> disagree_by_gap{};     ///< every disagreement, by gap_bin_names
    long distances = 0;                        ///< separation distances judged (judged apart, answer not intersecting)
    std::array<long, 6> distance_error{};      ///< by error_bin_names (relative to max(distance, 1e-9·size))
    double worst_distance_error = 0;
    long distances_far = 0;                    ///< of them, the judge's distance > 1e-6·size (the relative-error domain)
    std::array<long, 6> distance_error_far{};  ///< relative error there, by error_bin_names
    double worst_distance_error_far = 0;
    std::string first_wrong;  ///< one line for each of the first dozen wrong answers
    int wrong_described = 0;
    void add(const JudgedCounts& c) {
        judged += c.judged, separated += c.separated, overlapping += c.overlapping;
        answers += c.answers, wrong += c.wrong, disagree_band += c.disagree_band;
        for (std::size_t k = 0; k < disagree_by_gap.size(); ++k) disagree_by_gap[k] += c.disagree_by_gap[k];
        distances += c.distances;
        for (std::size_t k = 0; k < distance_error.size(); ++k) distance_error[k] += c.distance_error[k];
        worst_distance_error = std::max(worst_distance_error, c.worst_distance_error);
        distances_far += c.distances_far;
        for (std::size_t k = 0; k < distance_error_far.size(); ++k) distance_error_far[k] += c.distance_error_far[k];
        worst_distance_error_far = std::max(worst_distance_error_far, c.worst_distance_error_far);
        if (wrong_described < 12) first_wrong += c.first_wrong, wrong_described += c.wrong_described;
    }
};

/// What the exact judge counted over the polytope cases (separated: exact distance > 0; overlapping: with depth).
struct ExactCounts : JudgedCounts {
    long not_judged = 0;                       ///< curved cases (left to the curved referee)
    long touching = 0;                         ///< exact: touching (undecided: either boolean is right)
    long in_band = 0;                          ///< exact gap or L∞ depth in (0, band_rel·size]
    long epa_checked = 0, epa_contradicted = 0;  ///< EPA brackets against δ ∈ [depth_inf/√3, depth_inf]
    /// The curved referee checked against the exact answer on these polytope cases (its boxes and hulls, the
    /// triangles as hulls): cases, undecided, contradicted (a certificate the exact answer refutes).
    long referee_checked = 0, referee_undecided = 0, referee_contradicted = 0;
    void add(const ExactCounts& c) {
        JudgedCounts::add(c);
        not_judged += c.not_judged, touching += c.touching, in_band += c.in_band;
        epa_checked += c.epa_checked, epa_contradicted += c.epa_contradicted;
        referee_checked += c.referee_checked, referee_undecided += c.referee_undecided;
        referee_contradicted += c.referee_contradicted;
    }
};

/// What the curved judge counted over the cases with a curved shape (separated / overlapping: certified; the
/// distance errors are off the certified interval, relative to max(lower, 1e-9·size) and, far, to lower).
struct CurvedCounts : JudgedCounts {
    long undecided = 0;                        ///< no certificate (touching within its error bounds, or search failed)
    long disagree_undecided = 0;               ///< contradicting an overlap whose depth the referee cannot place
    double widest_interval = 0;                ///< the widest certified interval, (upper − lower) / max(lower, 1e-9·size)
    long iterations = 0;                       ///< the referee's support rounds, summed
    std::string first_undecided;  ///< one line for each of the first undecided cases (pose digits to rebuild it)
    int undecided_described = 0;
    void add(const CurvedCounts& c) {
        JudgedCounts::add(c);
        undecided += c.undecided, disagree_undecided += c.disagree_undecided;
        widest_interval = std::max(widest_interval, c.widest_interval);
        iterations += c.iterations;
        if (undecided_described < 6)
            first_undecided += c.first_undecided, undecided_described += c.undecided_described;
    }
};

struct Counts {
    long cases = 0, decisive = 0, colliding = 0, placed_random = 0;
    long nonfinite = 0, bad_status = 0, wrong_boolean = 0, wrong_distance_status = 0, bad_depth = 0;
    long distance_checked = 0, distance_outliers = 0, epa_runs = 0;
    std::array<long, 5> epa_status{};
    // EPA against h(n), D's support value along the reported normal in long double (the true depth is the least
    // h over all directions): separated or touching where h(n) > 1e-9·size, per placement (failures); per EPA
    // status, the bracket (depth − depth_lower) / depth ≤ 1e-9, ≤ 1e-6, ≤ 1e-3, > 1e-3, and depths off h(n) by
    // more than 1e-9·h + 1e-12·size (bin 4); shallower overlaps (h(n) ≤ 1e-9·size) and those off h(n) by more
    // than 1e-12·size.
    std::array<long, placements> epa_wrong_status{};
    std::array<std::array<long, 5>, 5> epa_gap{};
    long epa_checked = 0, epa_shallow = 0, epa_shallow_off = 0;
    std::array<long, placements> epa_loose{};  ///< bracket > 1e-3 of the depth, per placement
    std::array<long, placements> by_placement{};
    double slowest_us = 0;
    std::string first_failures;  ///< one line for each of the first dozen failures
    int described = 0;
    std::string first_outliers;  ///< one line for each of the first distances off the certified interval
    int outliers_described = 0;
    ExactCounts exact;  ///< the exact judge's counts (all zero without an oracle)
    CurvedCounts curved;  ///< the curved judge's counts (all zero without the curved referee)
    [[nodiscard]] long failures() const {
        long wrong_epa = 0;
        for (long n : epa_wrong_status) wrong_epa += n;
        return nonfinite + bad_status + wrong_boolean + wrong_distance_status + bad_depth + wrong_epa;
    }
    void add(const Counts& c) {
        cases += c.cases, decisive += c.decisive, colliding += c.colliding, placed_random += c.placed_random;
        nonfinite += c.nonfinite, bad_status += c.bad_status, wrong_boolean += c.wrong_boolean;
        wrong_distance_status += c.wrong_distance_status, bad_depth += c.bad_depth;
        distance_checked += c.distance_checked, distance_outliers += c.distance_outliers, epa_runs += c.epa_runs;
        for (std::size_t k = 0; k < epa_status.size(); ++k) epa_status[k] += c.epa_status[k];
        for (std::size_t k = 0; k < epa_gap.size(); ++k)
            for (std::size_t j = 0; j < epa_gap[k].size(); ++j) epa_gap[k][j] += c.epa_gap[k][j];
        epa_checked += c.epa_checked, epa_shallow += c.epa_shallow, epa_shallow_off += c.epa_shallow_off;
        for (std::size_t k = 0; k < by_placement.size(); ++k) {
            by_placement[k] += c.by_placement[k];
            epa_wrong_status[k] += c.epa_wrong_status[k];
            epa_loose[k] += c.epa_loose[k];
        }
        slowest_us = std::max(slowest_us, c.slowest_us);
        if (described < 12) first_failures += c.first_failures, described += c.described;
        if (outliers_described < 12)
            first_outliers += c.first_outliers, outliers_described += c.outliers_described;
        exact.add(c.exact);
        curved.add(c.curved);
    }
};

/// A primitive's extents drawn once per case (box half extents, radii, half heights); `make<K, double>` and
/// `make<K, long double>` build the same shape from them.
struct ShapeDraw {
    double x = 0.1, y = 0.1, z = 0.1;
    double r = 0;  ///< the rounding radius of a rounded box (class 7)
};

/// A box rounded by a radius, `Inflated<Box>`: the view holds a reference, so the box lives beside it (built in
/// place by `make`, never copied; `shape_of` hands the view to the queries).
template <class S> struct RoundedBox {
    Box<S> core;
    Inflated<Box<S>> shape;
    RoundedBox(const Box<S>& b, S radius) : core(b), shape{core, radius} {}
    RoundedBox(const RoundedBox&) = delete;
    RoundedBox& operator=(const RoundedBox&) = delete;
};
template <class T> const T& shape_of(const T& s) { return s; }
template <class S> const Inflated<Box<S>>& shape_of(const RoundedBox<S>& s) { return s.shape; }

/// Hulls are built once (Qhull per case would dominate the run): regular, 1e-7 thin and 1e-7 needle, at every
/// scale 10^k, k ∈ −6…6, in double and long double from the same points.
struct HullPool {
    static constexpr int kinds = 3, scales = 13;
    std::vector<ConvexPolyhedron<double>> d;
    std::vector<ConvexPolyhedron<LD>> l;
    explicit HullPool(std::mt19937_64& rng) {
        std::normal_distribution<double> g;
        for (int kind = 0; kind < kinds; ++kind) {
            std::vector<Vec3<double>> pts;
            for (int i = 0; i < 60; ++i) {
                Vec3<double> p;
                for (int k = 0; k < 3; ++k) p[k] = g(rng);
                p = p.normalized() * 0.1;
                if (kind == 1) p[2] *= 1e-6;  // a slab 1e-7 thick
                if (kind == 2) p[0] *= 1e-6, p[1] *= 1e-6;  // a needle 1e-7 wide
                pts.push_back(p);
            }
            for (int k = 0; k < scales; ++k) {
                const double s = std::pow(10.0, k - 6);
                std::vector<Vec3<double>> sd;
                std::vector<Vec3<LD>> sl;
                for (const auto& p : pts) sd.push_back(p * s), sl.push_back((p * s).cast<LD>());
                d.emplace_back(sd);
                l.emplace_back(sl);
            }
        }
    }
};

template <class S> Vec3<S> v3(double x, double y, double z) { return Vec3<S>(S(x), S(y), S(z)); }

/// The shape of class K from a draw, in scalar S (K: 0 box, 1 cylinder, 2 capsule, 3 cone, 4 ellipsoid, 5 sphere,
/// 6 triangle: an isosceles one x long and 2y wide, a sliver or a segment when y is tiny or 0; 7 a box rounded by r).
template <int K, class S> auto make(const ShapeDraw& p) {
    if constexpr (K == 7) return RoundedBox<S>(Box<S>(v3<S>(p.x, p.y, p.z)), S(p.r));
    else if constexpr (K == 6)
        return ConvexTriangle<S>(v3<S>(p.x, 0, 0), v3<S>(-0.5 * p.x, p.y, 0), v3<S>(-0.5 * p.x, -p.y, 0));
    else if constexpr (K == 0) return Box<S>(v3<S>(p.x, p.y, p.z));
    else if constexpr (K == 1) return Cylinder<S>(S(p.x), S(p.z));
    else if constexpr (K == 2) return Capsule<S>(S(p.x), S(p.z));
    else if constexpr (K == 3) return Cone<S>(S(p.x), S(p.z));
    else if constexpr (K == 4) return Ellipsoid<S>(v3<S>(p.x, p.y, p.z));
    else return Sphere<S>(S(p.x));
}

/// Regular or degenerate extents for class K at scale s: flat (one extent 0 or 1e-9 of the others) or needle.
inline ShapeDraw draw_extents(int kind, double s, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.05, 0.1);
    ShapeDraw p{u(rng) * s, u(rng) * s, u(rng) * s};
    const int degenerate = std::uniform_int_distribution<int>(0, 2)(rng);  // 0 regular, 1 flat, 2 needle
    const double tiny = std::uniform_int_distribution<int>(0, 1)(rng) ? 0.0 : 1e-9;
    if (degenerate == 1 && (kind == 0 || kind == 4)) p.z = kind == 0 ? tiny * s : std::max(tiny, 1e-7) * s;
    if (degenerate == 2) {
        if (kind == 0) p.x = p.y = tiny * s;                  // a box needle (a segment when 0)
        if (kind == 1 || kind == 3) p.x = 1e-7 * s;           // needle cylinder, needle cone
        if (kind == 2) p.x = std::max(tiny, 1e-9) * s;        // capsule of radius 1e-9
        if (kind == 4) p.x = p.y = 1e-7 * s;                  // needle ellipsoid
    }
    if (degenerate != 0 && kind == 6) p.y = tiny * s;         // a sliver triangle (a segment when 0)
    if (kind == 7) {  // a rounded box: the box as class 0's (flat: a coin; needle: a rounded segment), radius
        // the box's size, a thousandth of it or 1e-9 of it
        if (degenerate == 1) p.z = tiny * s;
        if (degenerate == 2) p.x = p.y = tiny * s;
        const double f[3] = {1.0, 1e-3, 1e-9};
        p.r = u(rng) * s * f[std::uniform_int_distribution<int>(0, 2)(rng)];
    }
    return p;
}

/// A shape in a few words, for the failure lines.
inline std::string describe(const Box<double>& s) {
    return "box " + std::to_string(s.half[0]) + " " + std::to_string(s.half[1]) + " " + std::to_string(s.half[2]);
}
inline std::string describe(const Cylinder<double>& s) {
    return "cylinder " + std::to_string(s.radius) + " " + std::to_string(s.half_height);
}
inline std::string describe(const Capsule<double>& s) {
    return "capsule " + std::to_string(s.radius) + " " + std::to_string(s.half_length);
}
inline std::string describe(const Cone<double>& s) {
    return "cone " + std::to_string(s.radius) + " " + std::to_string(s.half_height);
}
inline std::string describe(const Ellipsoid<double>& s) {
    return "ellipsoid " + std::to_string(s.radii[0]) + " " + std::to_string(s.radii[1]) + " " +
           std::to_string(s.radii[2]);
}
inline std::string describe(const Sphere<double>& s) { return "sphere " + std::to_string(s.radius); }
inline std::string describe(const Inflated<Box<double>>& s) {
    return "rounded box " + std::to_string(s.shape.half[0]) + " " + std::to_string(s.shape.half[1]) + " " +
           std::to_string(s.shape.half[2]) + " radius " + std::to_string(s.radius);
}
inline std::string describe(const ConvexTriangle<double>& s) {
    return "triangle " + std::to_string(s.a[0]) + " x " + std::to_string(2 * s.b[1]);
}
inline std::string describe(const ConvexPolyhedron<double>& s) {
    return "hull of " + std::to_string(s.vertices().size()) + " vertices, radius " +
           std::to_string(s.bounding_radius());
}

/// The points whose hull is the shape, for the exact judge: boxes, triangles and hulls are polytopes.
template <class T>
inline constexpr bool is_polytope_v = std::is_same_v<T, Box<double>> || std::is_same_v<T, ConvexTriangle<double>> ||
                                      std::is_same_v<T, ConvexPolyhedron<double>>;
inline std::vector<Vec3<double>> vertex_list(const Box<double>& s) {
    std::vector<Vec3<double>> v;
    for (int k = 0; k < 8; ++k)
        v.emplace_back(k & 1 ? s.half[0] : -s.half[0], k & 2 ? s.half[1] : -s.half[1], k & 4 ? s.half[2] : -s.half[2]);
    return v;
}
inline std::vector<Vec3<double>> vertex_list(const ConvexTriangle<double>& s) { return {s.a, s.b, s.c}; }
inline std::vector<Vec3<double>> vertex_list(const ConvexPolyhedron<double>& s) { return s.vertices(); }

/// One boolean answer of a case, kept for the exact judge (distance queries: their status and distance too).
struct Answer {
    const char* name;
    bool colliding, distance_query;
    GjkStatus status;
    double distance;
};

/// The exact judge of one polytope case (see the header comment): `answers` are the case's boolean answers, `epa`
/// its penetration() result if it ran.
template <class A, class B>
void judge_exactly(const ExactOracle& oracle, const A& a, const Transform<double>& pa, const B& b,
                   const Transform<double>& pb, double size, Placement m, const std::vector<Answer>& answers,
                   const PenetrationResult<double>* epa, ExactCounts& e) {
    ++e.judged;
    const std::vector<Vec3<double>> va = vertex_list(a), vb = vertex_list(b);
    const auto x = oracle.pair(va, pa, vb, pb, true);
    if (oracle.curved != nullptr) {
        // The curved referee on the same pair (its hull support function), against the exact answer: a separation
        // certificate must hold the exact distance (rounded within ~2ε) and the pair must be apart; an overlap
        // certificate needs an exact intersection, its depth bound at most the exact L∞ depth (δ ≤ depth_inf).
        const curved::ShapeSpec sa{curved::ShapeKind::hull, 0, 0, 0, 0, &va}, sb{curved::ShapeKind::hull, 0, 0, 0, 0, &vb};
        const curved::CurvedAnswer r = oracle.curved(sa, pa, sb, pb, pb.t - pa.t);
        ++e.referee_checked;
        bool refuted = false;
        if (r.verdict == curved::Verdict::undecided) ++e.referee_undecided;
        else if (r.verdict == curved::Verdict::separated)
            refuted = x.intersect || r.lower > x.distance * (1 + 1e-15) || r.upper < x.distance * (1 - 1e-15);
        else
            refuted = !x.intersect || (x.depth_known && r.depth_lower > x.depth_inf * (1 + 1e-15));
        e.referee_contradicted += refuted;
        if (refuted && e.wrong_described < 12) {
            char line[320];
            std::snprintf(line, sizeof line,
                          "  referee refuted: %s placement, size %.3g: verdict %d [%.17g, %.17g] depth >= %.17g; exact "
                          "intersect %d distance %.17g depth_inf %.17g; ",
                          placement_names[m], size, int(r.verdict), r.lower, r.upper, r.depth_lower, int(x.intersect),
                          x.distance, x.depth_inf);
            e.first_wrong += line + describe(a) + " / " + describe(b) + "\n";
            ++e.wrong_described;
        }
    }
    // side: +1 apart, −1 overlapping with depth, 0 touching; gap: the exact distance or L∞ depth.
    const int side = !x.intersect ? 1 : x.touching ? 0 : -1;
    const double gap = side > 0 ? x.distance : side < 0 ? x.depth_inf : 0.0;
    e.separated += side > 0, e.overlapping += side < 0, e.touching += side == 0;
    const bool banded = side != 0 && gap <= band_rel * size;
    e.in_band += banded;
    for (const Answer& ans : answers) {
        ++e.answers;
        if (side > 0 && ans.distance_query && ans.status != GjkStatus::intersecting) {
            const double err = std::abs(ans.distance - x.distance) / std::max(x.distance, 1e-9 * size);
            ++e.distances;
            ++e.distance_error[error_bin(err)];
            e.worst_distance_error = std::max(e.worst_distance_error, err);
            if (x.distance > 1e-6 * size) {
                ++e.distances_far;
                ++e.distance_error_far[error_bin(err)];
                e.worst_distance_error_far = std::max(e.worst_distance_error_far, err);
            }
        }
        if (side == 0 || ans.colliding == (side < 0)) continue;
        const double rel = gap / size;
        ++e.disagree_by_gap[rel <= 1e-15 ? 0 : rel <= 1e-12 ? 1 : rel <= 1e-10 ? 2 : rel <= 1e-9 ? 3 : 4];
        if (banded) {
            ++e.disagree_band;
            continue;
        }
        ++e.wrong;
        if (e.wrong_described < 12) {
            char line[320];
            std::snprintf(line, sizeof line,
                          "  exact: %s wrong, %s placement, size %.3g, |t_a| %.3g: answered %s; exact %s, gap %.17g; ",
                          ans.name, placement_names[m], size, pa.t.norm(), ans.colliding ? "colliding" : "apart",
                          side > 0 ? "apart" : "overlapping", gap);
            e.first_wrong += line + describe(a) + " / " + describe(b) + "\n";
            ++e.wrong_described;
        }
    }
    // EPA's bracket [depth_lower, depth] holds the Euclidean depth δ, and depth_inf/√3 ≤ δ ≤ depth_inf exactly.
    if (side < 0 && epa != nullptr && epa->status != GjkStatus::separated && epa->status != GjkStatus::touching) {
        ++e.epa_checked;
        const double slack = 1e-9 * x.depth_inf + 1e-12 * size;
        const bool contradicted =
            epa->depth_lower > x.depth_inf + slack || epa->depth < x.depth_inf / std::sqrt(3.0) - slack;
        e.epa_contradicted += contradicted;
        if (contradicted && e.wrong_described < 12) {
            char line[320];
            std::snprintf(line, sizeof line,
                          "  exact: EPA bracket [%.17g, %.17g] (status %s), %s placement, size %.3g: exact L-inf depth "
                          "%.17g; ",
                          epa->depth_lower, epa->depth, to_string(epa->status), placement_names[m], size, x.depth_inf);
            e.first_wrong += line + describe(a) + " / " + describe(b) + "\n";
            ++e.wrong_described;
        }
    }
}

/// The curved referee's description of a shape (its parameters as the shape holds them; hulls by their vertices,
/// which outlive the call).
inline curved::ShapeSpec spec_of(const Box<double>& s) {
    return {curved::ShapeKind::box, s.half[0], s.half[1], s.half[2], 0, nullptr};
}
inline curved::ShapeSpec spec_of(const Sphere<double>& s) { return {curved::ShapeKind::sphere, s.radius, 0, 0, 0, nullptr}; }
inline curved::ShapeSpec spec_of(const Capsule<double>& s) {
    return {curved::ShapeKind::capsule, s.radius, s.half_length, 0, 0, nullptr};
}
inline curved::ShapeSpec spec_of(const Cylinder<double>& s) {
    return {curved::ShapeKind::cylinder, s.radius, s.half_height, 0, 0, nullptr};
}
inline curved::ShapeSpec spec_of(const Cone<double>& s) {
    return {curved::ShapeKind::cone, s.radius, s.half_height, 0, 0, nullptr};
}
inline curved::ShapeSpec spec_of(const Ellipsoid<double>& s) {
    return {curved::ShapeKind::ellipsoid, s.radii[0], s.radii[1], s.radii[2], 0, nullptr};
}
inline curved::ShapeSpec spec_of(const Inflated<Box<double>>& s) {
    return {curved::ShapeKind::rounded_box, s.shape.half[0], s.shape.half[1], s.shape.half[2], s.radius, nullptr};
}
inline curved::ShapeSpec spec_of(const ConvexPolyhedron<double>& s) {
    return {curved::ShapeKind::hull, 0, 0, 0, 0, &s.vertices()};
}

/// The curved judge of one case (see the header comment): `answers` are the case's boolean answers, `hint` a
/// direction from A towards B to start the referee's search from (long-double GJK's normal: the certificates do
/// not depend on it).
template <class A, class B>
void judge_curved(const ExactOracle& oracle, const A& a, const Transform<double>& pa, const B& b,
                  const Transform<double>& pb, double size, Placement m, const std::vector<Answer>& answers,
                  const Vec3<double>& hint, CurvedCounts& e) {
    ++e.judged;
    const curved::ShapeSpec sa = spec_of(a), sb = spec_of(b);
    const curved::CurvedAnswer x = oracle.curved(sa, pa, sb, pb, hint);
    e.iterations += x.iterations;
    if (x.verdict == curved::Verdict::undecided) {
        ++e.undecided;
        if (e.undecided_described < 6) {
            char line[640];
            std::snprintf(line, sizeof line,
                          "  undecided: %s placement, size %.3g, %d rounds; t_a %a %a %a, t_b %a %a %a; ",
                          placement_names[m], size, x.iterations, pa.t[0], pa.t[1], pa.t[2], pb.t[0], pb.t[1],
                          pb.t[2]);
            e.first_undecided += line + describe(a) + " / " + describe(b) + "\n";
            ++e.undecided_described;
        }
        return;
    }
    const bool apart = x.verdict == curved::Verdict::separated;
    e.separated += apart, e.overlapping += !apart;
    const double band = band_rel * size;
    if (apart)
        e.widest_interval = std::max(e.widest_interval, (x.upper - x.lower) / std::max(x.lower, 1e-9 * size));
    int depth_class = 2;  // for overlaps: +1 deeper than the band, −1 within √3·band, 0 undecided; 2 not asked yet
    for (const Answer& ans : answers) {
        ++e.answers;
        if (apart && ans.distance_query && ans.status != GjkStatus::intersecting) {
            const double off = std::max({0.0, x.lower - ans.distance, ans.distance - x.upper});
            const double err = off / std::max(x.lower, 1e-9 * size);
            ++e.distances;
            ++e.distance_error[error_bin(err)];
            e.worst_distance_error = std::max(e.worst_distance_error, err);
            if (x.lower > 1e-6 * size) {
                const double rel = off / x.lower;
                ++e.distances_far;
                ++e.distance_error_far[error_bin(rel)];
                e.worst_distance_error_far = std::max(e.worst_distance_error_far, rel);
            }
        }
        if (ans.colliding != apart) continue;  // agrees with the certificate
        // The certified gap: the distance's lower end, or the depth's lower bound.
        const double gap = apart ? x.lower : x.depth_lower;
        const double rel = gap / size;
        ++e.disagree_by_gap[rel <= 1e-15 ? 0 : rel <= 1e-12 ? 1 : rel <= 1e-10 ? 2 : rel <= 1e-9 ? 3 : 4];
        // Beyond the band (wrong), within it, or undecided against it: apart, the interval against the band;
        // overlapping, the depth bound, else the six points ±√3·band·size tested in B − A (once per case).
        int beyond;  // +1 beyond the band, −1 within, 0 undecided
        if (apart) {
            beyond = x.lower > band ? 1 : x.upper <= band ? -1 : 0;
        } else if (x.depth_lower > band) {
            beyond = 1;
        } else {
            if (depth_class == 2) depth_class = oracle.curved_depth(sa, pa, sb, pb, band);
            beyond = depth_class;
        }
        if (beyond < 0) {
            ++e.disagree_band;
            continue;
        }
        if (beyond == 0) {
            ++e.disagree_undecided;
            continue;
        }
        ++e.wrong;
        if (e.wrong_described < 12) {
            char line[360];
            std::snprintf(line, sizeof line,
                          "  curved: %s wrong, %s placement, size %.3g, |t_a| %.3g: answered %s; certified %s, %s "
                          "%.17g; ",
                          ans.name, placement_names[m], size, pa.t.norm(), ans.colliding ? "colliding" : "apart",
                          apart ? "apart" : "overlapping", apart ? "distance >=" : "depth >", gap);
            e.first_wrong += line + describe(a) + " / " + describe(b) + "\n";
            ++e.wrong_described;
        }
    }
}

template <class A, class AL, class B, class BL>
void run_case(const A& a, const AL& al, const B& b, const BL& bl, Placement m, std::mt19937_64& rng, Counts& c,
              const ExactOracle& oracle = {}) {
    const double size = a.bounding_radius() + b.bounding_radius();
    // One draw per statement: the order of a call's arguments is unspecified, and the corpus must be the same
    // whichever compiler builds it.
    const double offset = size * std::pow(10.0, int(rng() % 4) - 1);
    const Mat3<double> ra = test::random_rotation(rng);
    Transform<double> pa(ra, test::random_unit(rng) * offset);
    Transform<double> pb = pa;
    bool placed = true;
    switch (m) {
        case touching: placed = test::place_near_contact(al, bl, size, 0.0, rng, pa, pb); break;
        case near_contact: {
            const double g[4] = {1e-9, -1e-9, 1e-12, -1e-12};
            placed = test::place_near_contact(al, bl, size, g[rng() % 4], rng, pa, pb);
            break;
        }
        case shallow: {
            const double g[4] = {1e-4, -1e-4, 1e-2, -1e-2};
            placed = test::place_near_contact(al, bl, size, g[rng() % 4], rng, pa, pb);
            break;
        }
        case nested:
        case coincident: pb = pa; break;  // coincident: the caller passes the same shape twice
        default: placed = false; break;
    }
    if (!placed) {  // random pose (also where long double gave no normal to place along)
        const Mat3<double> rb = test::random_rotation(rng);
        const Vec3<double> u = test::random_unit(rng);
        pb = Transform<double>(rb, pa.t + u * (size * std::uniform_real_distribution<double>(0, 2)(rng)));
        c.placed_random += m != random_pose;
    }
    ++c.cases;
    ++c.by_placement[std::size_t(m)];
    const auto t0 = Clock::now();
    GjkSettings<LD> exact;
    exact.rel_tolerance = LD(1e-16);
    const Transform<LD> pal(pa.R.cast<LD>(), pa.t.cast<LD>()), pbl(pb.R.cast<LD>(), pb.t.cast<LD>());
    const auto ref = gjk_distance(al, pal, bl, pbl, nullptr, exact);
    const bool ref_overlap = ref.status == GjkStatus::intersecting;
    const bool decisive = ref_overlap || (ref.status == GjkStatus::separated && ref.distance > LD(1e-9 * size));
    c.decisive += decisive;
    c.colliding += ref.colliding;

    const auto cold = gjk_intersect(a, pa, b, pb);
    GjkCache<double> bool_cache, dist_cache;
    (void)gjk_intersect(a, pa, b, pb, &bool_cache);
    const auto warm = gjk_intersect(a, pa, b, pb, &bool_cache);
    const auto dist = gjk_distance(a, pa, b, pb);
    (void)gjk_distance(a, pa, b, pb, &dist_cache);
    const auto warm_dist = gjk_distance(a, pa, b, pb, &dist_cache);

    auto finite = [](const GjkResult<double>& r) {
        if (!std::isfinite(r.distance)) return false;
        if (r.status == GjkStatus::separated || r.status == GjkStatus::touching)
            return r.normal.allFinite() && r.point_a.allFinite() && r.point_b.allFinite();
        return true;
    };
    // One query's verdict: finite numbers, a status a query may give on finite shapes, and where long double is
    // decisive the same overlap answer (boolean queries count as wrong booleans, distance queries as wrong
    // distance statuses); the first dozen failures are described.
    std::vector<Answer> answers;  // for the exact judge
    auto judge = [&](const char* name, bool finite_values, GjkStatus st, bool colliding, bool distance_query,
                     double distance, int iterations) {
        answers.push_back({name, colliding, distance_query, st, distance});
        const long before = c.failures();
        c.nonfinite += !finite_values;
        c.bad_status += !(st == GjkStatus::separated || st == GjkStatus::touching || st == GjkStatus::intersecting);
        if (decisive && colliding != ref_overlap) {
            if (distance_query) ++c.wrong_distance_status;
            else ++c.wrong_boolean;
        }
        if (c.failures() > before && c.described < 12) {
            char line[320];
            std::snprintf(line, sizeof line,
                          "  failure: %s, %s placement, size %.3g, |t_a| %.3g: status %d colliding %d distance %.17g "
                          "it %d; long double status %d distance %.17Lg; ",
                          name, placement_names[m], size, pa.t.norm(), int(st), int(colliding), distance, iterations,
                          int(ref.status), ref.distance);
            c.first_failures += line + describe(a) + " / " + describe(b) + "\n";
            ++c.described;
        }
    };
    const char* const query_names[4] = {"cold boolean", "warm boolean", "distance", "warm distance"};
    int q = 0;
    for (const auto* r : {&cold, &warm, &dist, &warm_dist}) {
        judge(query_names[q], finite(*r), r->status, r->colliding, q >= 2, r->distance, r->iterations);
        ++q;
    }
    // The separating plane and, for two hulls, the closest-feature walk: cold, and after a query at B moved half a
    // size away along the centre line (a cached plane or feature pair from there, which near contact fails: then
    // the walk, or GJK from the handed-over support pair).
    Transform<double> pb_far = pb;
    {
        const Vec3<double> away = pb.t - pa.t;
        pb_far.t += 0.5 * size * (away.squaredNorm() > 0 ? Vec3<double>(away.normalized()) : Vec3<double>::UnitX());
    }
    {
        SeparatingPlaneCache<double> fresh, moved;
        const auto cold_plane = separating_plane_intersect(a, pa, b, pb, &fresh);
        (void)separating_plane_intersect(a, pa, b, pb_far, &moved);
        const auto warm_plane = separating_plane_intersect(a, pa, b, pb, &moved);
        for (const auto* r : {&cold_plane, &warm_plane})
            judge(r == &cold_plane ? "separating plane" : "separating plane (cached)", true,
                  r->used_gjk ? r->status : GjkStatus::separated, r->colliding, false, 0.0, r->iterations);
    }
    if constexpr (std::is_same_v<A, ConvexPolyhedron<double>> && std::is_same_v<B, ConvexPolyhedron<double>>) {
        ClosestFeatureCache<double> moved;
        const auto cold_walk = closest_features(a, pa, b, pb);
        (void)closest_features(a, pa, b, pb_far, &moved);
        const auto warm_walk = closest_features(a, pa, b, pb, &moved);
        for (const auto* r : {&cold_walk, &warm_walk}) {
            const bool finite_values = std::isfinite(r->distance) && r->point_a.allFinite() &&
                                       r->point_b.allFinite() && r->normal.allFinite();
            judge(r == &cold_walk ? "closest features" : "closest features (cached)", finite_values, r->status,
                  r->colliding, true, r->distance, r->iterations);
        }
    }
    // Separation distances against the certified interval (reported).
    if (ref.status == GjkStatus::separated && ref.distance > LD(1e-6 * size) && dist.status == GjkStatus::separated) {
        ++c.distance_checked;
        const auto [lower, upper] = test::certified_interval(al, pal, bl, pbl, ref, dist.normal);
        const LD d = LD(dist.distance);
        const bool outlier = d < lower * (1 - LD(1e-9)) || d > upper * (1 + LD(1e-9));
        c.distance_outliers += outlier;
        if (outlier && c.outliers_described < 12) {
            char line[320];
            std::snprintf(line, sizeof line,
                          "  off the interval: %s placement, size %.3g, |t_a| %.3g: distance %.17g it %d; certified "
                          "[%.17Lg, %.17Lg] (relative %.2Lg); ",
                          placement_names[m], size, pa.t.norm(), dist.distance, dist.iterations, lower, upper,
                          (d < lower ? lower - d : d - upper) / upper);
            c.first_outliers += line + describe(a) + " / " + describe(b) + "\n";
            ++c.outliers_described;
        }
    }
    PenetrationResult<double> epa_result;
    bool epa_ran = false;
    if (ref_overlap || cold.colliding) {
        ++c.epa_runs;
        const auto p = penetration(a, pa, b, pb);
        epa_result = p, epa_ran = true;
        ++c.epa_status[std::size_t(p.status)];
        const bool ok_numbers = std::isfinite(p.depth) && std::isfinite(p.distance) && p.normal.allFinite() &&
                                p.point_a.allFinite() && p.point_b.allFinite();
        c.nonfinite += !ok_numbers;
        c.bad_depth += !(p.depth >= 0) || (p.depth > 0 && !(std::abs(p.normal.norm() - 1) <= 1e-9));
        if (ref_overlap) {
            // h(n): D's support value along the reported normal, in long double — the translation along n that
            // separates is at most h(n), and the true depth is the least h over all directions.
            const LD h = -test::supporting_plane_gap(al, pal, bl, pbl, p.normal.template cast<LD>());
            const LD deep = LD(1e-9 * size);
            if (p.status == GjkStatus::separated || p.status == GjkStatus::touching) {
                c.epa_wrong_status[std::size_t(m)] += h > deep;
            } else if (h > deep) {
                ++c.epa_checked;
                // The bracket [depth_lower, depth] EPA reports, and its depth against h(n) (it must be that value).
                const LD gap = (LD(p.depth) - LD(p.depth_lower)) / LD(p.depth);
                const bool off = std::abs(h - LD(p.depth)) > LD(1e-9) * h + LD(1e-12 * size);
                c.epa_loose[std::size_t(m)] += gap > LD(1e-3);
                c.epa_gap[std::size_t(p.status)][std::size_t(off ? 4 : gap <= LD(1e-9) ? 0 : gap <= LD(1e-6) ? 1 : gap <= LD(1e-3) ? 2 : 3)]++;
            } else {
                ++c.epa_shallow;
                c.epa_shallow_off += std::abs(h - LD(p.depth)) > LD(1e-12 * size);
            }
        }
    }
    c.slowest_us = std::max(c.slowest_us, std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    if constexpr (is_polytope_v<A> && is_polytope_v<B>) {
        if (oracle.pair != nullptr)
            judge_exactly(oracle, a, pa, b, pb, size, m, answers, epa_ran ? &epa_result : nullptr, c.exact);
    } else if (oracle.curved != nullptr) {
        judge_curved(oracle, a, pa, b, pb, size, m, answers, Vec3<double>(ref.normal.template cast<double>()),
                     c.curved);
    } else {
        c.exact.not_judged += oracle.pair != nullptr;
    }
}

/// One case of the class pair (KA, KB), make's classes or −1 for a hull from the pool.
template <int KA, int KB>
void primitive_pair(std::mt19937_64& rng, const HullPool& hulls, Placement m, Counts& c, const ExactOracle& oracle) {
    auto scale_b = [&] { return std::pow(10.0, std::uniform_int_distribution<int>(-6, 6)(rng)); };
    auto hull_index = [&](double s) {
        const int kind = std::uniform_int_distribution<int>(0, HullPool::kinds - 1)(rng);
        return kind * HullPool::scales + int(std::lround(std::log10(s))) + 6;
    };
    if constexpr (KA < 0 && KB < 0) {
        const int ia = hull_index(1.0), ib = m == coincident ? ia : hull_index(scale_b());
        run_case(hulls.d[std::size_t(ia)], hulls.l[std::size_t(ia)], hulls.d[std::size_t(ib)],
                 hulls.l[std::size_t(ib)], m, rng, c, oracle);
    } else if constexpr (KA < 0) {
        const int ia = hull_index(1.0);
        const ShapeDraw pb = draw_extents(KB, scale_b(), rng);
        run_case(hulls.d[std::size_t(ia)], hulls.l[std::size_t(ia)], shape_of(make<KB, double>(pb)),
                 shape_of(make<KB, LD>(pb)), m == coincident ? nested : m, rng, c, oracle);
    } else if constexpr (KB < 0) {
        const ShapeDraw pa = draw_extents(KA, 1.0, rng);
        const int ib = hull_index(scale_b());
        run_case(shape_of(make<KA, double>(pa)), shape_of(make<KA, LD>(pa)), hulls.d[std::size_t(ib)],
                 hulls.l[std::size_t(ib)], m == coincident ? nested : m, rng, c, oracle);
    } else {
        const ShapeDraw pa = draw_extents(KA, 1.0, rng);
        const ShapeDraw pb = (KA == KB && m == coincident) ? pa : draw_extents(KB, scale_b(), rng);
        run_case(shape_of(make<KA, double>(pa)), shape_of(make<KA, LD>(pa)), shape_of(make<KB, double>(pb)),
                 shape_of(make<KB, LD>(pb)), KA == KB ? m : (m == coincident ? nested : m), rng, c, oracle);
    }
}

/// The class pairs (−1: a hull): every class against a regular partner and against itself, hulls against all.
using PairRun = void (*)(std::mt19937_64&, const HullPool&, Placement, Counts&, const ExactOracle&);
inline constexpr std::array<PairRun, 20> pair_runs = {
    primitive_pair<0, 0>,  primitive_pair<0, 1>,   primitive_pair<1, 3>,   primitive_pair<2, 0>, primitive_pair<2, 2>,
    primitive_pair<3, 3>,  primitive_pair<4, 1>,   primitive_pair<4, 4>,   primitive_pair<5, 0>, primitive_pair<-1, -1>,
    primitive_pair<-1, 0>, primitive_pair<3, -1>,  primitive_pair<-1, 4>,  primitive_pair<5, -1>, primitive_pair<-1, 2>,
    primitive_pair<6, 6>,  primitive_pair<6, 0>,   primitive_pair<-1, 6>,  primitive_pair<7, 7>, primitive_pair<-1, 7>};
inline constexpr std::array<const char*, 20> pair_names = {
    "box-box",   "box-cyl",  "cyl-cone",  "caps-box", "caps-caps", "cone-cone", "ell-cyl",
    "ell-ell",   "sph-box",  "hull-hull", "hull-box", "cone-hull", "hull-ell",  "sph-hull",
    "hull-caps", "tri-tri",  "tri-box",   "hull-tri", "rbox-rbox", "hull-rbox"};

/// `cases` seeded cases, cycling through the class pairs; counts per pair. With an oracle, the polytope cases are
/// judged exactly too (Counts::exact); the corpus is the same either way.
inline std::array<Counts, pair_runs.size()> run_hard_cases(long cases, unsigned long seed,
                                                           const ExactOracle& oracle = {}) {
    std::mt19937_64 rng(seed);
    const HullPool hulls(rng);
    std::array<Counts, pair_runs.size()> per_pair{};
    for (long i = 0; i < cases; ++i) {
        const std::size_t p = std::size_t(i) % pair_runs.size();
        const auto m = Placement(std::uniform_int_distribution<int>(0, placements - 1)(rng));
        pair_runs[p](rng, hulls, m, per_pair[p], oracle);
    }
    return per_pair;
}

}  // namespace cdkit::test::hard
