// "Separated" is a claim that a separating plane exists: every GJK answer that says so must be backed by one.
// Pairs of all shape classes (box, sphere, capsule, cylinder, cone, ellipsoid, hull) are placed by long-double
// GJK at ±1e-9, ±1e-12 and 0 of their size, at random orientations, scale ratios up to 100 and poses up to 100
// sizes from the origin. For every "separated" answer of the cold boolean query (default, and without its
// ball / containment pre-tests), of the warm-start loop (a cache) and of gjk_distance, the answer's normal must
// give a long-double supporting-plane gap of at least −(rounding) (gjk_distance: its status only, see below); and
// no query may answer "separated" where long-double GJK proves the overlap (before the certification of the loops'
// plane-less exits, all four did for 1e-12 … 1e-9 overlaps of cones, cylinders and ellipsoids, and the warm-start
// loop reported its last direction instead of the one that proved the plane).
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "convex_reference.hpp"
#include "near_contact_pose.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <limits>
#include <random>

using namespace cdkit;

namespace {

using L = long double;

using test::random_unit;

/// Shape parameters drawn once per case; `make<K>` builds class K from them in double and in long double.
struct Params {
    double r1, r2, h, scale;
    const std::vector<Vec3<double>>* cloud;
};

constexpr int classes = 7;
const char* const class_names[classes] = {"box", "sphere", "capsule", "cylinder", "cone", "ellipsoid", "hull"};

template <int K, class S> auto make(const Params& p) {
    const S s = S(p.scale), r1 = S(p.r1) * s, r2 = S(p.r2) * s, h = S(p.h) * s;
    if constexpr (K == 0) return Box<S>(Vec3<S>(r1, h, r2));
    else if constexpr (K == 1) return Sphere<S>(r1);
    else if constexpr (K == 2) return Capsule<S>(r1 / 2, h);
    else if constexpr (K == 3) return Cylinder<S>(r1, h);
    else if constexpr (K == 4) return Cone<S>(r1, h);
    else if constexpr (K == 5) return Ellipsoid<S>(Vec3<S>(r1, h, r2));
    else {
        std::vector<Vec3<S>> pts;
        for (const Vec3<double>& q : *p.cloud) pts.push_back((q * p.scale).template cast<S>());
        return ConvexPolyhedron<S>(pts);
    }
}

struct Tally {
    int cases = 0, separated_answers = 0, unbacked = 0, wrong_separated = 0, overlaps_proven = 0;
    int apart_proven = 0, apart_answered_separated = 0, apart_touching = 0;
    double worst_gap = std::numeric_limits<double>::infinity();  // smallest plane gap of a boolean "separated", / size
};

/// One pair at the relative gaps; `rng` draws the poses.
template <class A, class AL, class B, class BL>
void run_pair(const A& a, const AL& a_l, const B& b, const BL& b_l, std::mt19937_64& rng, Tally& t) {
    GjkSettings<double> plain;
    plain.bounding_ball_test = false;
    plain.containment_test = false;
    GjkSettings<L> exact;
    exact.rel_tolerance = L(1e-16);
    const double size = a.bounding_radius() + b.bounding_radius();
    for (const double g : {1e-9, 1e-12, 0.0, -1e-12, -1e-9}) {
        Transform<double> pa, pb;
        if (!test::place_near_contact(a_l, b_l, size, g, rng, pa, pb)) continue;
        const Transform<L> pa_l(pa.R.template cast<L>(), pa.t.template cast<L>());
        ++t.cases;
        const Transform<L> pb_l(pb.R.template cast<L>(), pb.t.template cast<L>());
        const auto ref = gjk_distance(a_l, pa_l, b_l, pb_l, nullptr, exact);
        const bool overlap = ref.status == GjkStatus::intersecting;
        const bool apart = ref.status == GjkStatus::separated && ref.distance > L(1e-10 * size);
        t.overlaps_proven += overlap;
        t.apart_proven += apart;
        GjkCache<double> cache;
        const GjkResult<double> answers[4] = {gjk_intersect(a, pa, b, pb), gjk_intersect(a, pa, b, pb, nullptr, plain),
                                              gjk_intersect(a, pa, b, pb, &cache), gjk_distance(a, pa, b, pb)};
        for (int q = 0; q < 4; ++q) {
            const GjkResult<double>& r = answers[q];
            if (apart) {
                t.apart_answered_separated += r.status == GjkStatus::separated;
                t.apart_touching += r.status == GjkStatus::touching;
            }
            if (r.status != GjkStatus::separated) continue;
            ++t.separated_answers;
            t.wrong_separated += overlap;
            // gjk_distance's normal is its closest-point direction, which near contact carries the sub-simplex
            // step's rounding (a needle triangle's normal): its plane need not separate; the status must be right.
            if (q == 3) continue;
            // The booleans' claim itself: the planes orthogonal to the answer's normal through A's and B's extreme
            // points are apart, up to the double rounding of the support maps (a few ε of the size).
            const L gap = test::supporting_plane_gap(a_l, pa_l, b_l, pb_l, r.normal.template cast<L>());
            t.worst_gap = std::min(t.worst_gap, double(gap) / size);
            t.unbacked += !(gap >= L(-1e-13 * size));
        }
    }
}

template <int I, int J> void run_classes(std::mt19937_64& rng, const std::vector<std::vector<Vec3<double>>>& clouds,
                                         int orientations, Tally* tally) {
    std::uniform_real_distribution<double> u(0.05, 0.1);
    for (int k = 0; k < orientations; ++k) {
        // Scale ratios 0.01 … 100 between the two shapes (B scaled).
        const double s = std::pow(10.0, std::uniform_int_distribution<int>(-2, 2)(rng));
        const Params pa{u(rng), u(rng), u(rng), 1.0, &clouds[std::size_t(k) % clouds.size()]};
        const Params pb{u(rng), u(rng), u(rng), s, &clouds[std::size_t(k + 1) % clouds.size()]};
        run_pair(make<I, double>(pa), make<I, L>(pa), make<J, double>(pb), make<J, L>(pb), rng, tally[I * classes + J]);
    }
}

template <int I, int J> void all_pairs(std::mt19937_64& rng, const std::vector<std::vector<Vec3<double>>>& clouds,
                                       int orientations, Tally* tally) {
    if constexpr (I < classes) {
        if constexpr (J < classes) {
            run_classes<I, J>(rng, clouds, orientations, tally);
            all_pairs<I, J + 1>(rng, clouds, orientations, tally);
        } else {
            all_pairs<I + 1, I + 1>(rng, clouds, orientations, tally);
        }
    }
}

}  // namespace

