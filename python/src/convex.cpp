// Convex shapes, GJK (boolean and distance, with GjkCache) and EPA (penetration). The shape pairs dispatch to the
// double instances compiled into libcdkit (narrowphase/precompiled_queries.hpp), so this unit instantiates no GJK.
#include "common.hpp"

#include <cdkit/narrowphase/epa.hpp>
#include <cdkit/narrowphase/gjk.hpp>

namespace cdkit::python {

ShapeVar shape_of(py::handle obj, const char* name) {
    if (py::isinstance<Sphere<double>>(obj)) return &obj.cast<const Sphere<double>&>();
    if (py::isinstance<Box<double>>(obj)) return &obj.cast<const Box<double>&>();
    if (py::isinstance<Capsule<double>>(obj)) return &obj.cast<const Capsule<double>&>();
    if (py::isinstance<Cylinder<double>>(obj)) return &obj.cast<const Cylinder<double>&>();
    if (py::isinstance<Cone<double>>(obj)) return &obj.cast<const Cone<double>&>();
    if (py::isinstance<Ellipsoid<double>>(obj)) return &obj.cast<const Ellipsoid<double>&>();
    if (py::isinstance<ConvexTriangle<double>>(obj)) return &obj.cast<const ConvexTriangle<double>&>();
    if (py::isinstance<Polyhedron>(obj)) return &obj.cast<const Polyhedron&>();
    throw py::type_error(std::string(name) + ": expected a convex shape (Sphere, Box, Capsule, Cylinder, Cone, "
                                             "Ellipsoid, ConvexTriangle, ConvexPolyhedron), got " +
                         std::string(py::str(py::type::of(obj))));
}

namespace {
template <class T> std::string shape_repr(const char* name, const T& v) {
    return std::string("<cdkit.") + name + " " + v + ">";
}

GjkSettings<double> gjk_settings(py::handle h) { return h.is_none() ? GjkSettings<double>{} : h.cast<GjkSettings<double>>(); }
GjkCache<double>* gjk_cache(py::handle h) { return h.is_none() ? nullptr : &h.cast<GjkCache<double>&>(); }
}  // namespace

void init_convex(py::module_& m) {
    py::class_<Sphere<double>>(m, "Sphere", "Ball of `radius` centred at the origin of its frame.")
        .def(py::init([](double r) {
                 if (!std::isfinite(r) || r < 0) throw py::value_error("radius must be finite and >= 0");
                 return Sphere<double>(r);
             }),
             py::arg("radius"))
        .def_readonly("radius", &Sphere<double>::radius)
        .def("support", [](const Sphere<double>& s, py::object d) { return to_array(s.support(vec3(d, "direction"))); },
             py::arg("direction"), "The point of the shape farthest along `direction` (local frame).")
        .def("__repr__", [](const Sphere<double>& s) { return "<cdkit.Sphere radius=" + std::to_string(s.radius) + ">"; });
    py::class_<Box<double>>(m, "Box", "Box with the given half extents, centred and axis-aligned in its frame.")
        .def(py::init([](py::object h) { return Box<double>(vec3(h, "half_extents")); }), py::arg("half_extents"))
        .def_property_readonly("half_extents", [](const Box<double>& b) { return to_array(b.half); })
        .def("support", [](const Box<double>& s, py::object d) { return to_array(s.support(vec3(d, "direction"))); },
             py::arg("direction"));
    py::class_<Capsule<double>>(m, "Capsule", "Segment from (0,0,-half_length) to (0,0,+half_length) grown by radius.")
        .def(py::init([](double r, double h) {
                 if (!std::isfinite(r) || !std::isfinite(h)) throw py::value_error("sizes must be finite");
                 return Capsule<double>(r, h);
             }),
             py::arg("radius"), py::arg("half_length"))
        .def_readonly("radius", &Capsule<double>::radius)
        .def_readonly("half_length", &Capsule<double>::half_length)
        .def("support", [](const Capsule<double>& s, py::object d) { return to_array(s.support(vec3(d, "direction"))); },
             py::arg("direction"));
    py::class_<Cylinder<double>>(m, "Cylinder", "Cylinder along z, from -half_height to +half_height.")
        .def(py::init([](double r, double h) {
                 if (!std::isfinite(r) || !std::isfinite(h)) throw py::value_error("sizes must be finite");
                 return Cylinder<double>(r, h);
             }),
             py::arg("radius"), py::arg("half_height"))
        .def_readonly("radius", &Cylinder<double>::radius)
        .def_readonly("half_height", &Cylinder<double>::half_height)
        .def("support", [](const Cylinder<double>& s, py::object d) { return to_array(s.support(vec3(d, "direction"))); },
             py::arg("direction"));
    py::class_<Cone<double>>(m, "Cone", "Cone along z: base disc of `radius` at -half_height, apex at +half_height.")
        .def(py::init([](double r, double h) {
                 if (!std::isfinite(r) || !std::isfinite(h)) throw py::value_error("sizes must be finite");
                 return Cone<double>(r, h);
             }),
             py::arg("radius"), py::arg("half_height"))
        .def_readonly("radius", &Cone<double>::radius)
        .def_readonly("half_height", &Cone<double>::half_height)
        .def("support", [](const Cone<double>& s, py::object d) { return to_array(s.support(vec3(d, "direction"))); },
             py::arg("direction"));
    py::class_<Ellipsoid<double>>(m, "Ellipsoid", "Ellipsoid with the given semi-axes along x, y, z.")
        .def(py::init([](py::object r) { return Ellipsoid<double>(vec3(r, "radii")); }), py::arg("radii"))
        .def_property_readonly("radii", [](const Ellipsoid<double>& e) { return to_array(e.radii); })
        .def("support", [](const Ellipsoid<double>& s, py::object d) { return to_array(s.support(vec3(d, "direction"))); },
             py::arg("direction"));
    py::class_<ConvexTriangle<double>>(m, "ConvexTriangle", "A triangle as a (flat) convex shape.")
        .def(py::init([](py::object a, py::object b, py::object c) {
                 return ConvexTriangle<double>(vec3(a, "a"), vec3(b, "b"), vec3(c, "c"));
             }),
             py::arg("a"), py::arg("b"), py::arg("c"))
        .def_property_readonly("points", [](const ConvexTriangle<double>& t) { return to_array(std::vector<V3>{t.a, t.b, t.c}); })
        .def("support", [](const ConvexTriangle<double>& s, py::object d) { return to_array(s.support(vec3(d, "direction"))); },
             py::arg("direction"));
    py::class_<Polyhedron, std::shared_ptr<Polyhedron>>(
        m, "ConvexPolyhedron", "The convex hull of points (Qhull), with its topology for closest_features().")
        .def(py::init([](py::object pts) {
                 std::vector<V3> p = points(pts, "points");
                 py::gil_scoped_release nogil;
                 return std::make_shared<Polyhedron>(p);
             }),
             py::arg("points"), "From (N,3) points; raises cdkit.Error for fewer than 4 points or a flat set.")
        .def_property_readonly("vertices", [](const Polyhedron& p) { return to_array(p.vertices()); },
                               "(V,3) hull vertices.")
        .def_property_readonly("triangles", [](const Polyhedron& p) {
            std::vector<Triangle> t(p.triangles().begin(), p.triangles().end());
            return to_array(t);
        }, "(F,3) hull triangles (indices into vertices).")
        .def_property_readonly("face_count", &Polyhedron::face_count)
        .def_property_readonly("center", [](const Polyhedron& p) { return to_array(p.center()); })
        .def_property_readonly("bounding_radius", &Polyhedron::bounding_radius)
        .def("support", [](const Polyhedron& s, py::object d) { return to_array(s.support(vec3(d, "direction"))); },
             py::arg("direction"));

    py::class_<GjkSettings<double>>(m, "GjkSettings", "Tolerances of GJK (defaults as in C++).")
        .def(py::init<>())
        .def_readwrite("max_iterations", &GjkSettings<double>::max_iterations)
        .def_readwrite("rel_tolerance", &GjkSettings<double>::rel_tolerance)
        .def_readwrite("touch_factor", &GjkSettings<double>::touch_factor)
        .def_readwrite("bounding_ball_test", &GjkSettings<double>::bounding_ball_test)
        .def_readwrite("refine_near_contact", &GjkSettings<double>::refine_near_contact);
    py::class_<GjkCache<double>>(m, "GjkCache",
                                 "Caller-owned warm-start state of one shape pair: pass it as `cache=` to every query "
                                 "of that pair. Not shared between threads.")
        .def(py::init<>())
        .def_readonly("size", &GjkCache<double>::size)
        .def("reset", [](GjkCache<double>& c) { c = GjkCache<double>{}; }, "Forget the warm start.");
    py::class_<GjkResult<double>>(m, "GjkResult", "Result of gjk_distance / gjk_intersect (world frame).")
        .def_readonly("status", &GjkResult<double>::status)
        .def_readonly("colliding", &GjkResult<double>::colliding)
        .def_readonly("iterations", &GjkResult<double>::iterations)
        .def_readonly("distance", &GjkResult<double>::distance)
        .def_property_readonly("point_a", [](const GjkResult<double>& r) { return to_array(r.point_a); })
        .def_property_readonly("point_b", [](const GjkResult<double>& r) { return to_array(r.point_b); })
        .def_property_readonly("normal", [](const GjkResult<double>& r) { return to_array(r.normal); })
        .def("__repr__", [](const GjkResult<double>& r) {
            return std::string("<cdkit.GjkResult status=") + to_string(r.status) + " distance=" + std::to_string(r.distance) + ">";
        });

    m.def(
        "gjk_intersect",
        [](py::object a, py::object pose_a, py::object b, py::object pose_b, py::object cache, py::object settings) {
            const ShapeVar sa = shape_of(a, "a"), sb = shape_of(b, "b");
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            GjkCache<double>* c = gjk_cache(cache);
            const GjkSettings<double> s = gjk_settings(settings);
            py::gil_scoped_release nogil;
            return std::visit([&](auto* x, auto* y) { return gjk_intersect(*x, pa, *y, pb, c, s); }, sa, sb);
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("cache") = py::none(),
        py::arg("settings") = py::none(),
        "Boolean GJK with early exit: status separated (with a proven plane), touching or intersecting.");
    m.def(
        "gjk_distance",
        [](py::object a, py::object pose_a, py::object b, py::object pose_b, py::object cache, py::object settings) {
            const ShapeVar sa = shape_of(a, "a"), sb = shape_of(b, "b");
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            GjkCache<double>* c = gjk_cache(cache);
            const GjkSettings<double> s = gjk_settings(settings);
            py::gil_scoped_release nogil;
            return std::visit([&](auto* x, auto* y) { return gjk_distance(*x, pa, *y, pb, c, s); }, sa, sb);
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("cache") = py::none(),
        py::arg("settings") = py::none(), "Separation distance with closest points and normal (world frame).");
    m.def(
        "gjk_distance_within",
        [](py::object a, py::object pose_a, py::object b, py::object pose_b, double max_distance, py::object cache,
           py::object settings) {
            const ShapeVar sa = shape_of(a, "a"), sb = shape_of(b, "b");
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            GjkCache<double>* c = gjk_cache(cache);
            const GjkSettings<double> s = gjk_settings(settings);
            py::gil_scoped_release nogil;
            return std::visit([&](auto* x, auto* y) { return gjk_distance_within(*x, pa, *y, pb, max_distance, c, s); },
                              sa, sb);
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("max_distance"),
        py::arg("cache") = py::none(), py::arg("settings") = py::none(),
        "One GJK search for a speculative contact: colliding, or the distance with closest points when it is at most "
        "max_distance, else separated with a lower bound above max_distance as distance.");

    py::class_<EpaSettings<double>>(m, "EpaSettings", "Tolerances of EPA (penetration).")
        .def(py::init<>())
        .def_readwrite("max_iterations", &EpaSettings<double>::max_iterations)
        .def_readwrite("rel_tolerance", &EpaSettings<double>::rel_tolerance)
        .def_readwrite("gjk", &EpaSettings<double>::gjk);
    py::class_<PenetrationResult<double>>(m, "PenetrationResult",
                                          "Result of penetration(): depth bracket [depth_lower, depth], normal, deepest "
                                          "points; the distance when apart.")
        .def_readonly("status", &PenetrationResult<double>::status)
        .def_readonly("colliding", &PenetrationResult<double>::colliding)
        .def_readonly("depth", &PenetrationResult<double>::depth)
        .def_readonly("depth_lower", &PenetrationResult<double>::depth_lower)
        .def_readonly("distance", &PenetrationResult<double>::distance)
        .def_readonly("gjk_iterations", &PenetrationResult<double>::gjk_iterations)
        .def_readonly("epa_iterations", &PenetrationResult<double>::epa_iterations)
        .def_property_readonly("normal", [](const PenetrationResult<double>& r) { return to_array(r.normal); })
        .def_property_readonly("point_a", [](const PenetrationResult<double>& r) { return to_array(r.point_a); })
        .def_property_readonly("point_b", [](const PenetrationResult<double>& r) { return to_array(r.point_b); });
    m.def(
        "penetration",
        [](py::object a, py::object pose_a, py::object b, py::object pose_b, py::object settings) {
            const ShapeVar sa = shape_of(a, "a"), sb = shape_of(b, "b");
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            const EpaSettings<double> s = settings.is_none() ? EpaSettings<double>{} : settings.cast<EpaSettings<double>>();
            py::gil_scoped_release nogil;
            return std::visit([&](auto* x, auto* y) { return penetration(*x, pa, *y, pb, s); }, sa, sb);
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("settings") = py::none(),
        "Penetration depth, normal (moving b by depth*normal separates them) and deepest points (GJK + EPA).");
}

}  // namespace cdkit::python
