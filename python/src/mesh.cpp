// MeshModel (every BV type behind one class), collide / distance with their requests and results.
#include "common.hpp"

#include <cdkit/distance.hpp>
#include <cdkit/io/load_mesh.hpp>
#include <cdkit/query.hpp>

#include <limits>

namespace cdkit::python {

namespace {
template <class BV> ModelVar build(TriangleMesh<double> mesh, const BuildOptions& options) {
    return std::make_shared<const MeshModel<BV>>(std::move(mesh), options);
}

PyMeshModel make_model(TriangleMesh<double> mesh, BV bv, const BuildOptions& options) {
    PyMeshModel out;
    out.bv = bv;
    py::gil_scoped_release nogil;
    switch (bv) {
        case BV::aabb: out.model = build<Aabb<double>>(std::move(mesh), options); break;
        case BV::obb: out.model = build<Obb<double>>(std::move(mesh), options); break;
        case BV::rss: out.model = build<Rss<double>>(std::move(mesh), options); break;
        case BV::kdop18: out.model = build<Kdop<double, 18>>(std::move(mesh), options); break;
        case BV::sphere: out.model = build<BoundingSphere<double>>(std::move(mesh), options); break;
    }
    return out;
}

BV bv_from(py::handle h) {
    if (py::isinstance<py::str>(h)) {
        const std::string s = h.cast<std::string>();
        for (BV b : {BV::aabb, BV::obb, BV::rss, BV::kdop18, BV::sphere})
            if (s == bv_name(b)) return b;
        throw py::value_error("bv: expected one of 'aabb', 'obb', 'rss', 'kdop18', 'sphere', got '" + s + "'");
    }
    return h.cast<BV>();
}

py::array_t<std::int64_t> contact_pairs(const CollisionResult<double>& r) {
    py::array_t<std::int64_t> a({py::ssize_t(r.contacts.size()), py::ssize_t(2)});
    auto w = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < r.contacts.size(); ++i) {
        w(py::ssize_t(i), 0) = r.contacts[i].triangle_a;
        w(py::ssize_t(i), 1) = r.contacts[i].triangle_b;
    }
    return a;
}
}  // namespace