TEST_CASE("every separated GJK answer is backed by a separating plane", "[gjk][certified]") {
    std::mt19937_64 rng(1905);
    std::vector<std::vector<Vec3<double>>> clouds(6);
    std::uniform_real_distribution<double> u(0.3, 1.0);
    for (auto& c : clouds)
        for (int i = 0; i < 40; ++i) c.push_back(random_unit(rng) * (0.1 * u(rng)));
    const int orientations = test::scaled(150, 15);
    Tally tally[classes * classes];
    all_pairs<0, 0>(rng, clouds, orientations, tally);
    Tally sum;
    for (int i = 0; i < classes; ++i)
        for (int j = i; j < classes; ++j) {
            const Tally& t = tally[i * classes + j];
            INFO(class_names[i] << "–" << class_names[j] << ": " << t.cases << " cases, " << t.separated_answers
                                << " separated answers, " << t.overlaps_proven << " proven overlaps, worst plane gap "
                                << t.worst_gap << " of the size");
            CHECK(t.wrong_separated == 0);
            CHECK(t.unbacked == 0);
            // Every class pair was placed and answered "separated" somewhere (no pass by never answering).
            CHECK(t.cases >= orientations * 5 * 8 / 10);
            CHECK(t.separated_answers > 0);
            sum.cases += t.cases;
            sum.overlaps_proven += t.overlaps_proven;
            sum.apart_proven += t.apart_proven;
            sum.apart_answered_separated += t.apart_answered_separated;
            sum.apart_touching += t.apart_touching;
        }
    // The certification is not bought by calling apart pairs touching: at 1e-9 of the size every query that
    // long double GJK sees apart by more than 1e-10 of the size answers "separated".
    INFO(sum.cases << " cases, " << sum.overlaps_proven << " proven overlaps, " << sum.apart_proven
                   << " proven apart (4 queries each): " << sum.apart_answered_separated << " answered separated, "
                   << sum.apart_touching << " touching");
    CHECK(sum.overlaps_proven >= sum.cases / 5);
    CHECK(sum.apart_proven >= sum.cases / 10);
    CHECK(sum.apart_answered_separated == 4 * sum.apart_proven);
}
