#pragma once
/// \file The convex queries for the built-in shapes in double, compiled once into libcdkit.
///
/// GJK (`detail::gjk_query`: distance, boolean, warm-started, with its long-double refinement and certification)
/// and EPA (`detail::penetration_query`) instantiate a few hundred kilobytes of code per shape pair. Every
/// translation unit that used them for the eight built-in shapes compiled and optimised that code again — most
/// of the test suite's compile time (a narrow-phase test TU spent 3/4 of its time in the optimiser and code
/// generator on these instantiations). For the 64 ordered pairs of Sphere, Box, Capsule, Cylinder, Cone,
/// Ellipsoid, ConvexTriangle and ConvexPolyhedron in double, gjk.hpp and epa.hpp declare explicit instantiations
/// (`extern template`), which src/convex/queries_*.cpp define; user code calling gjk_distance, gjk_intersect or
/// penetration on those pairs links them instead of instantiating them. The answers are the same code compiled
/// with the library's flags. Other shapes, wrappers (Transformed, Inflated) and float instantiate as before.
///
/// Define CDKIT_NO_PRECOMPILED_QUERIES before including cdkit to instantiate everything in your own translation
/// units (e.g. to build them with other optimisation flags than the library's).

/// M(prefix, A, B) for every built-in shape B, with A fixed.
#define CDKIT_WITH_EACH_BUILTIN_SHAPE(M, prefix, A)                                                               \
    M(prefix, A, ::cdkit::Sphere<double>) M(prefix, A, ::cdkit::Box<double>) M(prefix, A, ::cdkit::Capsule<double>) \
    M(prefix, A, ::cdkit::Cylinder<double>) M(prefix, A, ::cdkit::Cone<double>)                                     \
    M(prefix, A, ::cdkit::Ellipsoid<double>) M(prefix, A, ::cdkit::ConvexTriangle<double>)                          \
    M(prefix, A, ::cdkit::ConvexPolyhedron<double>)

/// M(prefix, A, B) for every ordered pair of built-in shapes.
#define CDKIT_FOR_EACH_BUILTIN_PAIR(M, prefix)                                      \
    CDKIT_WITH_EACH_BUILTIN_SHAPE(M, prefix, ::cdkit::Sphere<double>)               \
    CDKIT_WITH_EACH_BUILTIN_SHAPE(M, prefix, ::cdkit::Box<double>)                  \
    CDKIT_WITH_EACH_BUILTIN_SHAPE(M, prefix, ::cdkit::Capsule<double>)              \
    CDKIT_WITH_EACH_BUILTIN_SHAPE(M, prefix, ::cdkit::Cylinder<double>)             \
    CDKIT_WITH_EACH_BUILTIN_SHAPE(M, prefix, ::cdkit::Cone<double>)                 \
    CDKIT_WITH_EACH_BUILTIN_SHAPE(M, prefix, ::cdkit::Ellipsoid<double>)            \
    CDKIT_WITH_EACH_BUILTIN_SHAPE(M, prefix, ::cdkit::ConvexTriangle<double>)       \
    CDKIT_WITH_EACH_BUILTIN_SHAPE(M, prefix, ::cdkit::ConvexPolyhedron<double>)

/// The explicit instantiation (prefix empty) or its declaration (prefix `extern`) of GJK for one pair; used in
/// namespace cdkit.
#define CDKIT_GJK_QUERY_INSTANCE(prefix, A, B)                                                                 \
    prefix template GjkResult<double> detail::gjk_query<A, B>(                                               \
        const A&, const ::cdkit::Transform<double>&, const B&, const ::cdkit::Transform<double>&,             \
        ::cdkit::GjkCache<double>*, const ::cdkit::GjkSettings<double>&, bool, bool, double) noexcept;

/// The same for EPA's queries (from scratch and from GJK's simplex; the long-double retry `refine_penetration` is
/// instantiated with them).
#define CDKIT_PENETRATION_QUERY_INSTANCE(prefix, A, B)                                                     \
    prefix template PenetrationResult<double> detail::penetration_query<A, B>(          \
        const A&, const ::cdkit::Transform<double>&, const B&, const ::cdkit::Transform<double>&,         \
        const ::cdkit::EpaSettings<double>&) noexcept;                                                     \
    prefix template void detail::refine_penetration<A, B>(                                        \
        const A&, const ::cdkit::Transform<double>&, const B&, const ::cdkit::Transform<double>&,         \
        const ::cdkit::EpaSettings<double>&, ::cdkit::PenetrationResult<double>&) noexcept;           \
    prefix template PenetrationResult<double> detail::penetration_from_simplex<A, B>(                   \
        const A&, const ::cdkit::Transform<double>&, const B&, const ::cdkit::Transform<double>&,         \
        const ::cdkit::GjkSimplex<double>&, const ::cdkit::EpaSettings<double>&) noexcept;
