// Batches: collide_many / distance_many (cdkit/batch.hpp) and ray casts, N inputs in, arrays out, the GIL released
// for the whole batch (every query runs without it), TBB over all cores or `threads` of them.
#include "common.hpp"

#include <limits>

#include <cdkit/batch.hpp>
#include <cdkit/ccd/ray_cast.hpp>

#if defined(CDKIT_HAS_TBB)
#include <tbb/task_arena.h>
#endif

namespace cdkit::python {

namespace {
/// Runs f in an arena of `threads` workers (0: TBB's default, all cores), without the GIL.
template <class F> void run_batch(int threads, F&& f) {
    if (threads < 0) throw py::value_error("threads must be >= 0");
    py::gil_scoped_release nogil;
#if defined(CDKIT_HAS_TBB)
    if (threads > 0) {
        tbb::task_arena arena(threads);
        arena.execute(f);
        return;
    }
#endif
    f();
}

/// The pose lists of a batch: (N,4,4) each, or one side a single pose for every entry.
std::pair<std::vector<Pose>, std::vector<Pose>> batch_poses(py::handle pa, py::handle pb) {
    // A side given as an (N,4,4) array sets N (N may be 0); the other side may be one pose for every entry.
    auto stacked = [](py::handle h) {
        if (h.is_none() || py::isinstance<py::tuple>(h)) return false;
        py::array a = py::array::ensure(h);
        return a && a.ndim() == 3;
    };
    const bool sa = stacked(pa), sb = stacked(pb);
    if (!sa && !sb) throw py::value_error("poses_a / poses_b: at least one must be an (N,4,4) array");
    std::vector<Pose> a, b;
    if (sa) a = poses(pa, "poses_a");
    if (sb) b = poses(pb, "poses_b");
    if (!sa) a.assign(b.size(), pose(pa, "poses_a"));
    if (!sb) b.assign(a.size(), pose(pb, "poses_b"));
    if (a.size() != b.size())
        throw py::value_error("poses_a has " + std::to_string(a.size()) + " poses but poses_b has " + std::to_string(b.size()));
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (!pose_is_usable(a[i])) throw py::value_error("poses_a [" + std::to_string(i) + "]: not a rigid motion");
        if (!pose_is_usable(b[i])) throw py::value_error("poses_b [" + std::to_string(i) + "]: not a rigid motion");
    }
    return {std::move(a), std::move(b)};
}

/// Arrays of a distance batch.
struct DistanceBatch {
    py::array_t<double> distance, point_a, point_b;
    py::array_t<std::int64_t> triangle_a, triangle_b;
};
struct RayBatch {
    py::array_t<bool> hit;
    py::array_t<double> t, point, normal;
    py::array_t<std::int64_t> triangle;
};
}  // namespace

