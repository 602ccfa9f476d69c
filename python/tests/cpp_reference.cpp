// The C++ side of the Python differential tests: runs cdkit's queries on fixed inputs (the bunny at seeded poses,
// every built-in convex shape pair, a World, rays, mesh CCD) and prints the inputs and the answers as JSON, doubles
// with 17 significant digits (exact round trip). python/tests/test_against_cpp.py runs the module on the same inputs
// and requires the same answers.
#include <cdkit/batch.hpp>
#include <cdkit/cdkit.hpp>
#include <cdkit/ccd/mesh_convex_toi.hpp>
#include <cdkit/ccd/mesh_toi.hpp>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

using namespace cdkit;
using P = Transform<double>;

namespace {
std::string num(double x) {
    if (x == std::numeric_limits<double>::infinity()) return "1e999";
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", x);
    return b;
}
std::string vec(const Vec3<double>& v) { return "[" + num(v.x()) + "," + num(v.y()) + "," + num(v.z()) + "]"; }
std::string pose(const P& p) {
    std::string s = "[";
    for (int r = 0; r < 4; ++r) {
        s += r ? ",[" : "[";
        for (int c = 0; c < 4; ++c) s += (c ? "," : "") + num(r < 3 ? (c < 3 ? p.R(r, c) : p.t[r]) : (c == 3 ? 1 : 0));
        s += "]";
    }
    return s + "]";
}
P random_pose(std::mt19937_64& rng, double reach) {
    std::normal_distribution<double> g;
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    q.normalize();
    std::uniform_real_distribution<double> u(-reach, reach);
    return P(q.toRotationMatrix(), Vec3<double>(u(rng), u(rng), u(rng)));
}
}  // namespace

