#pragma once
// The exact referee for mesh–mesh disagreements: B's vertices are moved by the given (double) rotation and
// translation in exact rational arithmetic (CGAL's Epeck kernel), and every triangle pair whose padded
// boxes overlap is tested with CGAL's exact do_intersect. Slow: used only to settle a disagreement.
#include "cdkit/core/mesh.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <vector>

namespace cdkit::test {

using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;

/// Exact answer: does some triangle of a intersect some triangle of b moved by (R, t)? (touching counts)
/// Degenerate triangles are handled as the segment or point they are.
inline bool exact_meshes_intersect(const TriangleMesh<double>& a, const TriangleMesh<double>& b,
                                   const Mat3<double>& R, const Vec3<double>& t) {
    using K = ExactKernel;
    using P = K::Point_3;
    auto exact_move = [&](const Vec3<double>& v) {
        K::FT c[3];
        for (int i = 0; i < 3; ++i)
            c[i] = K::FT(R(i, 0)) * v.x() + K::FT(R(i, 1)) * v.y() + K::FT(R(i, 2)) * v.z() + K::FT(t[i]);
        return P(c[0], c[1], c[2]);
    };
    std::vector<P> pb;
    std::vector<Vec3<double>> approx_b;  // for the box prefilter only
    for (const auto& v : b.vertices) {
        pb.push_back(exact_move(v));
        approx_b.push_back(R * v + t);
    }
    std::vector<P> pa;
    for (const auto& v : a.vertices) pa.emplace_back(v.x(), v.y(), v.z());
    auto box = [](const std::vector<Vec3<double>>& vs, const Triangle& tr, double pad) {
        Vec3<double> lo = vs[tr[0]].cwiseMin(vs[tr[1]]).cwiseMin(vs[tr[2]]);
        Vec3<double> hi = vs[tr[0]].cwiseMax(vs[tr[1]]).cwiseMax(vs[tr[2]]);
        return std::make_pair(Vec3<double>(lo.array() - pad), Vec3<double>(hi.array() + pad));
    };
    auto as_object = [](const P& p, const P& q, const P& r) -> CGAL::Object {
        if (!CGAL::collinear(p, q, r)) return CGAL::make_object(K::Triangle_3(p, q, r));
        // Degenerate: the longest of the three segments, or a point.
        K::Segment_3 s[3] = {K::Segment_3(p, q), K::Segment_3(q, r), K::Segment_3(r, p)};
        int k = 0;
        for (int i = 1; i < 3; ++i)
            if (s[i].squared_length() > s[k].squared_length()) k = i;
        if (s[k].squared_length() == 0) return CGAL::make_object(p);
        return CGAL::make_object(s[k]);
    };
    auto intersects = [](const CGAL::Object& x, const CGAL::Object& y) {
        if (auto tx = CGAL::object_cast<K::Triangle_3>(&x)) {
            if (auto ty = CGAL::object_cast<K::Triangle_3>(&y)) return CGAL::do_intersect(*tx, *ty);
            if (auto sy = CGAL::object_cast<K::Segment_3>(&y)) return CGAL::do_intersect(*tx, *sy);
            return tx->has_on(*CGAL::object_cast<P>(&y));
        }
        if (auto sx = CGAL::object_cast<K::Segment_3>(&x)) {
            if (auto ty = CGAL::object_cast<K::Triangle_3>(&y)) return CGAL::do_intersect(*ty, *sx);
            if (auto sy = CGAL::object_cast<K::Segment_3>(&y)) return CGAL::do_intersect(*sx, *sy);
            return sx->has_on(*CGAL::object_cast<P>(&y));
        }
        const P& px = *CGAL::object_cast<P>(&x);
        if (auto ty = CGAL::object_cast<K::Triangle_3>(&y)) return ty->has_on(px);
        if (auto sy = CGAL::object_cast<K::Segment_3>(&y)) return sy->has_on(px);
        return px == *CGAL::object_cast<P>(&y);
    };
    // Rounding of approx_b is far below this padding for meshes of unit size.
    const double pad = 1e-9;
    for (std::size_t i = 0; i < a.triangles.size(); ++i) {
        const auto& ta = a.triangles[i];
        const auto [alo, ahi] = box(a.vertices, ta, pad);
        CGAL::Object oa;
        bool have_oa = false;
        for (std::size_t j = 0; j < b.triangles.size(); ++j) {
            const auto& tb = b.triangles[j];
            const auto [blo, bhi] = box(approx_b, tb, pad);
            if ((alo.array() > bhi.array()).any() || (blo.array() > ahi.array()).any()) continue;
            if (!have_oa) oa = as_object(pa[ta[0]], pa[ta[1]], pa[ta[2]]), have_oa = true;
            if (intersects(oa, as_object(pb[tb[0]], pb[tb[1]], pb[tb[2]]))) return true;
        }
    }
    return false;
}

}  // namespace cdkit::test