void init_batch(py::module_& m) {
    m.def(
        "collide_many",
        [](const PyMeshModel& a, py::object poses_a, const PyMeshModel& b, py::object poses_b, int threads) {
            auto [pa, pb] = batch_poses(poses_a, poses_b);
            py::array_t<bool> out(py::ssize_t(pa.size()));
            bool* o = out.mutable_data();
            visit_pair(a, b, [&](const auto& x, const auto& y) {
                run_batch(threads, [&] {
                    const auto r = collide_many(x, std::span<const Pose>(pa), y, std::span<const Pose>(pb));
                    for (std::size_t i = 0; i < r.size(); ++i) o[i] = r[i].colliding;
                });
            });
            return out;
        },
        py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::arg("threads") = 0,
        "collide(a, poses_a[i], b, poses_b[i]) for every i (first contact), as an (N,) bool array. poses_a and "
        "poses_b are (N,4,4) arrays, or one of them a single pose used for every entry. Runs in C++ with TBB "
        "(`threads` workers, 0: all cores), the GIL released. ValueError for a pose that is not a rigid motion.");
    py::class_<DistanceBatch>(m, "DistanceBatch", "Arrays of distance_many(): entry i is distance(a, poses_a[i], b, poses_b[i]).")
        .def_readonly("distance", &DistanceBatch::distance, "(N,) float64")
        .def_readonly("point_a", &DistanceBatch::point_a, "(N,3) float64, world")
        .def_readonly("point_b", &DistanceBatch::point_b, "(N,3) float64, world")
        .def_readonly("triangle_a", &DistanceBatch::triangle_a, "(N,) int64")
        .def_readonly("triangle_b", &DistanceBatch::triangle_b, "(N,) int64")
        .def("__len__", [](const DistanceBatch& d) { return d.distance.size(); });
    m.def(
        "distance_many",
        [](const PyMeshModel& a, py::object poses_a, const PyMeshModel& b, py::object poses_b, double rel_err,
           double abs_err, double max_distance, int threads) {
            const DistanceRequest<double> req = distance_request(rel_err, abs_err, max_distance);
            auto [pa, pb] = batch_poses(poses_a, poses_b);
            const py::ssize_t n = py::ssize_t(pa.size());
            DistanceBatch out{py::array_t<double>(n), py::array_t<double>({n, py::ssize_t(3)}),
                              py::array_t<double>({n, py::ssize_t(3)}), py::array_t<std::int64_t>(n),
                              py::array_t<std::int64_t>(n)};
            double *d = out.distance.mutable_data(), *qa = out.point_a.mutable_data(), *qb = out.point_b.mutable_data();
            std::int64_t *ta = out.triangle_a.mutable_data(), *tb = out.triangle_b.mutable_data();
            visit_pair(a, b, [&](const auto& x, const auto& y) {
                run_batch(threads, [&] {
                    const auto r = distance_many(x, std::span<const Pose>(pa), y, std::span<const Pose>(pb), req);
                    for (std::size_t i = 0; i < r.size(); ++i) {
                        d[i] = r[i].distance;
                        ta[i] = r[i].triangle_a;
                        tb[i] = r[i].triangle_b;
                        for (int k = 0; k < 3; ++k) {
                            qa[3 * i + std::size_t(k)] = r[i].point_a[k];
                            qb[3 * i + std::size_t(k)] = r[i].point_b[k];
                        }
                    }
                });
            });
            return out;
        },
        py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::arg("rel_err") = 0.0,
        py::arg("abs_err") = 0.0, py::arg("max_distance") = std::numeric_limits<double>::infinity(),
        py::arg("threads") = 0,
        "distance(a, poses_a[i], b, poses_b[i]) for every i, as a DistanceBatch of arrays (inf where a pair lies "
        "beyond max_distance); poses and threads as in collide_many.");

    // ---- rays -----------------------------------------------------------------------------------------
    py::enum_<RayMode>(m, "RayMode", "Which hits a ray cast reports.")
        .value("closest", RayMode::closest)
        .value("any", RayMode::any)
        .value("all", RayMode::all);
    py::class_<RayHit>(m, "RayHit", "One hit: origin + t*direction, on `triangle` at barycentrics (u, v).")
        .def_readonly("triangle", &RayHit::triangle)
        .def_readonly("t", &RayHit::t)
        .def_readonly("u", &RayHit::u)
        .def_readonly("v", &RayHit::v)
        .def_property_readonly("point", [](const RayHit& h) { return to_array(h.point); })
        .def_property_readonly("normal", [](const RayHit& h) { return to_array(h.normal); });
    py::class_<RayCastResult>(m, "RayCastResult", "Result of ray_cast(): `hit` and the hits by increasing t.")
        .def_readonly("status", &RayCastResult::status)
        .def_readonly("hit", &RayCastResult::hit)
        .def_readonly("hits", &RayCastResult::hits)
        .def_readonly("bv_tests", &RayCastResult::bv_tests)
        .def_readonly("triangle_tests", &RayCastResult::triangle_tests);
    m.def(
        "ray_cast",
        [](const PyMeshModel& model, py::object pose_, py::object origin, py::object direction, double t_min,
           double t_max, RayMode mode) {
            const Pose p = pose(pose_, "pose");
            Ray r;
            r.origin = vec3(origin, "origin");
            r.direction = vec3(direction, "direction");
            r.t_min = t_min;
            r.t_max = t_max;
            return visit_model(model, [&](const auto& x) {
                py::gil_scoped_release nogil;
                return ray_cast(x, p, r, mode);
            });
        },
        py::arg("model"), py::arg("pose"), py::arg("origin"), py::arg("direction"), py::arg("t_min") = 0.0,
        py::arg("t_max") = std::numeric_limits<double>::infinity(), py::arg("mode") = RayMode::closest,
        "Casts the ray origin + t*direction (world), t in [t_min, t_max], against the mesh at `pose` (watertight).");
    py::class_<RayBatch>(m, "RayBatch", "Arrays of ray_cast_many() (closest hit per ray; entries of misses: t = inf, "
                                        "triangle = -1, points 0).")
        .def_readonly("hit", &RayBatch::hit)
        .def_readonly("t", &RayBatch::t)
        .def_readonly("triangle", &RayBatch::triangle)
        .def_readonly("point", &RayBatch::point)
        .def_readonly("normal", &RayBatch::normal)
        .def("__len__", [](const RayBatch& r) { return r.hit.size(); });
    m.def(
        "ray_cast_many",
        [](const PyMeshModel& model, py::object pose_, py::object origins, py::object directions, double t_max,
           RayMode mode, int threads) {
            if (mode == RayMode::all) throw py::value_error("ray_cast_many reports one hit per ray: mode closest or any");
            const Pose p = pose(pose_, "pose");
            const std::vector<V3> o = points(origins, "origins"), d = points(directions, "directions");
            if (o.size() != d.size())
                throw py::value_error("origins has " + std::to_string(o.size()) + " rows but directions has " +
                                      std::to_string(d.size()));
            std::vector<Ray> rays(o.size());
            for (std::size_t i = 0; i < rays.size(); ++i) {
                if (d[i].squaredNorm() == 0) throw py::value_error("directions [" + std::to_string(i) + "]: zero vector");
                rays[i].origin = o[i];
                rays[i].direction = d[i];
                rays[i].t_max = t_max;
            }
            const py::ssize_t n = py::ssize_t(rays.size());
            RayBatch out{py::array_t<bool>(n), py::array_t<double>(n), py::array_t<double>({n, py::ssize_t(3)}),
                         py::array_t<double>({n, py::ssize_t(3)}), py::array_t<std::int64_t>(n)};
            bool* h = out.hit.mutable_data();
            double *t = out.t.mutable_data(), *pt = out.point.mutable_data(), *nm = out.normal.mutable_data();
            std::int64_t* tri = out.triangle.mutable_data();
            visit_model(model, [&](const auto& x) {
                run_batch(threads, [&] {
                    const auto r = ray_cast_many(x, p, rays, mode);
                    for (std::size_t i = 0; i < r.size(); ++i) {
                        h[i] = r[i].hit;
                        const RayHit none{0, std::numeric_limits<double>::infinity()};
                        const RayHit& x0 = r[i].hit ? r[i].hits[0] : none;
                        t[i] = x0.t;
                        tri[i] = r[i].hit ? std::int64_t(x0.triangle) : -1;
                        for (int k = 0; k < 3; ++k) {
                            pt[3 * i + std::size_t(k)] = x0.point[k];
                            nm[3 * i + std::size_t(k)] = x0.normal[k];
                        }
                    }
                });
            });
            return out;
        },
        py::arg("model"), py::arg("pose"), py::arg("origins"), py::arg("directions"),
        py::arg("t_max") = std::numeric_limits<double>::infinity(), py::arg("mode") = RayMode::closest,
        py::arg("threads") = 0,
        "Casts N rays ((N,3) origins and directions, world) against the mesh in C++ with TBB, the GIL released; "
        "returns a RayBatch of arrays.");
}

}  // namespace cdkit::python
