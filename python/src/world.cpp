// World (objects, poses, step() through broad phase → interest matrix → narrow phase) and the broad phases.
#include "common.hpp"

#include <cdkit/broadphase/brute_force.hpp>
#include <cdkit/broadphase/dynamic_aabb_tree.hpp>
#include <cdkit/broadphase/sorted_cell_grid.hpp>
#include <cdkit/broadphase/sweep_and_prune.hpp>
#include <cdkit/broadphase/uniform_grid.hpp>
#include <cdkit/world/world.hpp>

#include <algorithm>

namespace cdkit::python {

namespace {
/// A World object's Shape from a Python shape: Sphere, Box, Capsule, ConvexPolyhedron or MeshModel.
Shape<double> world_shape(py::handle obj) {
    if (py::isinstance<Sphere<double>>(obj)) return Shape<double>::sphere(obj.cast<const Sphere<double>&>().radius);
    if (py::isinstance<Box<double>>(obj)) return Shape<double>::box(obj.cast<const Box<double>&>().half);
    if (py::isinstance<Capsule<double>>(obj)) {
        const auto& c = obj.cast<const Capsule<double>&>();
        return Shape<double>::capsule(c.radius, c.half_length);
    }
    if (py::isinstance<Cylinder<double>>(obj)) {
        const auto& c = obj.cast<const Cylinder<double>&>();
        return Shape<double>::cylinder(c.radius, c.half_height);
    }
    if (py::isinstance<Cone<double>>(obj)) {
        const auto& c = obj.cast<const Cone<double>&>();
        return Shape<double>::cone(c.radius, c.half_height);
    }
    if (py::isinstance<Ellipsoid<double>>(obj)) return Shape<double>::ellipsoid(obj.cast<const Ellipsoid<double>&>().radii);
    if (py::isinstance<ConvexTriangle<double>>(obj)) {
        const auto& t = obj.cast<const ConvexTriangle<double>&>();
        return Shape<double>::triangle(t.a, t.b, t.c);
    }
    if (py::isinstance<Polyhedron>(obj)) return Shape<double>::convex_hull(obj.cast<std::shared_ptr<Polyhedron>>());
    if (py::isinstance<PyMeshModel>(obj)) {
        const auto& m = obj.cast<const PyMeshModel&>();
        if (m.bv == BV::obb) return Shape<double>::mesh(std::get<std::shared_ptr<const MeshModel<Obb<double>>>>(m.model));
        // World meshes are OBB trees (WorldMeshModel): build one over the same mesh.
        py::gil_scoped_release nogil;
        return Shape<double>::mesh(std::make_shared<const WorldMeshModel<double>>(m.mesh_ptr()));
    }
    if (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj)) {  // a compound: [shape or (shape, pose), ...]
        std::vector<Shape<double>> children;
        for (py::handle item : obj) {
            if (py::isinstance<py::tuple>(item) && py::len(item) == 2) {
                const py::tuple t = item.cast<py::tuple>();
                children.push_back(world_shape(t[0]).with_offset(pose(t[1], "compound child pose")));
            } else {
                children.push_back(world_shape(item));
            }
        }
        return Shape<double>::compound(std::move(children));
    }
    throw py::type_error("shape: a World object is a Sphere, Box, Capsule, Cylinder, Cone, Ellipsoid, ConvexTriangle, "
                         "ConvexPolyhedron, MeshModel or a list of them (a compound; items (shape, pose) place them), got " +
                         std::string(py::str(py::type::of(obj))));
}

BroadBox<double> box_of(py::handle lo, py::handle hi) {
    BroadBox<double> b;
    b.lo = vec3(lo, "lo");
    b.hi = vec3(hi, "hi");
    if (!(b.lo.array() <= b.hi.array()).all()) throw py::value_error("lo must be <= hi in every coordinate");
    return b;
}

/// The common surface of every broad phase: insert / move / remove boxes, pairs() as a sorted (K,2) array.
template <class BP> void bind_broad_phase(py::module_& m, const char* name, const char* doc) {
    py::class_<BP>(m, name, doc)
        .def(py::init<>())
        .def("insert", [](BP& bp, py::object lo, py::object hi) { return bp.insert(box_of(lo, hi)); }, py::arg("lo"),
             py::arg("hi"), "Adds a world box (min and max corners); returns its id.")
        .def("move", [](BP& bp, ObjectId id, py::object lo, py::object hi) { bp.move(id, box_of(lo, hi)); },
             py::arg("id"), py::arg("lo"), py::arg("hi"))
        .def("remove", [](BP& bp, ObjectId id) { bp.remove(id); }, py::arg("id"))
        .def("contains", [](const BP& bp, ObjectId id) { return bp.contains(id); }, py::arg("id"))
        .def("__len__", [](const BP& bp) { return bp.size(); })
        .def(
            "pairs",
            [](BP& bp) {
                std::vector<ObjectPair> p;
                {
                    py::gil_scoped_release nogil;
                    bp.for_each_pair([&](ObjectId a, ObjectId b) { p.push_back(ObjectPair::make(a, b)); });
                    std::sort(p.begin(), p.end());
                }
                py::array_t<std::int64_t> out({py::ssize_t(p.size()), py::ssize_t(2)});
                auto w = out.mutable_unchecked<2>();
                for (std::size_t i = 0; i < p.size(); ++i) {
                    w(py::ssize_t(i), 0) = p[i].a;
                    w(py::ssize_t(i), 1) = p[i].b;
                }
                return out;
            },
            "Every overlapping pair of boxes as a (K,2) int64 array, rows (a, b) with a < b, sorted.");
}
}  // namespace

