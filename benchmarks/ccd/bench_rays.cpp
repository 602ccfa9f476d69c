// cdkit_bench_rays: ray casts against meshes through their trees, single rays in a loop and ray_cast_many (TBB) —
// a sensor sweep of N rays from a point outside the mesh towards random points of its bounding box — in rays per
// second, with the closest hits of a sample of 1,000 rays checked against every triangle tested one by one.
//   cdkit_bench_rays [--rays N] [--csv FILE] MESH...
#include <cdkit/bv/obb.hpp>
#include <cdkit/ccd/ray_cast.hpp>
#include <cdkit/io/load_mesh.hpp>

#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

int main(int argc, char** argv) try {
    using V = cdkit::Vec3<double>;
    using Clock = std::chrono::steady_clock;
    std::size_t n = 100000;
    std::string csv;
    std::vector<std::string> meshes;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--rays" && i + 1 < argc) n = std::stoul(argv[++i]);
        else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
        else meshes.push_back(a);
    }
    if (meshes.empty()) meshes.push_back(CDKIT_SOURCE_DIR "/data/bunny.obj");
    std::FILE* out = csv.empty() ? nullptr : std::fopen(csv.c_str(), "w");
    if (out) std::fprintf(out, "# command: cdkit_bench_rays --rays %zu\nmesh,triangles,rays,hit_fraction,single_rays_per_s,batch_rays_per_s,brute_checked,brute_mismatches\n", n);
    std::printf("%-18s %9s %8s %6s %16s %16s %8s %10s\n", "mesh", "triangles", "rays", "hit", "single rays/s",
                "batch rays/s", "checked", "mismatch");
    for (const auto& path : meshes) {
        const auto mesh = cdkit::load_mesh(path);
        const cdkit::MeshModel<cdkit::Obb<double>> model(mesh);
        V lo = mesh.vertices[0], hi = lo;
        for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
        const V centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
        std::mt19937_64 rng(1);
        std::uniform_real_distribution<double> u(-1, 1);
        std::vector<cdkit::Ray> rays(n);
        const V eye = centre + 3 * half.norm() * V(0.3, 0.5, 0.8).normalized();
        for (auto& r : rays) {
            const double x = u(rng), y = u(rng), z = u(rng);
            r.origin = eye;
            r.direction = centre + half.cwiseProduct(V(x, y, z)) - eye;
        }
        const cdkit::Transform<double> pose;
        std::size_t hits = 0;
        auto t0 = Clock::now();
        for (const auto& r : rays) hits += cdkit::ray_cast(model, pose, r).hit;
        const double single_s = std::chrono::duration<double>(Clock::now() - t0).count();
        t0 = Clock::now();
        const auto batch = cdkit::ray_cast_many(model, pose, rays);
        const double batch_s = std::chrono::duration<double>(Clock::now() - t0).count();
        // Every triangle, one by one, for a sample.
        std::size_t checked = 0, mismatches = 0;
        for (std::size_t i = 0; i < rays.size(); i += std::max<std::size_t>(1, rays.size() / 1000)) {
            const cdkit::detail::RayFrame f(rays[i]);
            double best = std::numeric_limits<double>::infinity();
            for (const auto& t : mesh.triangles) {
                double h, bu, bv;
                if (cdkit::detail::ray_triangle(f, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]], 0,
                                                best, h, bu, bv))
                    best = h;
            }
            ++checked;
            const bool brute_hit = best < std::numeric_limits<double>::infinity();
            mismatches += brute_hit != batch[i].hit || (brute_hit && best != batch[i].hits[0].t);
        }
        const std::string name = path.substr(path.find_last_of('/') + 1);
        std::printf("%-18s %9zu %8zu %6.3f %16.0f %16.0f %8zu %10zu\n", name.c_str(), mesh.triangles.size(), n,
                    double(hits) / double(n), double(n) / single_s, double(n) / batch_s, checked, mismatches);
        if (out)
            std::fprintf(out, "%s,%zu,%zu,%.4f,%.0f,%.0f,%zu,%zu\n", name.c_str(), mesh.triangles.size(), n,
                         double(hits) / double(n), double(n) / single_s, double(n) / batch_s, checked, mismatches);
        if (mismatches) return 1;
    }
    if (out) std::fclose(out);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "cdkit_bench_rays: %s\n", e.what());
    return 2;
}