int main() {
    const std::string bunny_path = std::string(CDKIT_DATA_DIR) + "/bunny.obj";
    const auto mesh = load_mesh(bunny_path);
    const MeshModel<Obb<double>> obb(mesh);
    const MeshModel<Rss<double>> rss(mesh);
    std::mt19937_64 rng(38);
    std::printf("{\n\"mesh\": \"%s\",\n", bunny_path.c_str());

    // Mesh pairs: the bunny is about 10 across; B within 12 of A gives a mix of hits and misses.
    std::vector<P> pa, pb;
    for (int i = 0; i < 40; ++i) {
        pa.push_back(random_pose(rng, 0.5));
        pb.push_back(random_pose(rng, 12.0));
    }
    CollisionRequest all;
    all.mode = ContactMode::all;
    std::printf("\"mesh_pairs\": [\n");
    for (std::size_t i = 0; i < pa.size(); ++i) {
        const auto first = collide(obb, pa[i], obb, pb[i]);
        const auto every = collide(obb, pa[i], obb, pb[i], all);
        const auto d = distance(rss, pa[i], rss, pb[i]);
        std::printf("{\"pose_a\": %s, \"pose_b\": %s, \"colliding\": %s, \"first\": [%d, %d], \"all_count\": %zu, "
                    "\"all_pairs\": [",
                    pose(pa[i]).c_str(), pose(pb[i]).c_str(), first.colliding ? "true" : "false",
                    first.colliding ? int(first.contacts[0].triangle_a) : -1,
                    first.colliding ? int(first.contacts[0].triangle_b) : -1, every.contacts.size());
        for (std::size_t k = 0; k < every.contacts.size(); ++k)
            std::printf("%s[%u,%u]", k ? "," : "", every.contacts[k].triangle_a, every.contacts[k].triangle_b);
        std::printf("], \"distance\": %s, \"triangles\": [%u, %u], \"point_a\": %s, \"point_b\": %s}%s\n",
                    num(d.distance).c_str(), d.triangle_a, d.triangle_b, vec(d.point_a).c_str(), vec(d.point_b).c_str(),
                    i + 1 < pa.size() ? "," : "");
    }
    std::printf("],\n");

    // The C++ batch on the same poses (parallel): the module's collide_many / distance_many must equal it.
    const auto many = collide_many(obb, std::span<const P>(pa), obb, std::span<const P>(pb));
    const auto dmany = distance_many(rss, std::span<const P>(pa), rss, std::span<const P>(pb));
    std::printf("\"batch_colliding\": [");
    for (std::size_t i = 0; i < many.size(); ++i) std::printf("%s%s", i ? "," : "", many[i].colliding ? "true" : "false");
    std::printf("],\n\"batch_distance\": [");
    for (std::size_t i = 0; i < dmany.size(); ++i) std::printf("%s%s", i ? "," : "", num(dmany[i].distance).c_str());
    std::printf("],\n");

    // Convex pairs: every ordered pair of the built-in shapes (python/tests/shapes.py builds the same ones).
    const Sphere<double> sphere(0.5);
    const Box<double> box(Vec3<double>(0.3, 0.4, 0.5));
    const Capsule<double> capsule(0.2, 0.5);
    const Cylinder<double> cylinder(0.3, 0.4);
    const Cone<double> cone(0.3, 0.5);
    const Ellipsoid<double> ellipsoid(Vec3<double>(0.3, 0.4, 0.5));
    const ConvexTriangle<double> triangle(Vec3<double>(0, 0, 0), Vec3<double>(0.6, 0, 0.1), Vec3<double>(0, 0.5, -0.1));
    std::vector<Vec3<double>> pts;
    for (int k = 0; k < 12; ++k) pts.emplace_back(0.4 * std::cos(k * 0.5236), 0.3 * std::sin(k * 0.5236), k % 2 ? 0.35 : -0.35);
    const ConvexPolyhedron<double> hull(pts);
    std::printf("\"hull_points\": [");  // libm's cos and numpy's may differ in the last bit: the points travel too
    for (std::size_t k = 0; k < pts.size(); ++k) std::printf("%s%s", k ? "," : "", vec(pts[k]).c_str());
    std::printf("],\n");
    auto with_shape = [&](int k, auto&& f) {
        switch (k) {
            case 0: return f(sphere);
            case 1: return f(box);
            case 2: return f(capsule);
            case 3: return f(cylinder);
            case 4: return f(cone);
            case 5: return f(ellipsoid);
            case 6: return f(triangle);
            default: return f(hull);
        }
    };
    std::printf("\"convex_pairs\": [\n");
    bool first_row = true;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
            for (int rep = 0; rep < 3; ++rep) {
                const P a = random_pose(rng, 0.3), b = random_pose(rng, 0.9);
                with_shape(i, [&](const auto& x) {
                    with_shape(j, [&](const auto& y) {
                        const auto g = gjk_distance(x, a, y, b);
                        const auto bi = gjk_intersect(x, a, y, b);
                        const auto e = penetration(x, a, y, b);
                        const auto sp = separating_plane_intersect(x, a, y, b);
                        const auto toi = convex_toi(x, a, a, y, b, P(b.R, a.t));
                        std::printf("%s{\"a\": %d, \"b\": %d, \"pose_a\": %s, \"pose_b\": %s, \"distance\": %s, "
                                    "\"status\": %d, \"intersect_status\": %d, \"depth\": %s, \"plane_colliding\": %s, "
                                    "\"toi\": %s}\n",
                                    first_row ? "" : ",", i, j, pose(a).c_str(), pose(b).c_str(), num(g.distance).c_str(),
                                    int(g.status), int(bi.status), num(e.depth).c_str(), sp.colliding ? "true" : "false",
                                    num(toi.toi).c_str());
                        first_row = false;
                    });
                });
            }
    std::printf("],\n");
    const P ha = random_pose(rng, 0.2), hb = random_pose(rng, 1.2);
    const auto cf = closest_features(hull, ha, hull, hb);
    std::printf("\"closest_features\": {\"pose_a\": %s, \"pose_b\": %s, \"distance\": %s, \"status\": %d},\n",
                pose(ha).c_str(), pose(hb).c_str(), num(cf.distance).c_str(), int(cf.status));

    // A World: spheres on a line (neighbours overlap), a box, the hull, the bunny.
    World<double> world;
    std::vector<P> wp;
    for (int k = 0; k < 6; ++k) {
        wp.push_back(P::translation(Vec3<double>(0.9 * k, 0, 0)));
        (void)world.add(Shape<double>::sphere(0.5), wp.back());
    }
    wp.push_back(P::translation(Vec3<double>(0.5, 0.7, 0)));
    (void)world.add(Shape<double>::box(Vec3<double>(0.3, 0.4, 0.5)), wp.back());
    wp.push_back(P::translation(Vec3<double>(2.2, 0.6, 0.1)));
    (void)world.add(Shape<double>::convex_hull(pts), wp.back());
    wp.push_back(P::translation(Vec3<double>(3.6, 0.45, 0)));
    (void)world.add(Shape<double>::mesh(mesh), wp.back());
    const auto step = world.step();
    std::printf("\"world_poses\": [");
    for (std::size_t k = 0; k < wp.size(); ++k) std::printf("%s%s", k ? "," : "", pose(wp[k]).c_str());
    std::printf("],\n\"world_contacts\": [");
    for (std::size_t k = 0; k < step.contacts.size(); ++k)
        std::printf("%s[%u,%u,%s]", k ? "," : "", step.contacts[k].a, step.contacts[k].b, num(step.contacts[k].depth).c_str());
    std::printf("],\n");

    // Rays towards the bunny from a ring around it.
    std::vector<Ray> rays;
    for (int k = 0; k < 64; ++k) {
        Ray r;
        r.origin = Vec3<double>(20 * std::cos(k * 0.098), 5 + 0.05 * k, 20 * std::sin(k * 0.098));
        r.direction = Vec3<double>(-0.5, 4, 0) - r.origin + Vec3<double>(0, 0.6 * (k % 7), 0);
        rays.push_back(r);
    }
    const auto hits = ray_cast_many(obb, P{}, rays);
    std::printf("\"rays\": [");
    for (std::size_t k = 0; k < rays.size(); ++k)
        std::printf("%s{\"origin\": %s, \"direction\": %s, \"hit\": %s, \"t\": %s, \"triangle\": %d}", k ? "," : "",
                    vec(rays[k].origin).c_str(), vec(rays[k].direction).c_str(), hits[k].hit ? "true" : "false",
                    num(hits[k].hit ? hits[k].hits[0].t : -1).c_str(), hits[k].hit ? int(hits[k].hits[0].triangle) : -1);
    std::printf("],\n");

    // Mesh–convex: the bunny (obb tree) against every shape, near it (a mix of hits and misses): collide (all
    // contacts), distance, penetration (deepest), the shape moving towards the bunny's origin (mesh_convex_toi), and
    // a ray from beside the shape towards its centre (convex_ray_cast).
    MeshConvexRequest mc_all;
    mc_all.mode = ContactMode::all;
    std::printf("\"mesh_convex\": [\n");
    first_row = true;
    for (int i = 0; i < 8; ++i)
        for (int rep = 0; rep < 4; ++rep) {
            const P a = random_pose(rng, 0.5), b = random_pose(rng, rep < 2 ? 6.0 : 2.5);
            with_shape(i, [&](const auto& x) {
                const auto c = collide(obb, a, x, b, mc_all);
                const auto d = distance(obb, a, x, b);
                const auto e = penetration(obb, a, x, b);
                const auto toi = mesh_convex_toi(obb, a, a, x, b, P(b.R, a.t));
                Ray ray;
                ray.origin = b.t + Vec3<double>(3, 2, 1);
                ray.direction = b.t - ray.origin;
                const auto rc = ray_cast(x, b, ray);
                std::printf("%s{\"shape\": %d, \"pose_mesh\": %s, \"pose_shape\": %s, \"colliding\": %s, \"triangles\": [",
                            first_row ? "" : ",", i, pose(a).c_str(), pose(b).c_str(), c.colliding ? "true" : "false");
                for (std::size_t k = 0; k < c.contacts.size(); ++k) std::printf("%s%u", k ? "," : "", c.contacts[k].triangle);
                std::printf("], \"distance\": %s, \"triangle\": %u, \"point_mesh\": %s, \"point_shape\": %s, "
                            "\"depth\": %s, \"deepest\": %d, \"toi\": %s, \"toi_colliding\": %s, \"ray_origin\": %s, "
                            "\"ray_direction\": %s, \"ray_hit\": %s, \"ray_t\": %s}\n",
                            num(d.distance).c_str(), d.triangle, vec(d.point_mesh).c_str(), vec(d.point_shape).c_str(),
                            num(e.deepest.depth).c_str(), e.colliding ? int(e.deepest.triangle) : -1,
                            num(toi.toi).c_str(), toi.colliding ? "true" : "false", vec(ray.origin).c_str(),
                            vec(ray.direction).c_str(), rc.hit ? "true" : "false", num(rc.hit ? rc.hits[0].t : -1).c_str());
                first_row = false;
            });
        }
    std::printf("],\n");
    // mesh_toi: a turning bunny (rss tree) passing by the fixed one.
    const P m0(Eigen::AngleAxisd(0.0, Vec3<double>::UnitZ()).toRotationMatrix(), Vec3<double>(-14, 0.3, 0.2));
    const P m1(Eigen::AngleAxisd(1.3, Vec3<double>(0.3, 0.8, 0.5).normalized()).toRotationMatrix(), Vec3<double>(14, 0.1, -0.3));
    const auto mt = mesh_toi(rss, P{}, P{}, rss, m0, m1);
    std::printf("\"mesh_toi\": {\"b_start\": %s, \"b_end\": %s, \"colliding\": %s, \"toi\": %s, \"point_a\": %s},\n",
                pose(m0).c_str(), pose(m1).c_str(), mt.colliding ? "true" : "false", num(mt.toi).c_str(),
                vec(mt.point_a).c_str());

    // Mesh CCD: the bunny sweeping through another.
    const P s0 = P::translation(Vec3<double>(-15, 0.1, 0)), s1 = P::translation(Vec3<double>(15, 0.0, 0.1));
    const auto ccd = mesh_ccd(obb, P{}, P{}, obb, s0, s1);
    std::printf("\"mesh_ccd\": {\"b_start\": %s, \"b_end\": %s, \"colliding\": %s, \"toi\": %s}\n}\n", pose(s0).c_str(),
                pose(s1).c_str(), ccd.colliding ? "true" : "false", num(ccd.toi).c_str());
    return 0;
}
