// Continuous collision: vertex–face and edge–edge primitives, mesh_ccd for two rigid meshes on their trees.
#include "common.hpp"

#include <cdkit/ccd/edge_edge.hpp>
#include <cdkit/ccd/mesh_ccd.hpp>
#include <cdkit/ccd/vertex_face.hpp>

namespace cdkit::python {

namespace {
CcdRequest ccd_request(py::handle h) { return h.is_none() ? CcdRequest{} : h.cast<CcdRequest>(); }
}  // namespace

void init_ccd(py::module_& m) {
    py::class_<CcdRequest>(m, "CcdRequest", "Settings of a primitive CCD query (absolute distances).")
        .def(py::init([](double min_separation, double tolerance, double time_tolerance, double t_max, std::uint32_t max_boxes) {
                 CcdRequest r;
                 r.min_separation = min_separation;
                 r.tolerance = tolerance;
                 r.time_tolerance = time_tolerance;
                 r.t_max = t_max;
                 r.max_boxes = max_boxes;
                 return r;
             }),
             py::arg("min_separation") = 0.0, py::arg("tolerance") = 1e-6, py::arg("time_tolerance") = 1e-6,
             py::arg("t_max") = 1.0, py::arg("max_boxes") = 4096)
        .def_readwrite("min_separation", &CcdRequest::min_separation)
        .def_readwrite("tolerance", &CcdRequest::tolerance)
        .def_readwrite("time_tolerance", &CcdRequest::time_tolerance)
        .def_readwrite("t_max", &CcdRequest::t_max)
        .def_readwrite("max_boxes", &CcdRequest::max_boxes);
    py::class_<CcdStats>(m, "CcdStats", "Work done by one primitive CCD query.")
        .def_readonly("boxes", &CcdStats::boxes)
        .def_readonly("subdivisions", &CcdStats::subdivisions)
        .def_readonly("newton_steps", &CcdStats::newton_steps)
        .def_readonly("capped", &CcdStats::capped);
    py::class_<CcdResult>(m, "CcdResult", "Answer of a primitive CCD query: no contact in [0, toi).")
        .def_readonly("status", &CcdResult::status)
        .def_readonly("colliding", &CcdResult::colliding)
        .def_readonly("proven", &CcdResult::proven)
        .def_readonly("toi", &CcdResult::toi)
        .def_readonly("toi_upper", &CcdResult::toi_upper)
        .def_readonly("u", &CcdResult::u)
        .def_readonly("v", &CcdResult::v)
        .def_property_readonly("point", [](const CcdResult& r) { return to_array(r.point); })
        .def_property_readonly("normal", [](const CcdResult& r) { return to_array(r.normal); })
        .def_readonly("stats", &CcdResult::stats);
    m.def(
        "vertex_face_ccd",
        [](py::object p0, py::object a0, py::object b0, py::object c0, py::object p1, py::object a1, py::object b1,
           py::object c1, py::object request) {
            const V3 P0 = vec3(p0, "p_t0"), A0 = vec3(a0, "a_t0"), B0 = vec3(b0, "b_t0"), C0 = vec3(c0, "c_t0");
            const V3 P1 = vec3(p1, "p_t1"), A1 = vec3(a1, "a_t1"), B1 = vec3(b1, "b_t1"), C1 = vec3(c1, "c_t1");
            const CcdRequest r = ccd_request(request);
            py::gil_scoped_release nogil;
            return vertex_face_ccd(P0, A0, B0, C0, P1, A1, B1, C1, r);
        },
        py::arg("p_t0"), py::arg("a_t0"), py::arg("b_t0"), py::arg("c_t0"), py::arg("p_t1"), py::arg("a_t1"),
        py::arg("b_t1"), py::arg("c_t1"), py::arg("request") = py::none(),
        "First contact of vertex p with triangle (a, b, c), every point moving linearly from t = 0 to t = 1.");
    m.def(
        "edge_edge_ccd",
        [](py::object a00, py::object a10, py::object b00, py::object b10, py::object a01, py::object a11, py::object b01,
           py::object b11, py::object request) {
            const V3 A00 = vec3(a00, "a0_t0"), A10 = vec3(a10, "a1_t0"), B00 = vec3(b00, "b0_t0"), B10 = vec3(b10, "b1_t0");
            const V3 A01 = vec3(a01, "a0_t1"), A11 = vec3(a11, "a1_t1"), B01 = vec3(b01, "b0_t1"), B11 = vec3(b11, "b1_t1");
            const CcdRequest r = ccd_request(request);
            py::gil_scoped_release nogil;
            return edge_edge_ccd(A00, A10, B00, B10, A01, A11, B01, B11, r);
        },
        py::arg("a0_t0"), py::arg("a1_t0"), py::arg("b0_t0"), py::arg("b1_t0"), py::arg("a0_t1"), py::arg("a1_t1"),
        py::arg("b0_t1"), py::arg("b1_t1"), py::arg("request") = py::none(),
        "First contact of edge (a0, a1) with edge (b0, b1), end points moving linearly from t = 0 to t = 1.");

    py::class_<DeformableCcdRequest>(m, "DeformableCcdRequest", "What mesh_ccd() reports: the first contact or all, and the primitive queries' settings.")
        .def(py::init([](ContactMode mode, py::object primitive, bool parallel) {
                 DeformableCcdRequest r;
                 r.mode = mode;
                 r.primitive = ccd_request(primitive);
                 r.parallel = parallel;
                 return r;
             }),
             py::arg("mode") = ContactMode::first, py::arg("primitive") = py::none(), py::arg("parallel") = true)
        .def_readwrite("mode", &DeformableCcdRequest::mode)
        .def_readwrite("primitive", &DeformableCcdRequest::primitive)
        .def_readwrite("parallel", &DeformableCcdRequest::parallel);
    py::class_<CcdContact>(m, "CcdContact", "A colliding feature pair of mesh_ccd (see the C++ docs for numbering).")
        .def_readonly("vertex_face", &CcdContact::vertex_face)
        .def_readonly("a", &CcdContact::a)
        .def_readonly("b", &CcdContact::b)
        .def_readonly("ccd", &CcdContact::ccd)
        .def_readonly("vertex_on_b", &CcdContact::vertex_on_b);
    py::class_<DeformableCcdStats>(m, "DeformableCcdStats", "Candidate counts of one mesh_ccd() query.")
        .def_readonly("vertex_face_candidates", &DeformableCcdStats::vertex_face_candidates)
        .def_readonly("edge_edge_candidates", &DeformableCcdStats::edge_edge_candidates)
        .def_readonly("capped", &DeformableCcdStats::capped);
    py::class_<DeformableCcdResult>(m, "DeformableCcdResult", "Result of mesh_ccd(): first contact time over all pairs.")
        .def_readonly("status", &DeformableCcdResult::status)
        .def_readonly("colliding", &DeformableCcdResult::colliding)
        .def_readonly("toi", &DeformableCcdResult::toi)
        .def_readonly("contacts", &DeformableCcdResult::contacts)
        .def_readonly("stats", &DeformableCcdResult::stats);
    m.def(
        "mesh_ccd",
        [](const PyMeshModel& a, py::object a_start, py::object a_end, const PyMeshModel& b, py::object b_start,
           py::object b_end, py::object request) {
            const Pose a0 = pose(a_start, "a_start"), a1 = pose(a_end, "a_end"), b0 = pose(b_start, "b_start"),
                       b1 = pose(b_end, "b_end");
            const DeformableCcdRequest req = request.is_none() ? DeformableCcdRequest{} : request.cast<DeformableCcdRequest>();
            return visit_pair(a, b, [&](const auto& x, const auto& y) {
                py::gil_scoped_release nogil;
                return mesh_ccd(x, a0, a1, y, b0, b1, req);
            });
        },
        py::arg("a"), py::arg("a_start"), py::arg("a_end"), py::arg("b"), py::arg("b_start"), py::arg("b_end"),
        py::arg("request") = py::none(),
        "Continuous collision of two rigid meshes moving from their start to their end poses in one step.");
}

}  // namespace cdkit::python
