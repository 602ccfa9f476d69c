#pragma once
// Adapter from cdkit support-mapped shapes (placed by a pose) to libccd's C callbacks. Only tests and
// benchmarks include this: the library never links libccd.
#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/support.hpp>

#include <ccd/ccd.h>

#include <cstdint>

namespace cdkit::bench {

/// A shape and its world pose as libccd's `const void* obj`.
struct CcdObject {
    const void* shape = nullptr;
    Transform<double> pose;
    /// The shape's support in its own frame; `hint` is the slot below (ignored unless the object was made hinted).
    Vec3<double> (*support_local)(const void*, const Vec3<double>&, std::uint32_t&) = nullptr;
    Vec3<double> center_local = Vec3<double>::Zero();
    /// The hint slot of a hinted object (issue 37): the hill-climbing start vertex of a shape with a hinted support
    /// (`HintedSupport`: hulls), updated by every support call, as cdkit's GJK keeps one per shape during a query.
    /// Set it to −1 before a query for a cold start (as cdkit's cold boolean starts); kept, it carries the last
    /// support vertex into the next query (as a `GjkCache` does between frames).
    mutable std::uint32_t hint = std::uint32_t(-1);
};

/// libccd's view of `s` placed by `pose`. `hinted`: the support goes through the shape's hinted query with the
/// object's hint slot (shapes without one: the same plain support either way).
template <SupportMapped Shape>
CcdObject make_ccd_object(const Shape& s, const Transform<double>& pose, bool hinted = false) {
    CcdObject o{&s, pose,
                [](const void* p, const Vec3<double>& d, std::uint32_t&) {
                    return Vec3<double>(static_cast<const Shape*>(p)->support(d));
                },
                Vec3<double>(s.center())};
    if constexpr (HintedSupport<Shape>) {
        if (hinted)
            o.support_local = [](const void* p, const Vec3<double>& d, std::uint32_t& h) {
                return Vec3<double>(static_cast<const Shape*>(p)->support(d, h));
            };
    }
    (void)hinted;
    return o;
}

inline void ccd_support(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
    const auto* o = static_cast<const CcdObject*>(obj);
    Vec3<double> d(dir->v[0], dir->v[1], dir->v[2]);
    Vec3<double> p = o->pose * o->support_local(o->shape, Vec3<double>(o->pose.R.transpose() * d), o->hint);
    out->v[0] = p.x(); out->v[1] = p.y(); out->v[2] = p.z();
}
inline void ccd_center(const void* obj, ccd_vec3_t* out) {
    const auto* o = static_cast<const CcdObject*>(obj);
    Vec3<double> p = o->pose * o->center_local;
    out->v[0] = p.x(); out->v[1] = p.y(); out->v[2] = p.z();
}
/// libccd settings as FCL uses them (bounded iterations; default tolerances).
inline ccd_t make_ccd() {
    ccd_t c;
    CCD_INIT(&c);
    c.support1 = ccd_support;
    c.support2 = ccd_support;
    c.center1 = ccd_center;
    c.center2 = ccd_center;
    c.max_iterations = 500;
    return c;
}

}  // namespace cdkit::bench
