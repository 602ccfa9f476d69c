// cdkit_bench_convex_toi: convex time of impact (issue 34 item 4). cdkit's convex_toi (conservative advancement on
// warm GJK distance) against FCL 0.7's fcl::continuousCollide with CCDC_CONSERVATIVE_ADVANCEMENT on the same shapes
// and the same motions, in one process, and a tunnelling count over many seeded fast pairs judged by a reference
// that shares no code with either advancement.
//
//   cdkit_bench_convex_toi [--pairs N] [--timed M] [--seed S] [--csv FILE]
//
// Pairs: each shape a sphere, box, capsule, cylinder, cone or hull (24 random points), sizes 1e-3 … 1e3
// (log-uniform, so size ratios up to 1e6), both moving. A's origin crosses a point near B's surface at a random
// time, travelling 0.1 … 100 of the smaller size per step (log-uniform) from outside; B drifts by up to its own
// size. Two classes of motion:
//   translation  the shape cast: both keep their rotations (FCL: CCDM_TRANS);
//   rotation     each also turns by up to π about a random axis, its origin on a straight line (FCL: CCDM_LINEAR,
//                its InterpMotion: the same motion as cdkit's, rotation about the origin at a constant rate; the
//                motions are built with the reference point set, see fcl#662 below).
// Reference: FCL's discrete collide (libccd's GJK) at 17 evenly spaced instants and at the crossing instant, the
// poses interpolated by the bench itself (Eigen's slerp). A contact it sees is certain; the first instant with one
// is narrowed by bisection against the instant before it without one, to the reference time s (an upper bound on
// the first contact). A method misses a certain contact when it reports none, and is late when its time of contact
// comes after s.
// Accuracy: how early each reported time is, s − toi (median and max over the certain contacts it reported).
// Each pair is drawn from its own generator (seeded by the seed, the class and its index), so the counts do not
// depend on threads: the first M pairs of each class run one by one and are timed, each query warm (one untimed
// run, then the fastest of 3); the others only count, on every core (TBB). Rows:
//   cdkit convex_toi         the default tolerance (1e-6, absolute distance): a GJK ray cast for translations,
//                            conservative advancement when a shape turns;
//   cdkit advancement        conservative advancement for translations too (the ray cast off);
//   cdkit convex_toi at FCL's stop  tolerance 1e-4 × the pair's motion bound (|v_A − v_B| + |ω_A| r_A + |ω_B| r_B),
//                            FCL's own stopping rule (it stops when an advancement step is under 1e-4 of the step);
//   FCL CA libccd            fcl::continuousCollide, its default GJK (libccd);
//   FCL CA indep             the same with FCL's own GJK (GST_INDEP).
#include "../fcl_pose.hpp"
#include "../bench_util.hpp"
#include "../provenance.hpp"

#include <cdkit/ccd/convex_toi.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>

#include <fcl/fcl.h>
#if defined(CDKIT_HAS_TBB)
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <variant>
#include <vector>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;
using cdbench::median;
using cdbench::random_rotation;

using Shape = std::variant<cdkit::Sphere<double>, cdkit::Box<double>, cdkit::Capsule<double>, cdkit::Cylinder<double>,
                           cdkit::Cone<double>, const cdkit::ConvexPolyhedron<double>*>;
constexpr const char* kind_names[] = {"sphere", "box", "capsule", "cylinder", "cone", "hull"};

/// A hull built once: cdkit's polyhedron and FCL's Convex of the same triangles.
struct Hull {
    double size;
    std::unique_ptr<cdkit::ConvexPolyhedron<double>> cdkit_hull;
    std::shared_ptr<fcl::Convexd> fcl_hull;
};

/// One pair's shapes in both libraries. FCL's capsule, cylinder and cone take the full length where cdkit keeps the
/// half, its box full sides; both have their axes along z and the cone's apex at +z.
struct PairShapes {
    Shape a, b;
    std::shared_ptr<fcl::CollisionGeometryd> fa, fb;
    double size_a = 0, size_b = 0;
};