void init_mesh(py::module_& m) {
    py::enum_<SplitStrategy>(m, "SplitStrategy", "How the BVH build splits a node.")
        .value("median", SplitStrategy::median)
        .value("mean", SplitStrategy::mean)
        .value("sah", SplitStrategy::sah)
        .value("pca_volume", SplitStrategy::pca_volume);

    py::class_<PyMeshModel>(m, "MeshModel",
                            "A triangle mesh with its bounding volume hierarchy (cdkit::MeshModel<BV>). Built once; "
                            "queries never copy it. Two models meet in a query only when they use the same `bv`.")
        .def(py::init([](py::object vertices, py::object faces, py::object bv, py::object split, std::size_t leaf_size,
                         std::string source) {
                 TriangleMesh<double> mesh = mesh_from_arrays(vertices, faces, source);
                 const BV kind = bv_from(bv);
                 BuildOptions o;
                 if (!split.is_none()) o.split = split.cast<SplitStrategy>();
                 if (leaf_size > 0) o.max_leaf_triangles = std::uint32_t(leaf_size);
                 return make_model(std::move(mesh), kind, o);
             }),
             py::arg("vertices"), py::arg("faces"), py::arg("bv") = "obb", py::arg("split") = py::none(),
             py::arg("leaf_size") = 0, py::arg("source") = "<mesh>",
             "From (N,3) float vertices and (M,3) integer faces. `bv`: 'aabb', 'obb' (default), 'rss', 'kdop18', "
             "'sphere' or a cdkit.BV; `split`: a cdkit.SplitStrategy (None: sah); `leaf_size`: "
             "triangles per leaf (0: default). Raises ValueError for bad arrays, cdkit.Error for a bad mesh.")
        .def_static(
            "from_file",
            [](const std::string& path, py::object bv) {
                const BV kind = bv_from(bv);
                TriangleMesh<double> mesh;
                {
                    py::gil_scoped_release nogil;
                    mesh = load_mesh(path);
                }
                return make_model(std::move(mesh), kind, BuildOptions{});
            },
            py::arg("path"), py::arg("bv") = "obb", "Loads a mesh file and builds its tree.")
        .def_property_readonly("bv", [](const PyMeshModel& s) { return s.bv; })
        .def_property_readonly("vertices", [](const PyMeshModel& s) { return to_array(s.mesh().vertices); },
                               "(N,3) float64 copy of the vertices.")
        .def_property_readonly("faces", [](const PyMeshModel& s) { return to_array(s.mesh().triangles); },
                               "(M,3) int64 copy of the triangles.")
        .def_property_readonly("num_triangles", [](const PyMeshModel& s) { return s.mesh().num_triangles(); })
        .def_property_readonly("num_vertices", [](const PyMeshModel& s) { return s.mesh().num_vertices(); })
        .def_property_readonly("memory_bytes",
                               [](const PyMeshModel& s) { return visit_model(s, [](const auto& x) { return x.memory_bytes(); }); },
                               "Bytes of the tree alone.")
        .def_property_readonly("num_nodes",
                               [](const PyMeshModel& s) { return visit_model(s, [](const auto& x) { return x.bvh().nodes().size(); }); })
        .def("validate", [](const PyMeshModel& s) { visit_model(s, [](const auto& x) { x.validate(); }); },
             "Checks the tree against the mesh; raises cdkit.Error on a broken invariant.")
        .def("__repr__", [](const PyMeshModel& s) {
            return "<cdkit.MeshModel bv=" + std::string(bv_name(s.bv)) + " triangles=" + std::to_string(s.mesh().num_triangles()) + ">";
        });

    py::class_<CollisionRequest>(m, "CollisionRequest", "What collide() reports.")
        .def(py::init([](ContactMode mode, std::size_t max_contacts) {
                 CollisionRequest r;
                 r.mode = mode;
                 r.max_contacts = max_contacts;
                 return r;
             }),
             py::arg("mode") = ContactMode::first, py::arg("max_contacts") = std::numeric_limits<std::size_t>::max())
        .def_readwrite("mode", &CollisionRequest::mode)
        .def_readwrite("max_contacts", &CollisionRequest::max_contacts);

    py::class_<TraversalStats>(m, "TraversalStats", "Work counters of one traversal.")
        .def_readonly("bv_tests", &TraversalStats::bv_tests)
        .def_readonly("leaf_pairs", &TraversalStats::leaf_pairs)
        .def_readonly("primitive_tests", &TraversalStats::primitive_tests);
    py::class_<CollisionStats, TraversalStats>(m, "CollisionStats", "Work counters of one collide() query.");

    py::class_<Contact<double>>(m, "Contact", "One intersecting triangle pair (world frame).")
        .def_readonly("triangle_a", &Contact<double>::triangle_a)
        .def_readonly("triangle_b", &Contact<double>::triangle_b)
        .def_property_readonly("point", [](const Contact<double>& c) { return to_array(c.point); })
        .def_property_readonly("segment",
                               [](const Contact<double>& c) { return to_array(std::vector<V3>{c.segment[0], c.segment[1]}); },
                               "(2,3): the intersection segment's end points.")
        .def_readonly("coplanar", &Contact<double>::coplanar);

    py::class_<CollisionResult<double>>(m, "CollisionResult", "Result of collide(): status, colliding, contacts.")
        .def_readonly("status", &CollisionResult<double>::status)
        .def_readonly("colliding", &CollisionResult<double>::colliding)
        .def_readonly("truncated", &CollisionResult<double>::truncated)
        .def_readonly("contacts", &CollisionResult<double>::contacts)
        .def_readonly("stats", &CollisionResult<double>::stats)
        .def_property_readonly("triangle_pairs", &contact_pairs, "(K,2) int64: (triangle_a, triangle_b) per contact.")
        .def_property_readonly(
            "points",
            [](const CollisionResult<double>& r) {
                std::vector<V3> p;
                for (const auto& c : r.contacts) p.push_back(c.point);
                return to_array(p);
            },
            "(K,3) float64: each contact's witness point (world).")
        .def("__bool__", [](const CollisionResult<double>& r) { return r.colliding; })
        .def("__repr__", [](const CollisionResult<double>& r) {
            return std::string("<cdkit.CollisionResult status=") + to_string(r.status) +
                   " colliding=" + (r.colliding ? "True" : "False") + " contacts=" + std::to_string(r.contacts.size()) + ">";
        });

    py::class_<DistanceRequest<double>>(m, "DistanceRequest", "Accuracy and range wanted from distance(): "
                                                              "distance <= (1 + rel_err) * true + abs_err; pairs farther "
                                                              "apart than max_distance report inf.")
        .def(py::init(&distance_request),
             py::arg("rel_err") = 0.0, py::arg("abs_err") = 0.0,
             py::arg("max_distance") = std::numeric_limits<double>::infinity())
        .def_readonly("rel_err", &DistanceRequest<double>::rel_err)
        .def_readonly("abs_err", &DistanceRequest<double>::abs_err)
        .def_readonly("max_distance", &DistanceRequest<double>::max_distance);
    py::class_<DistanceStats>(m, "DistanceStats", "Work counters of one distance() query.")
        .def_readonly("bv_tests", &DistanceStats::bv_tests)
        .def_readonly("primitive_tests", &DistanceStats::primitive_tests)
        .def_readonly("primitive_skips", &DistanceStats::primitive_skips);
    py::class_<DistanceResult<double>>(m, "DistanceResult", "Result of distance(): world-frame closest points.")
        .def_readonly("status", &DistanceResult<double>::status)
        .def_readonly("distance", &DistanceResult<double>::distance)
        .def_property_readonly("point_a", [](const DistanceResult<double>& r) { return to_array(r.point_a); })
        .def_property_readonly("point_b", [](const DistanceResult<double>& r) { return to_array(r.point_b); })
        .def_readonly("triangle_a", &DistanceResult<double>::triangle_a)
        .def_readonly("triangle_b", &DistanceResult<double>::triangle_b)
        .def_readonly("stats", &DistanceResult<double>::stats)
        .def("__repr__", [](const DistanceResult<double>& r) {
            return std::string("<cdkit.DistanceResult status=") + to_string(r.status) + " distance=" + std::to_string(r.distance) + ">";
        });

    m.def(
        "collide",
        [](const PyMeshModel& a, py::object pose_a, const PyMeshModel& b, py::object pose_b, py::object request) {
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            const CollisionRequest req = request.is_none() ? CollisionRequest{} : request.cast<CollisionRequest>();
            return visit_pair(a, b, [&](const auto& x, const auto& y) {
                py::gil_scoped_release nogil;
                return collide(x, pa, y, pb, req);
            });
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("request") = py::none(),
        "Mesh-mesh collision at world poses (4x4 or (R, t)): the first contact, or all with "
        "CollisionRequest(ContactMode.all). A pose that is not a rigid motion gives status invalid_pose.");
    m.def(
        "collide_brute_force",
        [](const PyMeshModel& a, py::object pose_a, const PyMeshModel& b, py::object pose_b, py::object request) {
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            const CollisionRequest req = request.is_none() ? CollisionRequest{} : request.cast<CollisionRequest>();
            py::gil_scoped_release nogil;
            return collide_brute_force(a.mesh(), pa, b.mesh(), pb, req);
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("request") = py::none(),
        "The all-pairs reference of collide(), O(n*m) (on the models' meshes).");
    m.def(
        "distance",
        [](const PyMeshModel& a, py::object pose_a, const PyMeshModel& b, py::object pose_b, py::object request) {
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            const DistanceRequest<double> req =
                request.is_none() ? DistanceRequest<double>{} : request.cast<DistanceRequest<double>>();
            return visit_pair(a, b, [&](const auto& x, const auto& y) -> DistanceResult<double> {
                py::gil_scoped_release nogil;
                return distance(x, pa, y, pb, req);
            });
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("request") = py::none(),
        "Separation distance of two meshes (0 when they touch) with closest points and triangles.");
    m.def(
        "distance_brute_force",
        [](const PyMeshModel& a, py::object pose_a, const PyMeshModel& b, py::object pose_b) {
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            py::gil_scoped_release nogil;
            return distance_brute_force(a.mesh(), pa, b.mesh(), pb);
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), "The all-pairs reference of distance().");
}

}  // namespace cdkit::python
