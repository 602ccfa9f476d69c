// Continuous queries and ray casts on the types of mesh_convex.cpp: convex_ray_cast (a ray against a convex shape),
// mesh_convex_toi (a mesh and a convex shape, both moving) and mesh_toi (two meshes, rigid motions with rotation).
// They return the RayCastResult / ToiResult bound in batch.cpp / convex_cached.cpp.
#include "common.hpp"

#include <cdkit/ccd/convex_ray_cast.hpp>
#include <cdkit/ccd/mesh_convex_toi.hpp>
#include <cdkit/ccd/mesh_toi.hpp>

#include <cmath>

namespace cdkit::python {

namespace {
ToiRequest toi_request(py::handle h) { return h.is_none() ? ToiRequest{} : h.cast<ToiRequest>(); }
}  // namespace

void init_mesh_convex_ccd(py::module_& m) {
    py::class_<ConvexRayRequest>(m, "ConvexRayRequest",
                                 "Settings of convex_ray_cast(): hit tolerance (absolute, > 0) and the step cap.")
        .def(py::init([](double tolerance, int max_iterations) {
                 if (!std::isfinite(tolerance) || !(tolerance > 0)) throw py::value_error("tolerance must be finite and > 0");
                 if (max_iterations < 1) throw py::value_error("max_iterations must be >= 1");
                 ConvexRayRequest r;
                 r.tolerance = tolerance;
                 r.max_iterations = max_iterations;
                 return r;
             }),
             py::arg("tolerance") = 1e-9, py::arg("max_iterations") = 256)
        .def_readwrite("tolerance", &ConvexRayRequest::tolerance)
        .def_readwrite("max_iterations", &ConvexRayRequest::max_iterations);
    m.def(
        "convex_ray_cast",
        [](py::object shape, py::object pose_, py::object origin, py::object direction, double t_min, double t_max,
           py::object request) {
            const ShapeVar s = shape_of(shape, "shape");
            const Pose p = pose(pose_, "pose");
            Ray r;
            r.origin = vec3(origin, "origin");
            r.direction = vec3(direction, "direction");
            if (!(r.direction.squaredNorm() > 0)) throw py::value_error("direction must not be zero");
            if (std::isnan(t_min) || std::isnan(t_max)) throw py::value_error("t_min and t_max must not be NaN");
            r.t_min = t_min;
            r.t_max = t_max;
            const ConvexRayRequest req = request.is_none() ? ConvexRayRequest{} : request.cast<ConvexRayRequest>();
            py::gil_scoped_release nogil;
            return std::visit([&](auto* c) { return ray_cast(*c, p, r, req); }, s);
        },
        py::arg("shape"), py::arg("pose"), py::arg("origin"), py::arg("direction"), py::arg("t_min") = 0.0,
        py::arg("t_max") = std::numeric_limits<double>::infinity(), py::arg("request") = py::none(),
        "Casts the ray origin + t*direction (world), t in [t_min, t_max], against a convex shape at `pose`: one hit "
        "(t, point, outward normal; triangle = u = v = 0).");
    m.def(
        "mesh_convex_toi",
        [](const PyMeshModel& mesh, py::object mesh_start, py::object mesh_end, py::object shape, py::object shape_start,
           py::object shape_end, py::object request) {
            const ShapeVar s = shape_of(shape, "shape");
            const Pose m0 = pose(mesh_start, "mesh_start"), m1 = pose(mesh_end, "mesh_end"),
                       s0 = pose(shape_start, "shape_start"), s1 = pose(shape_end, "shape_end");
            const ToiRequest req = toi_request(request);
            return visit_model(mesh, [&](const auto& x) {
                py::gil_scoped_release nogil;
                return std::visit([&](auto* c) { return mesh_convex_toi(x, m0, m1, *c, s0, s1, req); }, s);
            });
        },
        py::arg("mesh"), py::arg("mesh_start"), py::arg("mesh_end"), py::arg("shape"), py::arg("shape_start"),
        py::arg("shape_end"), py::arg("request") = py::none(),
        "Time of impact of a mesh and a convex shape moving from their start to their end poses (any bv).");
    m.def(
        "mesh_toi",
        [](const PyMeshModel& a, py::object a_start, py::object a_end, const PyMeshModel& b, py::object b_start,
           py::object b_end, py::object request) {
            const Pose a0 = pose(a_start, "a_start"), a1 = pose(a_end, "a_end"), b0 = pose(b_start, "b_start"),
                       b1 = pose(b_end, "b_end");
            const ToiRequest req = toi_request(request);
            return visit_pair(a, b, [&](const auto& x, const auto& y) -> ToiResult {
                py::gil_scoped_release nogil;
                return mesh_toi(x, a0, a1, y, b0, b1, req);
            });
        },
        py::arg("a"), py::arg("a_start"), py::arg("a_end"), py::arg("b"), py::arg("b_start"), py::arg("b_end"),
        py::arg("request") = py::none(),
        "Time of impact of two meshes under rigid motions (rotation included), by conservative advancement "
        "(any bv).");
}

}  // namespace cdkit::python