std::pair<Shape, std::shared_ptr<fcl::CollisionGeometryd>> make_shape(int kind, double s, const Hull* hull) {
    switch (kind) {
        case 0: return {cdkit::Sphere<double>(s), std::make_shared<fcl::Sphered>(s)};
        case 1: return {cdkit::Box<double>(V(s, 0.6 * s, 0.3 * s)), std::make_shared<fcl::Boxd>(2 * s, 1.2 * s, 0.6 * s)};
        case 2: return {cdkit::Capsule<double>(0.4 * s, 0.6 * s), std::make_shared<fcl::Capsuled>(0.4 * s, 1.2 * s)};
        case 3: return {cdkit::Cylinder<double>(0.5 * s, 0.5 * s), std::make_shared<fcl::Cylinderd>(0.5 * s, s)};
        case 4: return {cdkit::Cone<double>(0.6 * s, 0.5 * s), std::make_shared<fcl::Coned>(0.6 * s, s)};
        default: return {hull->cdkit_hull.get(), hull->fcl_hull};
    }
}

template <class F> decltype(auto) visit_shape(const Shape& s, F&& f) {
    return std::visit(
        [&](const auto& x) -> decltype(auto) {
            if constexpr (std::is_pointer_v<std::decay_t<decltype(x)>>) return f(*x);
            else return f(x);
        },
        s);
}

using cdbench::to_fcl;

/// The pose at time t of a motion from `start` to `end`: the origin on the straight line, the rotation along the
/// shortest arc at a constant rate (Eigen's slerp), the motion cdkit's convex_toi and FCL's InterpMotion describe.
/// The reference computes its poses here, not by either library's motion code.
T pose_at(const T& start, const T& end, double t) {
    const Eigen::Quaterniond q0(start.R), q1(end.R);
    return T(q0.slerp(t, q1).toRotationMatrix(), (1 - t) * start.t + t * end.t);
}

/// What one method answered for one pair.
struct Answer {
    bool colliding = false;
    double toi = 1;
};

/// One method's tally over a class of motions.
struct Tally {
    const char* name;
    long contacts = 0, missed = 0, late = 0, capped = 0;
    std::vector<double> us;
    std::vector<double> early;  ///< reference contact time − reported time, over certain contacts the method reported
    double late_by = 0;         ///< the largest reported time after the reference contact time
    void add(const Tally& o) {
        contacts += o.contacts, missed += o.missed, late += o.late, capped += o.capped;
        us.insert(us.end(), o.us.begin(), o.us.end());
        early.insert(early.end(), o.early.begin(), o.early.end());
        late_by = std::max(late_by, o.late_by);
    }
};

/// Every method's tally over a class, and the certain contacts.
struct Sums {
    Tally tallies[5] = {{"cdkit convex_toi"},
                        {"cdkit advancement"},
                        {"cdkit convex_toi at FCL's stop"},
                        {"FCL CA libccd"},
                        {"FCL CA indep"}};
    long certain = 0;
    void add(const Sums& o) {
        for (int m = 0; m < 5; ++m) tallies[m].add(o.tallies[m]);
        certain += o.certain;
    }
};

}  // namespace

