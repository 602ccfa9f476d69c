#include "peer_fcl.hpp"
#include "../fcl_pose.hpp"
#include "batch_timer.hpp"

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/narrowphase/contact_point.h>
#include <fcl/narrowphase/detail/gjk_solver_indep.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <type_traits>

namespace cdkit::bench {

namespace {
volatile double g_fcl_sink = 0;

using cdbench::to_fcl;

/// Calls f with the FCL shape of d. FCL's capsule, cylinder and cone have their axis along z like cdkit's,
/// with the full length lz where cdkit keeps the half; its cone has the apex at +lz/2 as cdkit's; its box
/// takes full sides. A Convex needs faces: cdkit's hull triangles (outward, counter-clockwise), encoded as
/// FCL's [3, i, j, k, 3, ...] list.
template <class F> void with_shape(const FclShapeDesc& d, F&& f) {
    using K = FclShapeDesc::Kind;
    switch (d.kind) {
        case K::ellipsoid: f(fcl::Ellipsoidd(d.size.x(), d.size.y(), d.size.z())); return;
        case K::box: f(fcl::Boxd(2 * d.size.x(), 2 * d.size.y(), 2 * d.size.z())); return;
        case K::capsule: f(fcl::Capsuled(d.size.x(), 2 * d.size.y())); return;
        case K::cylinder: f(fcl::Cylinderd(d.size.x(), 2 * d.size.y())); return;
        case K::cone: f(fcl::Coned(d.size.x(), 2 * d.size.y())); return;
        case K::convex: {
            if (!d.vertices || !d.triangles) throw std::invalid_argument("fcl_measure: convex without hull");
            auto v = std::make_shared<std::vector<fcl::Vector3d>>();
            v->reserve(d.vertices->size());
            for (const auto& p : *d.vertices) v->emplace_back(p.x(), p.y(), p.z());
            auto faces = std::make_shared<std::vector<int>>();
            faces->reserve(4 * d.triangles->size());
            for (const auto& t : *d.triangles) faces->insert(faces->end(), {3, int(t[0]), int(t[1]), int(t[2])});
            f(fcl::Convexd(v, int(d.triangles->size()), faces));
            return;
        }
    }
    throw std::invalid_argument("fcl_measure: unknown shape kind");
}

template <class A, class B>
void run(const A& sa, const fcl::Transform3d& ta, const B& sb, const fcl::Transform3d& tb, int reps, bool pen,
         FclPairResult& out) {
    const fcl::detail::GJKSolver_indep<double> indep;
    const fcl::detail::GJKSolver_libccd<double> lccd;
    std::vector<fcl::ContactPointd> contacts;
    contacts.reserve(4);
    bool h = false;
    double d = 0;
    // Witness points are asked for as cdkit's distance computes them (and FCL's capsuleCapsuleDistance
    // asserts that they are).
    fcl::Vector3d w1, w2;

    out.indep_bool.ns = time_ns(
        [&] {
            h = indep.shapeIntersect(sa, ta, sb, tb, nullptr);
            g_fcl_sink = g_fcl_sink + h;
        },
        reps);
    out.indep_bool.ok = true;
    out.indep_bool.hit = h;
    out.ccd_bool.ns = time_ns(
        [&] {
            h = lccd.shapeIntersect(sa, ta, sb, tb, nullptr);
            g_fcl_sink = g_fcl_sink + h;
        },
        reps);
    out.ccd_bool.ok = true;
    out.ccd_bool.hit = h;

    out.indep_dist.ns = time_ns(
        [&] {
            h = indep.shapeDistance(sa, ta, sb, tb, &d, &w1, &w2);
            g_fcl_sink = g_fcl_sink + d;
        },
        reps);
    out.indep_dist.ok = h;
    out.indep_dist.value = d;
    out.ccd_dist.ns = time_ns(
        [&] {
            h = lccd.shapeDistance(sa, ta, sb, tb, &d, &w1, &w2);
            g_fcl_sink = g_fcl_sink + d;
        },
        reps);
    out.ccd_dist.ok = h;
    out.ccd_dist.value = d;

    if (!pen) return;
    // The deepest contact (boxBoxIntersect reports several), as FCL's own single-contact overload picks it.
    // FCL's contact depth sign differs between its paths (its indep EPA stores -depth): magnitudes compared.
    auto depth = [&] {
        double m = 0;
        for (const auto& c : contacts) m = std::max(m, std::abs(c.penetration_depth));
        return m;
    };
    out.indep_pen.ns = time_ns(
        [&] {
            contacts.clear();
            h = indep.shapeIntersect(sa, ta, sb, tb, &contacts);
            g_fcl_sink = g_fcl_sink + depth();
        },
        reps);
    out.indep_pen.ok = h && !contacts.empty();
    out.indep_pen.hit = h;
    out.indep_pen.value = depth();
    out.ccd_pen.ns = time_ns(
        [&] {
            contacts.clear();
            h = lccd.shapeIntersect(sa, ta, sb, tb, &contacts);
            g_fcl_sink = g_fcl_sink + depth();
        },
        reps);
    out.ccd_pen.ok = h && !contacts.empty();
    out.ccd_pen.hit = h;
    out.ccd_pen.value = depth();
}
}  // namespace

FclPairResult fcl_measure(const FclShapeDesc& a, const Transform<double>& pa, const FclShapeDesc& b,
                          const Transform<double>& pb, int reps, bool with_penetration) {
    if (a.kind != b.kind) throw std::invalid_argument("fcl_measure: P3 pairs are of one shape kind");
    FclPairResult out;
    const fcl::Transform3d ta = to_fcl(pa), tb = to_fcl(pb);
    with_shape(a, [&](const auto& sa) {
        with_shape(b, [&](const auto& sb) {
            // Only same-kind pairs are instantiated: FCL's solver templates are costly to compile.
            if constexpr (std::is_same_v<std::decay_t<decltype(sa)>, std::decay_t<decltype(sb)>>)
                run(sa, ta, sb, tb, reps, with_penetration, out);
        });
    });
    return out;
}

}  // namespace cdkit::bench
