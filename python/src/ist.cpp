// Inner sphere trees: build (packing + hierarchy), save/load, penetration volume, sphere distance, penalty wrench.
#include "common.hpp"

#include <cdkit/ist/inner_sphere_tree.hpp>
#include <cdkit/ist/ist_query.hpp>
#include <cdkit/ist/penalty_force.hpp>
#include <cdkit/ist/serialize.hpp>

#include <memory>

namespace cdkit::python {

namespace {
using Ist = std::shared_ptr<const InnerSphereTree>;
IstRequest ist_request(std::uint64_t max_node_tests, bool collect_pairs) {
    IstRequest r;
    r.max_node_tests = max_node_tests;
    r.collect_pairs = collect_pairs;
    return r;
}
}  // namespace

void init_ist(py::module_& m) {
    py::class_<InnerSphereTree, std::shared_ptr<InnerSphereTree>>(
        m, "InnerSphereTree", "Inner spheres packed into a closed mesh and their hierarchy (penetration volume queries).")
        .def_property_readonly(
            "spheres",
            [](const InnerSphereTree& t) {
                py::array_t<double> a({py::ssize_t(t.spheres().size()), py::ssize_t(4)});
                auto w = a.mutable_unchecked<2>();
                for (std::size_t i = 0; i < t.spheres().size(); ++i) {
                    for (int k = 0; k < 3; ++k) w(py::ssize_t(i), k) = t.spheres()[i].center[k];
                    w(py::ssize_t(i), 3) = t.spheres()[i].radius;
                }
                return a;
            },
            "(S,4) float64: centre x, y, z and radius of every inner sphere (model frame).")
        .def_property_readonly("num_spheres", [](const InnerSphereTree& t) { return t.spheres().size(); })
        .def_property_readonly("num_nodes", [](const InnerSphereTree& t) { return t.nodes().size(); })
        .def_property_readonly("mesh_volume", &InnerSphereTree::mesh_volume)
        .def_property_readonly("sphere_volume", &InnerSphereTree::sphere_volume)
        .def_property_readonly("coverage", &InnerSphereTree::coverage, "Sphere volume / mesh volume.")
        .def("validate", [](const InnerSphereTree& t) { t.validate(); })
        .def("save", [](const InnerSphereTree& t, const std::string& path) { save_inner_sphere_tree(t, path); },
             py::arg("path"), "Writes the tree (binary, versioned, checksummed); cdkit.Error on an I/O failure.")
        .def("to_bytes", [](const InnerSphereTree& t) {
            const auto b = serialize_inner_sphere_tree(t);
            return py::bytes(reinterpret_cast<const char*>(b.data()), b.size());
        })
        .def_static(
            "load",
            [](const std::string& path) {
                py::gil_scoped_release nogil;
                return std::make_shared<InnerSphereTree>(load_inner_sphere_tree(path));
            },
            py::arg("path"), "Reads a saved tree; cdkit.Error naming the file for a missing, truncated or corrupt one.")
        .def_static(
            "from_bytes",
            [](py::bytes data) {
                const std::string s = data;
                const std::vector<std::uint8_t> b(s.begin(), s.end());
                return std::make_shared<InnerSphereTree>(deserialize_inner_sphere_tree(b, "<bytes>"));
            },
            py::arg("data"));
    m.def(
        "build_inner_sphere_tree",
        [](py::object vertices, py::object faces, std::size_t max_spheres, int grid_resolution, bool depth_calibration,
           std::uint64_t seed, int out_degree) {
            TriangleMesh<double> mesh = mesh_from_arrays(vertices, faces, "<mesh>");
            if (max_spheres < 1) throw py::value_error("max_spheres must be >= 1");
            PackingOptions p;
            if (grid_resolution < 0) throw py::value_error("grid_resolution must be >= 0");
            p.max_spheres = max_spheres;
            p.grid_resolution = grid_resolution;
            p.depth_calibration = depth_calibration;
            p.seed = seed;
            IstBuildOptions o;
            o.out_degree = out_degree;
            py::gil_scoped_release nogil;
            return std::make_shared<InnerSphereTree>(build_inner_sphere_tree(mesh, p, o));
        },
        py::arg("vertices"), py::arg("faces"), py::arg("max_spheres") = 10000, py::arg("grid_resolution") = 0,
        py::arg("depth_calibration") = true, py::arg("seed") = 1,
        py::arg("out_degree") = 8,
        "Packs inner spheres into a closed, consistently oriented mesh and builds their tree (seconds for 10k "
        "spheres; PackingOptions: `grid_resolution` samples along the longest axis, 0: chosen from max_spheres; "
        "`depth_calibration` fits the cell weights). Raises cdkit.Error for an open or non-manifold mesh.");

    py::class_<OverlappingSpheres>(m, "OverlappingSpheres", "Two overlapping inner spheres (indices into each tree's spheres) and their lens volume.")
        .def_readonly("a", &OverlappingSpheres::a)
        .def_readonly("b", &OverlappingSpheres::b)
        .def_readonly("volume", &OverlappingSpheres::volume);
    py::class_<IstQueryStats>(m, "IstQueryStats", "Work counters of one inner-sphere-tree query.")
        .def_readonly("node_tests", &IstQueryStats::node_tests)
        .def_readonly("leaf_pairs", &IstQueryStats::leaf_pairs);
    py::class_<PenetrationVolumeResult>(m, "PenetrationVolumeResult", "Result of penetration_volume() (model units^3).")
        .def_readonly("status", &PenetrationVolumeResult::status)
        .def_readonly("colliding", &PenetrationVolumeResult::colliding)
        .def_readonly("complete", &PenetrationVolumeResult::complete)
        .def_readonly("volume", &PenetrationVolumeResult::volume)
        .def_readonly("volume_lower", &PenetrationVolumeResult::volume_lower)
        .def_readonly("volume_upper", &PenetrationVolumeResult::volume_upper)
        .def_readonly("calibrated", &PenetrationVolumeResult::calibrated)
        .def_readonly("pairs", &PenetrationVolumeResult::pairs)
        .def_readonly("stats", &PenetrationVolumeResult::stats);
    py::class_<IstDistanceResult>(m, "IstDistanceResult", "Result of sphere_distance(): world-frame points on the closest inner spheres.")
        .def_readonly("status", &IstDistanceResult::status)
        .def_readonly("complete", &IstDistanceResult::complete)
        .def_readonly("distance", &IstDistanceResult::distance)
        .def_readonly("lower_bound", &IstDistanceResult::lower_bound)
        .def_property_readonly("point_a", [](const IstDistanceResult& r) { return to_array(r.point_a); })
        .def_property_readonly("point_b", [](const IstDistanceResult& r) { return to_array(r.point_b); })
        .def_readonly("sphere_a", &IstDistanceResult::sphere_a)
        .def_readonly("sphere_b", &IstDistanceResult::sphere_b)
        .def_readonly("stats", &IstDistanceResult::stats);
    m.def(
        "penetration_volume",
        [](const InnerSphereTree& a, py::object pose_a, const InnerSphereTree& b, py::object pose_b,
           std::uint64_t max_node_tests, bool collect_pairs) {
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            py::gil_scoped_release nogil;
            return penetration_volume(a, pa, b, pb, ist_request(max_node_tests, collect_pairs));
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("max_node_tests") = 0,
        py::arg("collect_pairs") = true,
        "Penetration volume of two inner sphere trees (0 node budget: exact over the spheres).");
    m.def(
        "sphere_distance",
        [](const InnerSphereTree& a, py::object pose_a, const InnerSphereTree& b, py::object pose_b,
           std::uint64_t max_node_tests) {
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            py::gil_scoped_release nogil;
            return sphere_distance(a, pa, b, pb, ist_request(max_node_tests, false));
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("max_node_tests") = 0,
        "Smallest distance between the inner spheres of a and of b.");
    py::class_<Wrench>(m, "Wrench", "Force and torque in the world frame.")
        .def_property_readonly("force", [](const Wrench& w) { return to_array(w.force); })
        .def_property_readonly("torque", [](const Wrench& w) { return to_array(w.torque); });
    py::class_<PenaltyWrench>(m, "PenaltyWrench", "The penalty wrenches on both objects.")
        .def_readonly("on_a", &PenaltyWrench::on_a)
        .def_readonly("on_b", &PenaltyWrench::on_b)
        .def_readonly("pairs", &PenaltyWrench::pairs);
    m.def(
        "penalty_wrench",
        [](const PenetrationVolumeResult& volume, const InnerSphereTree& a, py::object pose_a, const InnerSphereTree& b,
           py::object pose_b, double stiffness, py::object reference_a, py::object reference_b) {
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            const V3 ra = reference_a.is_none() ? pa.t : vec3(reference_a, "reference_a");
            const V3 rb = reference_b.is_none() ? pb.t : vec3(reference_b, "reference_b");
            if (!std::isfinite(stiffness)) throw py::value_error("stiffness must be finite");
            py::gil_scoped_release nogil;
            return penalty_wrench(volume, a, pa, b, pb, stiffness, ra, rb);
        },
        py::arg("volume"), py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("stiffness"),
        py::arg("reference_a") = py::none(), py::arg("reference_b") = py::none(),
        "Penalty force and torques from a complete penetration_volume() result with pairs, at the same poses "
        "(torques about the reference points; None: the poses' origins).");
}

}  // namespace cdkit::python