int main(int argc, char** argv) try {
    long pairs = 100000, timed = 5000;
    std::uint64_t seed = 1;
    std::string csv;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--pairs" && i + 1 < argc) pairs = std::stol(argv[++i]);
        else if (a == "--timed" && i + 1 < argc) timed = std::stol(argv[++i]);
        else if (a == "--seed" && i + 1 < argc) seed = std::stoull(argv[++i]);
        else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
        else throw std::invalid_argument("unknown argument " + a + " (usage: [--pairs N] [--timed M] [--seed S] "
                                         "[--csv FILE])");
    }
    if (pairs < 1 || timed < 0) throw std::invalid_argument("--pairs must be ≥ 1 and --timed ≥ 0");
    std::FILE* out = nullptr;
    if (!csv.empty()) {
        out = std::fopen(csv.c_str(), "w");
        if (!out) throw std::runtime_error("cannot write " + csv);
        cdbench::write_provenance(out, argc, argv);
        std::fprintf(out, "motion,method,pairs,certain_contacts,contacts,missed,late,capped,timed,median_us,p99_us,"
                          "max_us,fcl_over_this,median_early,max_early,max_late\n");
    }

    // A pool of hulls of every size (qhull and FCL's Convex are built once, not per pair).
    std::mt19937_64 pool_rng(seed ^ 0x9e3779b97f4a7c15ULL);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<Hull> hulls(256);
    for (Hull& h : hulls) {
        h.size = std::pow(10.0, -3 + 6 * unit(pool_rng));
        h.cdkit_hull = std::make_unique<cdkit::ConvexPolyhedron<double>>(cdbench::random_cloud(pool_rng, 24, h.size));
        auto v = std::make_shared<std::vector<fcl::Vector3d>>(h.cdkit_hull->vertices().begin(),
                                                              h.cdkit_hull->vertices().end());
        auto faces = std::make_shared<std::vector<int>>();
        for (const auto& t : h.cdkit_hull->triangles()) faces->insert(faces->end(), {3, int(t[0]), int(t[1]), int(t[2])});
        h.fcl_hull = std::make_shared<fcl::Convexd>(v, int(h.cdkit_hull->triangles().size()), faces);
    }

    std::printf("%-11s %-30s %8s %8s %8s %6s %5s %6s %9s %9s %9s %7s %10s %10s %8s\n", "motion", "method", "pairs",
                "certain", "contacts", "missed", "late", "capped", "median_us", "p99_us", "max_us", "FCL/x",
                "med_early", "max_early", "max_late");
    for (const bool rotate : {false, true}) {
        // One pair of draw k (its own generator, so the answers do not depend on threads or order), redrawn until
        // the shapes start apart; its answers added to `sums`.
        auto one_pair = [&](long k, bool time_it, Sums& sums) {
            std::seed_seq seq{seed, std::uint64_t(rotate), std::uint64_t(k)};
            std::mt19937_64 rng(seq);
            std::uniform_real_distribution<double> unit(0, 1);
            for (;;) {
                // Shapes.
                const int ka = int(unit(rng) * 6), kb = int(unit(rng) * 6);
                const Hull* ha = &hulls[std::size_t(unit(rng) * double(hulls.size()))];
                const Hull* hb = &hulls[std::size_t(unit(rng) * double(hulls.size()))];
                const double sa = ka == 5 ? ha->size : std::pow(10.0, -3 + 6 * unit(rng));
                const double sb = kb == 5 ? hb->size : std::pow(10.0, -3 + 6 * unit(rng));
                const auto shape_a = make_shape(ka, sa, ha), shape_b = make_shape(kb, sb, hb);
                const Shape &a = shape_a.first, &b = shape_b.first;
                const auto &fa = shape_a.second, &fb = shape_b.second;
                const double small = std::min(sa, sb);

                // Motion: A's origin passes a point q near B's surface (B's support point along a random direction, in
                // B's frame at the crossing instant) at time tc, heading inwards, travelling 0.1 … 100 small sizes.
                const cdkit::Mat3<double> ra0 = random_rotation(rng), rb0 = random_rotation(rng);
                const cdkit::Mat3<double> ra1 =
                    rotate ? cdkit::Mat3<double>(Eigen::AngleAxisd(M_PI * unit(rng), random_rotation(rng).col(0)) * ra0)
                           : ra0;
                const cdkit::Mat3<double> rb1 =
                    rotate ? cdkit::Mat3<double>(Eigen::AngleAxisd(M_PI * unit(rng), random_rotation(rng).col(0)) * rb0)
                           : rb0;
                const V bt0 = random_rotation(rng).col(0) * (sb * unit(rng) * 4);
                const V bt1 = bt0 + random_rotation(rng).col(0) * (sb * unit(rng));
                const double tc = unit(rng);
                const V d = random_rotation(rng).col(0);
                const T b_tc = cdkit::detail::PoseMotion(T(rb0, bt0), T(rb1, bt1)).at(tc);
                const V q = visit_shape(b, [&](const auto& s) { return V(b_tc.R * s.support(b_tc.R.transpose() * d)); });
                const V qw = q + b_tc.t + random_rotation(rng).col(0) * (sa * unit(rng));
                V u = random_rotation(rng).col(0);
                if (u.dot(d) > 0) u = -u;
                const double travel = small * std::pow(10.0, -1 + 3 * unit(rng));
                const V at0 = qw - tc * travel * u, at1 = qw + (1 - tc) * travel * u;
                const T a0(ra0, at0), a1(ra1, at1), b0(rb0, bt0), b1(rb1, bt1);
                {
                    // Every pair starts apart: a contact at t = 0 is a discrete test, not a time of impact.
                    fcl::CollisionRequestd req;
                    fcl::CollisionResultd res;
                    if (fcl::collide(fa.get(), to_fcl(a0), fb.get(), to_fcl(b0), req, res) > 0) continue;
                }

                // Reference: FCL's discrete collide at 17 instants and at tc; the first instant it sees an overlap is
                // narrowed by bisection against the last instant before it without one (poses by the bench's own
                // interpolation, below).
                auto seen_at = [&](double t) {
                    fcl::CollisionRequestd req;
                    fcl::CollisionResultd res;
                    return fcl::collide(fa.get(), to_fcl(pose_at(a0, a1, t)), fb.get(), to_fcl(pose_at(b0, b1, t)), req,
                                        res) > 0;
                };
                double first_seen = 2, clear_before = 0;
                for (int i = 1; i <= 16 && first_seen > 1; ++i) {
                    if (seen_at(i / 16.0)) first_seen = i / 16.0;
                    else clear_before = i / 16.0;
                }
                if (tc > clear_before && tc < first_seen && seen_at(tc)) first_seen = tc;
                if (first_seen <= 1) {
                    for (int i = 0; i < 48 && first_seen - clear_before > 1e-15; ++i) {
                        const double mid = 0.5 * (clear_before + first_seen);
                        (seen_at(mid) ? first_seen : clear_before) = mid;
                    }
                    ++sums.certain;
                }

                // The four methods.
                const double spin = cdkit::detail::PoseMotion(a0, a1).angle *
                                        visit_shape(a, [](const auto& s) { return cdkit::detail::radius_about_origin(s); }) +
                                    cdkit::detail::PoseMotion(b0, b1).angle *
                                        visit_shape(b, [](const auto& s) { return cdkit::detail::radius_about_origin(s); });
                const double bound = ((a1.t - a0.t) - (b1.t - b0.t)).norm() + spin;
                cdkit::ToiRequest fcl_stop;
                fcl_stop.tolerance = std::max(1e-4 * bound, 1e-300);
                for (int m = 0; m < 5; ++m) {
                    Tally& tally = sums.tallies[m];
                    Answer ans;
                    bool capped = false;
                    auto run = [&] {
                        if (m < 3) {
                            const cdkit::ToiResult r = visit_shape(a, [&](const auto& x) {
                                return visit_shape(b, [&](const auto& y) {
                                    if (m == 1)
                                        return cdkit::detail::convex_toi_advancement(x, cdkit::detail::PoseMotion(a0, a1), y,
                                                                                     cdkit::detail::PoseMotion(b0, b1), {});
                                    return cdkit::convex_toi(x, a0, a1, y, b0, b1, m == 0 ? cdkit::ToiRequest{} : fcl_stop);
                                });
                            });
                            ans = {r.colliding, r.toi};
                            capped = r.capped;
                        } else {
                            fcl::ContinuousCollisionRequestd req;
                            req.ccd_solver_type = fcl::CCDC_CONSERVATIVE_ADVANCEMENT;
                            req.ccd_motion_type = rotate ? fcl::CCDM_LINEAR : fcl::CCDM_TRANS;
                            req.gjk_solver_type = m == 3 ? fcl::GST_LIBCCD : fcl::GST_INDEP;
                            fcl::ContinuousCollisionResultd res;
                            if (rotate) {
                                // FCL's CCDM_LINEAR builds InterpMotion(tf1, tf2), which leaves its reference point
                                // uninitialised (fcl#662): the motions are built here with the reference point at the
                                // origin, the motion both sides are asked about.
                                const fcl::InterpMotion<double> ma(a0.R, a0.t, a1.R, a1.t, V::Zero()),
                                    mb(b0.R, b0.t, b1.R, b1.t, V::Zero());
                                fcl::continuousCollide<double>(fa.get(), &ma, fb.get(), &mb, req, res);
                            } else {
                                fcl::continuousCollide(fa.get(), to_fcl(a0), to_fcl(a1), fb.get(), to_fcl(b0),
                                                       to_fcl(b1), req, res);
                            }
                            ans = {res.is_collide, res.is_collide ? res.time_of_contact : 1.0};
                        }
                    };
                    if (time_it) tally.us.push_back(1e6 * cdbench::warm_best_seconds(run));
                    else run();
                    tally.contacts += ans.colliding;
                    tally.capped += capped;
                    if (first_seen <= 1) {
                        tally.missed += !ans.colliding;
                        tally.late += ans.colliding && ans.toi > first_seen;
                    }
                    if (first_seen <= 1 && ans.colliding) {
                        tally.early.push_back(std::max(0.0, first_seen - ans.toi));
                        tally.late_by = std::max(tally.late_by, ans.toi - first_seen);
                    }
                }
                return;
            }
        };
        Sums total;
        for (long k = 0; k < std::min(timed, pairs); ++k) one_pair(k, true, total);
        // The untimed pairs on every core: they only count.
#if defined(CDKIT_HAS_TBB)
        tbb::enumerable_thread_specific<Sums> partial;
        tbb::parallel_for(tbb::blocked_range<long>(std::min(timed, pairs), pairs), [&](const tbb::blocked_range<long>& r) {
            Sums& mine = partial.local();
            for (long k = r.begin(); k != r.end(); ++k) one_pair(k, false, mine);
        });
        for (const Sums& p : partial) total.add(p);
#else
        for (long k = std::min(timed, pairs); k < pairs; ++k) one_pair(k, false, total);
#endif
        const long certain = total.certain;
        const Tally* tallies = total.tallies;
        const char* motion = rotate ? "rotation" : "translation";
        const double fcl_median = median(tallies[3].us);
        for (int m = 0; m < 5; ++m) {
            const Tally& t = tallies[m];
            const double med = median(t.us), p99 = cdbench::quantile(t.us, 0.99);
            const double mx = t.us.empty() ? 0 : *std::max_element(t.us.begin(), t.us.end());
            const double ratio = med > 0 ? fcl_median / med : 0;
            const double early_med = median(t.early);
            const double early_max = t.early.empty() ? 0 : *std::max_element(t.early.begin(), t.early.end());
            std::printf("%-11s %-30s %8ld %8ld %8ld %6ld %5ld %6ld %9.3f %9.3f %9.1f %7.2f %10.2g %10.2g %8.2g\n", motion,
                        t.name, pairs, certain, t.contacts, t.missed, t.late, t.capped, med, p99, mx, ratio, early_med,
                        early_max, t.late_by);
            if (out)
                std::fprintf(out, "%s,%s,%ld,%ld,%ld,%ld,%ld,%ld,%zu,%.4f,%.4f,%.2f,%.3f,%.3g,%.3g,%.3g\n", motion,
                             t.name, pairs, certain, t.contacts, t.missed, t.late, t.capped, t.us.size(), med, p99, mx,
                             ratio, early_med, early_max, t.late_by);
        }
        std::fflush(stdout);
    }
    if (out) std::fclose(out);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "cdkit_bench_convex_toi: %s\n", e.what());
    return 2;
}
