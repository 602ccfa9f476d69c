// The hard-case count's one wrong boolean after the review of its corpus (cdkit_bench_convex_hard, 1M cases, seed 1):
// a regular 60-vertex hull (radius 0.1) and a needle ellipsoid (radii 1e-8, 1e-8, 0.00976) 11.5 from the origin,
// placed 1e-12 into overlap along a long-double normal, are in fact 3.46e-14 apart (an exact plane,
// test_gjk_exact_plane_cgal.cpp). Long-double GJK had answered "intersecting": its last tetrahedron had a face
// of three support points along the needle, whose rounded normal put the origin inside; the double cold boolean
// answered "separated", correctly. Values as hexadecimal literals: exact in every build.
#pragma once

#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>

#include <array>
#include <vector>

namespace cdkit::test::sliver_face {

inline constexpr std::array<std::array<double, 3>, 60> hull_points = {{
    {-0x1.be21328c0a124p-5, -0x1.2c7696357ff9bp-7, -0x1.55790664531e8p-4},
    {-0x1.1e4df22717ad7p-4, 0x1.24b9569b980b8p-4, -0x1.5688bea6941cfp-9},
    {-0x1.8ec0d70dbd6bap-4, 0x1.1002f119db2f5p-8, 0x1.7053327eb33fbp-6},
    {-0x1.5264ffeb0beb6p-4, -0x1.b7f692998ddfp-6, 0x1.95c663152e9a4p-5},
    {-0x1.d6e8e335e21e7p-5, -0x1.40433735d1831p-4, 0x1.8b45f7344217ep-6},
    {0x1.4925a416861p-4, -0x1.00692e78418a3p-5, 0x1.9eb7cf511f44cp-5},
    {0x1.6b658bc2e437p-4, 0x1.7763d46b31d37p-5, 0x1.60969b39e583ap-8},
    {0x1.84f7fcb844098p-4, 0x1.b1da675395437p-7, -0x1.d159b65995035p-6},
    {0x1.8157e62ef7056p-5, -0x1.fac4bdaadb4edp-5, 0x1.01c5880d404e7p-4},
    {0x1.e6fbeefb7d782p-6, -0x1.3c12f45c7e667p-12, 0x1.87161b9cd8b02p-4},
    {-0x1.6139aace54b37p-4, 0x1.550b2805bcf9fp-5, 0x1.d80a6220c7e1dp-6},
    {-0x1.ec336bedd2457p-5, 0x1.a37fba1da6c3dp-5, 0x1.f6d6eb69d4945p-5},
    {-0x1.3c62d92bc2e1cp-5, 0x1.7014a822c4db3p-4, 0x1.54e8eb672002bp-6},
    {0x1.75851db28ac7p-4, 0x1.3a065eb64c563p-10, -0x1.500a85e467fbdp-5},
    {0x1.e3f9c3daa0764p-5, -0x1.b6c66a7ec3175p-5, -0x1.ee4cd80efaec2p-5},
    {-0x1.4622e11e0e685p-5, 0x1.77bb3a40764fap-4, -0x1.50149d29dc29cp-11},
    {-0x1.5fd65a9fd9a3p-6, 0x1.892fb3c03be03p-4, 0x1.2705440686a77p-6},
    {-0x1.36bceeaa22ac4p-5, -0x1.77d3a26974d7ep-4, 0x1.86d96e497d4bfp-7},
    {-0x1.13a73ba75a1efp-5, -0x1.7f625c731a094p-4, -0x1.52b484167f1eap-7},
    {-0x1.68496f7e850b4p-5, -0x1.26aaf522eb15bp-4, 0x1.b86a4bb24b5aap-5},
    {0x1.7ac2a23969404p-5, -0x1.5c63b1c71f208p-4, 0x1.9a812b8b639e8p-6},
    {0x1.60ac0672168b6p-5, 0x1.2c9b37fd80f7ap-5, 0x1.51c46cd977d98p-4},
    {0x1.017d3ba5fdc26p-9, 0x1.45ac082078a88p-6, 0x1.91588c2d2a85fp-4},
    {0x1.a408d34f2b1c2p-12, 0x1.59b13790a59c4p-4, 0x1.b7645a64b933p-5},
    {-0x1.2c3f63317d0a3p-5, 0x1.9bc578ce5e2adp-5, 0x1.40b23db3fbe01p-4},
    {-0x1.d7c4f860a56f2p-5, 0x1.d740368f9e2c8p-8, 0x1.4d8faae6bdae1p-4},
    {-0x1.bbf84b2dd84dfp-5, -0x1.e855f8055e0efp-6, 0x1.41dac3bb6c544p-4},
    {-0x1.f2f1f27090e04p-9, -0x1.02df744978464p-4, 0x1.3d0a0c586673cp-4},
    {-0x1.6dd01d88c5978p-5, 0x1.c85b71da0c1e8p-5, 0x1.1ecbc22d6c6bdp-4},
    {-0x1.bf52ab87dd395p-9, -0x1.30046884b5ab8p-8, -0x1.98eb90b6e85acp-4},
    {-0x1.e68b49e3808acp-6, 0x1.681e65509f08dp-8, -0x1.867971fe559a8p-4},
    {-0x1.1cee89c916f4ap-5, -0x1.87c33d3426a5cp-8, -0x1.7f3e82ea77352p-4},
    {0x1.c6b735bee3c5cp-6, 0x1.131047d000807p-4, -0x1.1967e94565f23p-4},
    {0x1.18746eaa01222p-10, -0x1.e97234a4ccb1cp-5, -0x1.486d08cf19299p-4},
    {-0x1.03bd34180b4dbp-6, -0x1.371eaccc0e4ap-4, -0x1.026136bbd2202p-4},
    {0x1.3ec9f8f423059p-4, -0x1.a6cfdb88d65bcp-8, -0x1.ffa76983dabaap-5},
    {-0x1.e87a017232e12p-6, -0x1.860d49491d1d2p-4, -0x1.ace787ee423d7p-8},
    {-0x1.022d551090db1p-7, -0x1.97cc45832cd23p-4, 0x1.4c5dc2211a38p-8},
    {-0x1.7869cbd365ae5p-6, -0x1.7a165f8855c26p-4, -0x1.f96fd2163bacdp-6},
    {-0x1.14fc45316ffacp-4, -0x1.a22c6eb94abb4p-5, 0x1.b32098c88d0c2p-5},
    {0x1.decef07821c8p-6, -0x1.7e26192a906ccp-4, -0x1.583a9c5f5d533p-6},
    {0x1.5cdae6657e476p-5, -0x1.9d265562817p-5, -0x1.33b1019d26fd7p-4},
    {-0x1.1fcce2a0bf3c3p-5, -0x1.53dcecf6b2268p-4, -0x1.634aad6c257b5p-5},
    {0x1.09e4c09313b5cp-4, 0x1.7383949db0ec8p-5, 0x1.f444b4634c1cfp-5},
    {0x1.e5a2997f01948p-5, 0x1.c40979bf8cfe4p-5, 0x1.e087d68fba59p-5},
    {-0x1.472afdc11dcbap-10, 0x1.09bab7a3536c8p-4, 0x1.37a9c595d7f62p-4},
    {-0x1.9182a1cfa2c3bp-5, -0x1.4728f99b1aa81p-8, 0x1.647157f95468p-4},
    {0x1.dc53471f3a345p-5, 0x1.39d779e35362fp-4, -0x1.c02e2524937bcp-6},
    {-0x1.b9286ac022c14p-7, 0x1.88e0943356814p-4, -0x1.9780cdfb01a5dp-6},
    {0x1.420186e1e766ep-5, -0x1.35b47682c2181p-4, 0x1.aca3d4783d33ap-5},
    {0x1.170d67c7adc8fp-5, -0x1.2be11cf4787a3p-5, -0x1.62b707394b0bdp-4},
    {0x1.5355d6004328cp-5, 0x1.2376cf0e080d1p-4, -0x1.d0e733516beecp-5},
    {0x1.6066034819dbcp-4, 0x1.02605ffda095bp-5, -0x1.4802e9e3c1d26p-5},
    {0x1.98594ca76fbd8p-5, 0x1.2bf5c5009e98fp-4, -0x1.7c0c0d390291ap-5},
    {-0x1.728ba53f77ee6p-5, -0x1.4bc6acb5774b5p-4, -0x1.31c011ea51964p-5},
    {-0x1.f26a111aecaedp-9, 0x1.583c0a5fffb64p-5, 0x1.735b1cec47e85p-4},
    {0x1.3c06b1e174b4p-7, 0x1.7fecb6d7474p-4, -0x1.12531c430a5eap-5},
    {-0x1.3793d857b296dp-9, -0x1.371324b442aa1p-4, 0x1.0a49fc8c895d5p-4},
    {0x1.60dd4e006b3acp-5, -0x1.2f378e59a70efp-5, -0x1.51220ee55f637p-4},
    {0x1.72be99358d682p-13, 0x1.8d201ddcafad4p-4, 0x1.914218564d711p-6},
}};
inline constexpr std::array<double, 3> ellipsoid_radii = {
    0x1.5798ee2308c3ap-27, 0x1.5798ee2308c3ap-27, 0x1.3fb3305955e7cp-7};
/// pose_hull: rotation (row-major) and translation.
inline constexpr std::array<double, 12> pose_hull = {
    0x1.c6cdca155c5a8p-3, 0x1.a921ff542dccdp-1, 0x1.05aef1e960ae7p-1,
    0x1.9d30a2c931767p-1, -0x1.cd8574766dbe4p-2, 0x1.86bafa41b4a2ep-2,
    0x1.18293075d5eb1p-1, 0x1.4f97bd79d8a58p-2, -0x1.8a55299bc9274p-1,
    0x1.c039a28cd3dcep+0, 0x1.52e8552a31b1bp+3, 0x1.0c9fdbff836f1p+2};
/// pose_ellipsoid: rotation (row-major) and translation.
inline constexpr std::array<double, 12> pose_ellipsoid = {
    -0x1.95cda2c65daaep-1, 0x1.0b7027581118dp-1, 0x1.4225792fc5c1fp-2,
    -0x1.243502dd66007p-1, -0x1.d0b6916113fc4p-2, -0x1.5e627c73befbep-1,
    -0x1.b7af9cdb59649p-3, -0x1.71a2fe2b2b022p-1, 0x1.50cb2e76895cp-1,
    0x1.b85cff723a5b6p+0, 0x1.5065e6dd33324p+3, 0x1.0bbdd8a598454p+2};

template <class S> ConvexPolyhedron<S> hull() {
    std::vector<Vec3<S>> pts;
    for (const auto& p : hull_points) pts.emplace_back(S(p[0]), S(p[1]), S(p[2]));
    return ConvexPolyhedron<S>(pts);
}
template <class S> Ellipsoid<S> ellipsoid() {
    return Ellipsoid<S>(Vec3<S>(S(ellipsoid_radii[0]), S(ellipsoid_radii[1]), S(ellipsoid_radii[2])));
}
template <class S> Transform<S> pose(const std::array<double, 12>& p) {
    Mat3<S> r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = S(p[std::size_t(3 * i + j)]);
    return Transform<S>(r, Vec3<S>(S(p[9]), S(p[10]), S(p[11])));
}

}  // namespace cdkit::test::sliver_face
