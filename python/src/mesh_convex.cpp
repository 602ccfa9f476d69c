// Mesh–convex queries (include/cdkit/mesh_convex/): collide, distance and penetration between a MeshModel (any BV)
// and a convex shape, as mesh_convex_collide / mesh_convex_distance / mesh_convex_penetration. The model's BV and
// the shape dispatch through their variants (visit_model × ShapeVar); the continuous and ray-cast queries on the
// same types are in mesh_convex_ccd.cpp, so neither unit holds the whole product.
#include "common.hpp"

#include <cdkit/mesh_convex/collide.hpp>
#include <cdkit/mesh_convex/distance.hpp>
#include <cdkit/mesh_convex/penetration.hpp>

namespace cdkit::python {

namespace {
MeshConvexRequest mesh_convex_request(py::handle h) {
    return h.is_none() ? MeshConvexRequest{} : h.cast<MeshConvexRequest>();
}

template <class Contacts> py::array_t<std::int64_t> triangles_of(const Contacts& contacts) {
    py::array_t<std::int64_t> a(py::ssize_t(contacts.size()));
    auto w = a.mutable_unchecked<1>();
    for (std::size_t i = 0; i < contacts.size(); ++i) w(py::ssize_t(i)) = std::int64_t(contacts[i].triangle);
    return a;
}
}  // namespace

void init_mesh_convex(py::module_& m) {
    py::class_<MeshConvexRequest>(m, "MeshConvexRequest",
                                  "What mesh_convex_collide() and mesh_convex_penetration() report.")
        .def(py::init([](ContactMode mode, std::size_t max_contacts, bool witness_points) {
                 MeshConvexRequest r;
                 r.mode = mode;
                 r.max_contacts = max_contacts;
                 r.witness_points = witness_points;
                 return r;
             }),
             py::arg("mode") = ContactMode::first, py::arg("max_contacts") = std::numeric_limits<std::size_t>::max(),
             py::arg("witness_points") = true)
        .def_readwrite("mode", &MeshConvexRequest::mode)
        .def_readwrite("max_contacts", &MeshConvexRequest::max_contacts)
        .def_readwrite("witness_points", &MeshConvexRequest::witness_points);

    py::class_<MeshConvexContact<double>>(m, "MeshConvexContact",
                                          "One mesh triangle touching the shape, with a point of it in the shape (world).")
        .def_readonly("triangle", &MeshConvexContact<double>::triangle)
        .def_property_readonly("point", [](const MeshConvexContact<double>& c) { return to_array(c.point); });
    py::class_<MeshConvexResult<double>>(m, "MeshConvexResult",
                                         "Result of mesh_convex_collide(): status, colliding, the touching triangles.")
        .def_readonly("status", &MeshConvexResult<double>::status)
        .def_readonly("colliding", &MeshConvexResult<double>::colliding)
        .def_readonly("truncated", &MeshConvexResult<double>::truncated)
        .def_readonly("contacts", &MeshConvexResult<double>::contacts)
        .def_readonly("stats", &MeshConvexResult<double>::stats)
        .def_property_readonly("triangles", [](const MeshConvexResult<double>& r) { return triangles_of(r.contacts); },
                               "(K,) int64: each contact's triangle.")
        .def_property_readonly(
            "points",
            [](const MeshConvexResult<double>& r) {
                std::vector<V3> p;
                for (const auto& c : r.contacts) p.push_back(c.point);
                return to_array(p);
            },
            "(K,3) float64: each contact's witness point (world; zero without witness_points).")
        .def("__bool__", [](const MeshConvexResult<double>& r) { return r.colliding; })
        .def("__repr__", [](const MeshConvexResult<double>& r) {
            return std::string("<cdkit.MeshConvexResult status=") + to_string(r.status) +
                   " colliding=" + (r.colliding ? "True" : "False") + " contacts=" + std::to_string(r.contacts.size()) + ">";
        });
    py::class_<MeshConvexDistanceResult<double>>(m, "MeshConvexDistanceResult",
                                                 "Result of mesh_convex_distance(): world-frame closest points.")
        .def_readonly("status", &MeshConvexDistanceResult<double>::status)
        .def_readonly("colliding", &MeshConvexDistanceResult<double>::colliding)
        .def_readonly("distance", &MeshConvexDistanceResult<double>::distance)
        .def_property_readonly("point_mesh", [](const MeshConvexDistanceResult<double>& r) { return to_array(r.point_mesh); })
        .def_property_readonly("point_shape", [](const MeshConvexDistanceResult<double>& r) { return to_array(r.point_shape); })
        .def_readonly("triangle", &MeshConvexDistanceResult<double>::triangle)
        .def_readonly("stats", &MeshConvexDistanceResult<double>::stats)
        .def("__repr__", [](const MeshConvexDistanceResult<double>& r) {
            return std::string("<cdkit.MeshConvexDistanceResult status=") + to_string(r.status) +
                   " distance=" + std::to_string(r.distance) + ">";
        });
    py::class_<MeshConvexPenetration<double>>(m, "MeshConvexPenetration",
                                              "One touching triangle's penetration (world): depth, normal from the "
                                              "triangle towards the shape, deepest points.")
        .def_readonly("triangle", &MeshConvexPenetration<double>::triangle)
        .def_readonly("depth", &MeshConvexPenetration<double>::depth)
        .def_property_readonly("normal", [](const MeshConvexPenetration<double>& p) { return to_array(p.normal); })
        .def_property_readonly("point_mesh", [](const MeshConvexPenetration<double>& p) { return to_array(p.point_mesh); })
        .def_property_readonly("point_shape", [](const MeshConvexPenetration<double>& p) { return to_array(p.point_shape); });
    py::class_<MeshConvexPenetrationResult<double>>(m, "MeshConvexPenetrationResult",
                                                    "Result of mesh_convex_penetration(): the deepest touching triangle "
                                                    "and (ContactMode.all) every one.")
        .def_readonly("status", &MeshConvexPenetrationResult<double>::status)
        .def_readonly("colliding", &MeshConvexPenetrationResult<double>::colliding)
        .def_readonly("truncated", &MeshConvexPenetrationResult<double>::truncated)
        .def_readonly("deepest", &MeshConvexPenetrationResult<double>::deepest)
        .def_readonly("contacts", &MeshConvexPenetrationResult<double>::contacts)
        .def_readonly("stats", &MeshConvexPenetrationResult<double>::stats)
        .def_property_readonly("triangles",
                               [](const MeshConvexPenetrationResult<double>& r) { return triangles_of(r.contacts); },
                               "(K,) int64: each contact's triangle.")
        .def("__bool__", [](const MeshConvexPenetrationResult<double>& r) { return r.colliding; });

    m.def(
        "mesh_convex_collide",
        [](const PyMeshModel& mesh, py::object pose_mesh, py::object shape, py::object pose_shape, py::object request) {
            const ShapeVar s = shape_of(shape, "shape");
            const Pose pm = pose(pose_mesh, "pose_mesh"), ps = pose(pose_shape, "pose_shape");
            const MeshConvexRequest req = mesh_convex_request(request);
            return visit_model(mesh, [&](const auto& x) {
                py::gil_scoped_release nogil;
                return std::visit([&](auto* c) { return collide(x, pm, *c, ps, req); }, s);
            });
        },
        py::arg("mesh"), py::arg("pose_mesh"), py::arg("shape"), py::arg("pose_shape"), py::arg("request") = py::none(),
        "Mesh-convex collision: the first touching triangle, or all with MeshConvexRequest(ContactMode.all).");
    m.def(
        "mesh_convex_distance",
        [](const PyMeshModel& mesh, py::object pose_mesh, py::object shape, py::object pose_shape, py::object request) {
            const ShapeVar s = shape_of(shape, "shape");
            const Pose pm = pose(pose_mesh, "pose_mesh"), ps = pose(pose_shape, "pose_shape");
            const DistanceRequest<double> req =
                request.is_none() ? DistanceRequest<double>{} : request.cast<DistanceRequest<double>>();
            return visit_model(mesh, [&](const auto& x) {
                py::gil_scoped_release nogil;
                return std::visit([&](auto* c) { return distance(x, pm, *c, ps, req); }, s);
            });
        },
        py::arg("mesh"), py::arg("pose_mesh"), py::arg("shape"), py::arg("pose_shape"), py::arg("request") = py::none(),
        "Distance from the mesh's triangles to a convex shape (0 when touching), closest points and triangle (any bv).");
    m.def(
        "mesh_convex_penetration",
        [](const PyMeshModel& mesh, py::object pose_mesh, py::object shape, py::object pose_shape, py::object request) {
            const ShapeVar s = shape_of(shape, "shape");
            const Pose pm = pose(pose_mesh, "pose_mesh"), ps = pose(pose_shape, "pose_shape");
            const MeshConvexRequest req = mesh_convex_request(request);
            return visit_model(mesh, [&](const auto& x) {
                py::gil_scoped_release nogil;
                return std::visit([&](auto* c) { return penetration(x, pm, *c, ps, req); }, s);
            });
        },
        py::arg("mesh"), py::arg("pose_mesh"), py::arg("shape"), py::arg("pose_shape"), py::arg("request") = py::none(),
        "Per-triangle penetration (EPA) of the touching triangles with a convex shape: the deepest, or all.");
}

}  // namespace cdkit::python
