#pragma once
// Adapter from cdkit support-mapped shapes (placed by a pose) to libccd's C callbacks. Only tests and
// benchmarks include this: the library never links libccd.
#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/support.hpp>

#include <ccd/ccd.h>

namespace cdkit::bench {

/// A shape and its world pose as libccd's `const void* obj`.
struct CcdObject {
    const void* shape = nullptr;
    Transform<double> pose;
    Vec3<double> (*support_local)(const void*, const Vec3<double>&) = nullptr;
    Vec3<double> center_local = Vec3<double>::Zero();
};

template <SupportMapped Shape> CcdObject make_ccd_object(const Shape& s, const Transform<double>& pose) {
    return {&s, pose,
            [](const void* o, const Vec3<double>& d) { return Vec3<double>(static_cast<const Shape*>(o)->support(d)); },
            Vec3<double>(s.center())};
}

inline void ccd_support(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
    const auto* o = static_cast<const CcdObject*>(obj);
    Vec3<double> d(dir->v[0], dir->v[1], dir->v[2]);
    Vec3<double> p = o->pose * o->support_local(o->shape, Vec3<double>(o->pose.R.transpose() * d));
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
