// The coherent-motion queries with their caller-owned caches: separating planes, closest features (V-Clip-style
// walk on polyhedra), and the convex time of impact (conservative advancement).
#include "common.hpp"

#include <cdkit/ccd/convex_toi.hpp>
#include <cdkit/narrowphase/closest_features.hpp>
#include <cdkit/narrowphase/separating_plane.hpp>

namespace cdkit::python {

void init_convex_cached(py::module_& m) {
    py::class_<SeparatingPlaneCache<double>>(m, "SeparatingPlaneCache",
                                             "Caller-owned per-pair state of separating_plane_intersect: the last "
                                             "plane and a GjkCache.")
        .def(py::init<>())
        .def_readonly("valid", &SeparatingPlaneCache<double>::valid)
        .def_property_readonly("normal", [](const SeparatingPlaneCache<double>& c) { return to_array(c.n); })
        .def_readonly("offset", &SeparatingPlaneCache<double>::c)
        .def("reset", [](SeparatingPlaneCache<double>& c) { c = SeparatingPlaneCache<double>{}; });
    py::class_<SeparatingPlaneResult<double>>(m, "SeparatingPlaneResult", "Result of separating_plane_intersect().")
        .def_readonly("status", &SeparatingPlaneResult<double>::status)
        .def_readonly("colliding", &SeparatingPlaneResult<double>::colliding)
        .def_readonly("used_gjk", &SeparatingPlaneResult<double>::used_gjk)
        .def_readonly("repaired", &SeparatingPlaneResult<double>::repaired)
        .def_readonly("iterations", &SeparatingPlaneResult<double>::iterations);
    py::class_<SeparatingPlaneSettings>(m, "SeparatingPlaneSettings", "Tuning of the plane search (defaults as in C++).")
        .def(py::init<>())
        .def_readwrite("max_iterations", &SeparatingPlaneSettings::max_iterations)
        .def_readwrite("repair_iterations", &SeparatingPlaneSettings::repair_iterations)
        .def_readwrite("eta", &SeparatingPlaneSettings::eta)
        .def_readwrite("repair_eta", &SeparatingPlaneSettings::repair_eta)
        .def_readwrite("eta_decay", &SeparatingPlaneSettings::eta_decay);
    m.def(
        "separating_plane_intersect",
        [](py::object a, py::object pose_a, py::object b, py::object pose_b, py::object cache, py::object settings) {
            const ShapeVar sa = shape_of(a, "a"), sb = shape_of(b, "b");
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            SeparatingPlaneCache<double>* c = cache.is_none() ? nullptr : &cache.cast<SeparatingPlaneCache<double>&>();
            const SeparatingPlaneSettings s =
                settings.is_none() ? SeparatingPlaneSettings{} : settings.cast<SeparatingPlaneSettings>();
            py::gil_scoped_release nogil;
            return std::visit([&](auto* x, auto* y) { return separating_plane_intersect(*x, pa, *y, pb, c, s); }, sa, sb);
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("cache") = py::none(),
        py::arg("settings") = py::none(),
        "Boolean test from a cached separating plane (GJK when the plane search is undecided).");

    py::enum_<FeatureType>(m, "FeatureType").value("vertex", FeatureType::vertex).value("edge", FeatureType::edge).value("face", FeatureType::face);
    py::class_<Feature>(m, "Feature", "A vertex, edge or face of a ConvexPolyhedron.")
        .def_readonly("type", &Feature::type)
        .def_readonly("index", &Feature::index)
        .def("__repr__", [](const Feature& f) {
            const char* t = f.type == FeatureType::vertex ? "vertex" : f.type == FeatureType::edge ? "edge" : "face";
            return std::string("<cdkit.Feature ") + t + " " + std::to_string(f.index) + ">";
        });
    py::class_<ClosestFeatureSettings<double>>(m, "ClosestFeatureSettings", "Tuning of the closest-feature walk (defaults as in C++).")
        .def(py::init<>())
        .def_readwrite("max_iterations", &ClosestFeatureSettings<double>::max_iterations)
        .def_readwrite("touch_factor", &ClosestFeatureSettings<double>::touch_factor)
        .def_readwrite("rel_tolerance", &ClosestFeatureSettings<double>::rel_tolerance);
    py::class_<ClosestFeatureCache<double>>(m, "ClosestFeatureCache",
                                            "Caller-owned per-pair state of closest_features: the last feature pair.")
        .def(py::init<>())
        .def_readonly("valid", &ClosestFeatureCache<double>::valid)
        .def_readonly("feature_a", &ClosestFeatureCache<double>::a)
        .def_readonly("feature_b", &ClosestFeatureCache<double>::b)
        .def("reset", [](ClosestFeatureCache<double>& c) { c = ClosestFeatureCache<double>{}; });
    py::class_<ClosestFeatureResult<double>>(m, "ClosestFeatureResult", "Result of closest_features(): distance, closest points, the final feature pair.")
        .def_readonly("status", &ClosestFeatureResult<double>::status)
        .def_readonly("colliding", &ClosestFeatureResult<double>::colliding)
        .def_readonly("distance", &ClosestFeatureResult<double>::distance)
        .def_property_readonly("point_a", [](const ClosestFeatureResult<double>& r) { return to_array(r.point_a); })
        .def_property_readonly("point_b", [](const ClosestFeatureResult<double>& r) { return to_array(r.point_b); })
        .def_property_readonly("normal", [](const ClosestFeatureResult<double>& r) { return to_array(r.normal); })
        .def_readonly("feature_a", &ClosestFeatureResult<double>::feature_a)
        .def_readonly("feature_b", &ClosestFeatureResult<double>::feature_b)
        .def_readonly("iterations", &ClosestFeatureResult<double>::iterations)
        .def_readonly("cycle", &ClosestFeatureResult<double>::cycle)
        .def_readonly("used_gjk", &ClosestFeatureResult<double>::used_gjk);
    m.def(
        "closest_features",
        [](const Polyhedron& a, py::object pose_a, const Polyhedron& b, py::object pose_b, py::object cache,
           py::object settings) {
            const Pose pa = pose(pose_a, "pose_a"), pb = pose(pose_b, "pose_b");
            ClosestFeatureCache<double>* c = cache.is_none() ? nullptr : &cache.cast<ClosestFeatureCache<double>&>();
            const ClosestFeatureSettings<double> s =
                settings.is_none() ? ClosestFeatureSettings<double>{} : settings.cast<ClosestFeatureSettings<double>>();
            py::gil_scoped_release nogil;
            return closest_features(a, pa, b, pb, c, s);
        },
        py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("cache") = py::none(),
        py::arg("settings") = py::none(),
        "Distance of two ConvexPolyhedra by walking their closest features from the cache's pair.");

    py::class_<ToiRequest>(m, "ToiRequest",
                           "Settings of convex_toi(): contact tolerance (absolute), the advancement step cap, and the "
                           "separation at which contact counts (the shapes grown by it).")
        .def(py::init([](double tolerance, int max_iterations, double separation) {
                 ToiRequest r;
                 r.tolerance = tolerance;
                 r.max_iterations = max_iterations;
                 r.separation = separation;
                 return r;
             }),
             py::arg("tolerance") = 1e-6, py::arg("max_iterations") = 512, py::arg("separation") = 0.0)
        .def_readwrite("tolerance", &ToiRequest::tolerance)
        .def_readwrite("max_iterations", &ToiRequest::max_iterations)
        .def_readwrite("separation", &ToiRequest::separation);
    py::class_<ToiResult>(m, "ToiResult", "Result of convex_toi(): no contact before `toi`.")
        .def_readonly("status", &ToiResult::status)
        .def_readonly("colliding", &ToiResult::colliding)
        .def_readonly("toi", &ToiResult::toi)
        .def_property_readonly("point_a", [](const ToiResult& r) { return to_array(r.point_a); })
        .def_property_readonly("point_b", [](const ToiResult& r) { return to_array(r.point_b); })
        .def_property_readonly("normal", [](const ToiResult& r) { return to_array(r.normal); })
        .def_readonly("iterations", &ToiResult::iterations)
        .def_readonly("capped", &ToiResult::capped);
    m.def(
        "convex_toi",
        [](py::object a, py::object a_start, py::object a_end, py::object b, py::object b_start, py::object b_end,
           py::object request) {
            const ShapeVar sa = shape_of(a, "a"), sb = shape_of(b, "b");
            const Pose a0 = pose(a_start, "a_start"), a1 = pose(a_end, "a_end"), b0 = pose(b_start, "b_start"),
                       b1 = pose(b_end, "b_end");
            const ToiRequest req = request.is_none() ? ToiRequest{} : request.cast<ToiRequest>();
            py::gil_scoped_release nogil;
            return std::visit([&](auto* x, auto* y) { return convex_toi(*x, a0, a1, *y, b0, b1, req); }, sa, sb);
        },
        py::arg("a"), py::arg("a_start"), py::arg("a_end"), py::arg("b"), py::arg("b_start"), py::arg("b_end"),
        py::arg("request") = py::none(),
        "Time of impact of two convex shapes moving from their start to their end poses (conservative advancement).");
}

}  // namespace cdkit::python
