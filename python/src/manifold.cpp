// Contact manifolds of convex pairs: up to four points sharing a normal, with ids that persist through a
// ManifoldCache (manifold/contact_manifold.hpp).
#include "common.hpp"

#include <cdkit/manifold/contact_manifold.hpp>

namespace cdkit::python {

void init_manifold(py::module_& m) {
    py::class_<ManifoldRequest>(m, "ManifoldRequest", "What contact_manifold() keeps: margin, feature angle, single point.")
        .def(py::init([](double margin, double feature_angle, bool single_point, bool mesh_depth) {
                 ManifoldRequest r;
                 r.margin = margin;
                 r.feature_angle = feature_angle;
                 r.single_point = single_point;
                 r.mesh_depth = mesh_depth;
                 return r;
             }),
             py::arg("margin") = 0.0, py::arg("feature_angle") = 0.1, py::arg("single_point") = false,
             py::arg("mesh_depth") = true)
        .def_readwrite("margin", &ManifoldRequest::margin)
        .def_readwrite("feature_angle", &ManifoldRequest::feature_angle)
        .def_readwrite("single_point", &ManifoldRequest::single_point)
        .def_readwrite("mesh_depth", &ManifoldRequest::mesh_depth);
    py::class_<ManifoldPoint<double>>(m, "ManifoldPoint",
                                      "One contact point: on A's and on B's surface, its depth along the normal "
                                      "(negative: a speculative point), its feature id.")
        .def_property_readonly("point_a", [](const ManifoldPoint<double>& p) { return to_array(p.point_a); })
        .def_property_readonly("point_b", [](const ManifoldPoint<double>& p) { return to_array(p.point_b); })
        .def_readonly("depth", &ManifoldPoint<double>::depth)
        .def_readonly("id", &ManifoldPoint<double>::id);
    py::class_<ManifoldCache<double>>(m, "ManifoldCache",
                                      "Per-pair state between frames: GJK's warm start and last frame's points and ids.")
        .def(py::init<>())
        .def_readonly("count", &ManifoldCache<double>::count)
        .def("reset", [](ManifoldCache<double>& c) { c = ManifoldCache<double>{}; }, "Forget the previous frame.");
    py::class_<ContactManifold<double>>(m, "ContactManifold",
                                        "Result of contact_manifold(): up to four points sharing one normal (A to B).")
        .def_readonly("status", &ContactManifold<double>::status)
        .def_readonly("colliding", &ContactManifold<double>::colliding)
        .def_readonly("distance", &ContactManifold<double>::distance)
        .def_readonly("count", &ContactManifold<double>::count)
        .def_property_readonly("normal", [](const ContactManifold<double>& r) { return to_array(r.normal); })
        .def_property_readonly(
            "points",
            [](const ContactManifold<double>& r) {
                return std::vector<ManifoldPoint<double>>(r.points.begin(), r.points.begin() + r.count);
            },
            "The count points.")
        .def("max_depth", &ContactManifold<double>::max_depth, "The deepest point's depth.");
    m.def(
        "contact_manifold",
        [](py::object a, py::object pose_a, py::object b, py::object pose_b, py::object request, py::object cache) {
            const ShapeVar sa = shape_of(a, "a"), sb = shape_of(b, "b");
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            const ManifoldRequest r = request.is_none() ? ManifoldRequest{} : request.cast<ManifoldRequest>();
            ManifoldCache<double>* c = cache.is_none() ? nullptr : &cache.cast<ManifoldCache<double>&>();
            ContactManifold<double> out;
            {
                py::gil_scoped_release nogil;
                out = std::visit([&](auto* x, auto* y) { return contact_manifold(*x, pa, *y, pb, r, c); }, sa, sb);
            }
            if (out.status == QueryStatus::invalid_input)
                throw py::value_error("contact_manifold: margin must be finite and >= 0, feature_angle in [0, pi/4]");
            return out;
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("request") = py::none(),
        py::arg("cache") = py::none(),
        "Contact manifold of two convex shapes: up to four points from the touching faces or edges, each with its "
        "depth and a feature id (kept across frames by a ManifoldCache).");
}

}  // namespace cdkit::python
