// penetration_depth / directional_depth between two MeshModels (mesh_depth/), with optional inner sphere trees.
#include "common.hpp"

#include <cdkit/mesh_depth/penetration_depth.hpp>

namespace cdkit::python {

void init_mesh_depth(py::module_& m) {
    py::enum_<DepthDirection>(m, "DepthDirection", "Where a mesh depth's direction came from.")
        .value("none", DepthDirection::none)
        .value("given", DepthDirection::given)
        .value("ist_force", DepthDirection::ist_force)
        .value("surface_normal", DepthDirection::surface_normal)
        .value("centre_line", DepthDirection::centre_line)
        .value("refined", DepthDirection::refined);
    py::class_<MeshDepthStats>(m, "MeshDepthStats", "Work counters of one mesh depth query.")
        .def_readonly("traversal", &MeshDepthStats::traversal)
        .def_readonly("directions", &MeshDepthStats::directions)
        .def_readonly("passes", &MeshDepthStats::passes);
    py::class_<MeshDepthResult>(m, "MeshDepthResult",
                                "Result of penetration_depth(): the translation of b along `normal` (length `depth`) "
                                "that undoes every crossing of the two surfaces; world frame.")
        .def_readonly("status", &MeshDepthResult::status)
        .def_readonly("colliding", &MeshDepthResult::colliding)
        .def_readonly("complete", &MeshDepthResult::complete)
        .def_readonly("depth", &MeshDepthResult::depth)
        .def_property_readonly("normal", [](const MeshDepthResult& r) { return to_array(r.normal); })
        .def_readonly("triangle_a", &MeshDepthResult::triangle_a)
        .def_readonly("triangle_b", &MeshDepthResult::triangle_b)
        .def_property_readonly("point_a", [](const MeshDepthResult& r) { return to_array(r.point_a); })
        .def_property_readonly("point_b", [](const MeshDepthResult& r) { return to_array(r.point_b); })
        .def_readonly("direction", &MeshDepthResult::direction)
        .def_readonly("volume", &MeshDepthResult::volume)
        .def_property_readonly("force_direction", [](const MeshDepthResult& r) { return to_array(r.force_direction); })
        .def_readonly("stats", &MeshDepthResult::stats)
        .def("__repr__", [](const MeshDepthResult& r) {
            return std::string("<cdkit.MeshDepthResult status=") + to_string(r.status) +
                   " colliding=" + (r.colliding ? "True" : "False") + " depth=" + std::to_string(r.depth) + ">";
        });
    m.def(
        "penetration_depth",
        [](const PyMeshModel& a, py::object pose_a, const PyMeshModel& b, py::object pose_b, py::object direction,
           int refine_steps, int max_passes, py::object ist_a, py::object ist_b) {
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            MeshDepthRequest req;
            if (!direction.is_none()) req.direction = vec3(direction, "direction");
            req.refine_steps = refine_steps;
            req.max_passes = max_passes;
            if (ist_a.is_none() != ist_b.is_none())
                throw py::value_error("penetration_depth: give both inner sphere trees (ist_a and ist_b) or neither");
            const InnerSphereTree* ta = ist_a.is_none() ? nullptr : &ist_a.cast<const InnerSphereTree&>();
            const InnerSphereTree* tb = ist_b.is_none() ? nullptr : &ist_b.cast<const InnerSphereTree&>();
            return visit_pair(a, b, [&](const auto& x, const auto& y) {
                py::gil_scoped_release nogil;
                return ta ? penetration_depth(x, *ta, pa, y, *tb, pb, req) : penetration_depth(x, pa, y, pb, req);
            });
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("direction") = py::none(),
        py::arg("refine_steps") = 0, py::arg("max_passes") = 1000, py::arg("ist_a") = py::none(),
        py::arg("ist_b") = py::none(),
        "Penetration depth and normal of two intersecting meshes: the translation of b along the normal that undoes "
        "every crossing of their surfaces. The normal is the intersection curve's (or, with both inner sphere trees, "
        "the shorter of that and the penalty force direction); `direction` fixes it; refine_steps > 0 searches the "
        "sphere of directions for a shorter one.");
}

}  // namespace cdkit::python