void init_world(py::module_& m) {
    bind_broad_phase<BruteForceBroadPhase<double>>(m, "BruteForceBroadPhase", "All pairs, O(n^2): the reference.");
    bind_broad_phase<SweepAndPrune<double>>(m, "SweepAndPrune", "Sweep and prune on one axis (coherent: O(n + pairs)).");
    bind_broad_phase<UniformGrid<double>>(m, "UniformGrid", "Uniform grid (cell size chosen per frame).");
    bind_broad_phase<SortedCellGrid<double>>(m, "SortedCellGrid", "Grid sorted by cell (radix sort per frame).");
    bind_broad_phase<DynamicAabbTree<double>>(m, "DynamicAabbTree", "Dynamic AABB tree with fat boxes.");

    py::enum_<BroadPhaseKind>(m, "BroadPhaseKind")
        .value("dynamic_aabb_tree", BroadPhaseKind::dynamic_aabb_tree)
        .value("sweep_and_prune", BroadPhaseKind::sweep_and_prune)
        .value("uniform_grid", BroadPhaseKind::uniform_grid)
        .value("brute_force", BroadPhaseKind::brute_force)
        .value("sorted_cell_grid", BroadPhaseKind::sorted_cell_grid);
    py::enum_<ShapeKind>(m, "ShapeKind")
        .value("sphere", ShapeKind::sphere)
        .value("box", ShapeKind::box)
        .value("capsule", ShapeKind::capsule)
        .value("convex_hull", ShapeKind::convex_hull)
        .value("mesh", ShapeKind::mesh)
        .value("cylinder", ShapeKind::cylinder)
        .value("cone", ShapeKind::cone)
        .value("ellipsoid", ShapeKind::ellipsoid)
        .value("triangle", ShapeKind::triangle)
        .value("compound", ShapeKind::compound);
    py::enum_<PairMethod>(m, "PairMethod")
        .value("convex_convex", PairMethod::convex_convex)
        .value("convex_mesh", PairMethod::convex_mesh)
        .value("mesh_mesh", PairMethod::mesh_mesh);
    py::class_<WorldOptions>(m, "WorldOptions", "How a World runs: its broad phase and whether the narrow phase runs with TBB.")
        .def(py::init([](BroadPhaseKind bp, bool parallel, std::size_t parallel_min_pairs, bool manifolds,
                         double contact_margin, bool mesh_depth) {
                 WorldOptions o;
                 o.broad_phase = bp;
                 o.parallel = parallel;
                 o.parallel_min_pairs = parallel_min_pairs;
                 o.manifolds = manifolds;
                 o.contact_margin = contact_margin;
                 o.mesh_depth = mesh_depth;
                 return o;
             }),
             py::arg("broad_phase") = BroadPhaseKind::dynamic_aabb_tree, py::arg("parallel") = false,
             py::arg("parallel_min_pairs") = 32, py::arg("manifolds") = true, py::arg("contact_margin") = 0.0,
             py::arg("mesh_depth") = true)
        .def_readwrite("manifolds", &WorldOptions::manifolds)
        .def_readwrite("mesh_depth", &WorldOptions::mesh_depth)
        .def_readwrite("contact_margin", &WorldOptions::contact_margin)
        .def_readwrite("broad_phase", &WorldOptions::broad_phase)
        .def_readwrite("parallel", &WorldOptions::parallel)
        .def_readwrite("parallel_min_pairs", &WorldOptions::parallel_min_pairs);
    py::class_<WorldContact<double>>(m, "WorldContact", "A contact between objects a < b (world frame).")
        .def_readonly("a", &WorldContact<double>::a)
        .def_readonly("b", &WorldContact<double>::b)
        .def_readonly("method", &WorldContact<double>::method)
        .def_readonly("colliding", &WorldContact<double>::colliding)
        .def_readonly("distance", &WorldContact<double>::distance)
        .def_readonly("has_depth", &WorldContact<double>::has_depth)
        .def_property_readonly(
            "points",
            [](const WorldContact<double>& c) {
                return std::vector<ManifoldPoint<double>>(c.points.begin(), c.points.begin() + c.point_count);
            },
            "The manifold's points (up to four; one for mesh and CCD contacts).")
        .def_readonly("depth", &WorldContact<double>::depth)
        .def_property_readonly("normal", [](const WorldContact<double>& c) { return to_array(c.normal); })
        .def_property_readonly("point_a", [](const WorldContact<double>& c) { return to_array(c.point_a); })
        .def_property_readonly("point_b", [](const WorldContact<double>& c) { return to_array(c.point_b); })
        .def_readonly("gjk_iterations", &WorldContact<double>::gjk_iterations)
        .def_readonly("toi", &WorldContact<double>::toi)
        .def_property_readonly(
            "child_a", [](const WorldContact<double>& c) -> py::object {
                return c.child_a == WorldContact<double>::no_child ? py::object(py::none()) : py::object(py::int_(c.child_a));
            },
            "Index of the touching child of a compound a, or None.")
        .def_property_readonly(
            "child_b", [](const WorldContact<double>& c) -> py::object {
                return c.child_b == WorldContact<double>::no_child ? py::object(py::none()) : py::object(py::int_(c.child_b));
            },
            "Index of the touching child of a compound b, or None.")
        .def("__repr__", [](const WorldContact<double>& c) {
            return "<cdkit.WorldContact " + std::to_string(c.a) + "-" + std::to_string(c.b) + " depth=" + std::to_string(c.depth) +
                   " toi=" + std::to_string(c.toi) + ">";
        });
    py::class_<WorldStepStats>(m, "WorldStepStats", "Counters of one World.step().")
        .def_readonly("broad_pairs", &WorldStepStats::broad_pairs)
        .def_readonly("tested_pairs", &WorldStepStats::tested_pairs)
        .def_readonly("contacts", &WorldStepStats::contacts)
        .def_readonly("gjk_iterations", &WorldStepStats::gjk_iterations)
        .def_readonly("ran_parallel", &WorldStepStats::ran_parallel);
    py::class_<WorldStepResult<double>>(m, "WorldStepResult", "Result of World.step(): contacts sorted by (a, b).")
        .def_readonly("contacts", &WorldStepResult<double>::contacts)
        .def_readonly("stats", &WorldStepResult<double>::stats)
        .def_property_readonly(
            "pairs",
            [](const WorldStepResult<double>& r) {
                py::array_t<std::int64_t> out({py::ssize_t(r.contacts.size()), py::ssize_t(2)});
                auto w = out.mutable_unchecked<2>();
                for (std::size_t i = 0; i < r.contacts.size(); ++i) {
                    w(py::ssize_t(i), 0) = r.contacts[i].a;
                    w(py::ssize_t(i), 1) = r.contacts[i].b;
                }
                return out;
            },
            "(K,2) int64: the object ids of each contact.");

    py::class_<World<double>>(m, "World",
                              "Objects with a shape and a pose; step() runs broad phase, interest matrix and narrow "
                              "phase. Not reentrant: one World per thread (the GIL is released during step()).")
        .def(py::init([](py::object options) {
                 return std::make_unique<World<double>>(options.is_none() ? WorldOptions{} : options.cast<WorldOptions>());
             }),
             py::arg("options") = py::none())
        .def(
            "add",
            [](World<double>& w, py::object shape, py::object pose_, double rounding) {
                Shape<double> s = world_shape(shape);
                if (rounding != 0) s = s.rounded(rounding);
                const Pose p = pose(pose_, "pose");
                return w.add(std::move(s), p);
            },
            py::arg("shape"), py::arg("pose") = py::none(), py::arg("rounding") = 0.0,
            "Adds an object (Sphere, Box, Capsule, Cylinder, Cone, Ellipsoid, ConvexTriangle, ConvexPolyhedron, "
            "MeshModel, or a list of convex shapes or (shape, pose) pairs: a compound) at `pose`; returns its id. "
            "`rounding` > 0 rounds a convex shape (its surface pushed out by that radius: a rounded box). Raises "
            "cdkit.Error for a pose that is not a rigid motion.")
        .def("remove", &World<double>::remove, py::arg("id"))
        .def(
            "set_pose", [](World<double>& w, ObjectId id, py::object pose_) { w.set_pose(id, pose(pose_, "pose")); },
            py::arg("id"), py::arg("pose"))
        .def("pose", [](const World<double>& w, ObjectId id) { return to_array(w.pose(id)); }, py::arg("id"))
        .def("set_ccd", &World<double>::set_ccd, py::arg("id"), py::arg("on"),
             "Continuous collision for this object: step() tests its motion since the previous step.")
        .def("ccd", &World<double>::ccd, py::arg("id"))
        .def("contains", &World<double>::contains, py::arg("id"))
        .def("set_parallel", &World<double>::set_parallel, py::arg("on"))
        .def("set_group", &World<double>::set_group, py::arg("id"), py::arg("group"))
        .def("set_groups_tested", &World<double>::set_groups_tested, py::arg("g"), py::arg("h"), py::arg("tested"))
        .def("set_pair_tested", &World<double>::set_pair_tested, py::arg("a"), py::arg("b"), py::arg("tested"))
        .def("pair_tested", &World<double>::pair_tested, py::arg("a"), py::arg("b"))
        .def("shape_kind", [](const World<double>& w, ObjectId id) { return w.shape(id).kind(); }, py::arg("id"))
        .def("__len__", &World<double>::size)
        .def(
            "step",
            [](World<double>& w) {
                py::gil_scoped_release nogil;
                return w.step();
            },
            "One pass of the pipeline at the current poses: a WorldStepResult.");
}

}  // namespace cdkit::python
