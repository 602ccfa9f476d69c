// Penalty forces (continuity along a path, Newton's third law, pushing apart) and tree serialization
// (round trip, corrupt and truncated files rejected with the file's name).
#include "ist_test_util.hpp"

#include "cdkit/ist/penalty_force.hpp"
#include "cdkit/ist/serialize.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace cdkit;
using cdkit::test::scaled;

namespace {

// Pose of B along a path: translation through A with a slow rotation (a continuous motion).
Transform<double> path_pose(double s) {
    const Mat3<double> R = Eigen::AngleAxisd(0.8 * s, Vec3<double>(0.3, 1, 0.2).normalized()).toRotationMatrix();
    return {R, Vec3<double>(1.6 - 1.2 * s, 0.15 * s, 0.05)};
}

Wrench wrench_on_b(const InnerSphereTree& t, double s) {
    const Transform<double> pb = path_pose(s);
    const auto v = penetration_volume(t, {}, t, pb);
    return penalty_wrench(v, t, {}, t, pb, 1.0, Vec3<double>::Zero(), pb.t).on_b;
}

// Largest change of force and torque between consecutive points of an n-step walk along the path.
std::pair<double, double> max_jumps(const InnerSphereTree& t, int n) {
    double jf = 0, jt = 0;
    Wrench prev = wrench_on_b(t, 0);
    for (int i = 1; i <= n; ++i) {
        const Wrench w = wrench_on_b(t, double(i) / n);
        jf = std::max(jf, (w.force - prev.force).norm());
        jt = std::max(jt, (w.torque - prev.torque).norm());
        prev = w;
    }
    return {jf, jt};
}

std::string temp_file(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("cdkit_ist_" + name + "_" + std::to_string(::getpid()))).string();
}

}  // namespace

TEST_CASE("penalty wrench: opposite on A and B, pushes B away, torque about the reference", "[ist][force]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    const Transform<double> pb(Mat3<double>::Identity(), Vec3<double>(1.4, 0, 0));
    const auto v = penetration_volume(t, {}, t, pb);
    REQUIRE(v.volume > 0);
    const auto w = penalty_wrench(v, t, {}, t, pb, 2.0, Vec3<double>::Zero(), pb.t);
    CHECK(w.pairs == v.pairs.size());
    CHECK((w.on_a.force + w.on_b.force).norm() < 1e-12 * w.on_b.force.norm());
    CHECK(w.on_b.force.x() > 0);  // B sits at +x of A: pushed further to +x
    CHECK(w.on_b.force.norm() <= 2.0 * v.volume * (1 + 1e-12));
    CHECK(w.on_b.force.norm() > 0.2 * 2.0 * v.volume);  // mostly aligned, not cancelling
    // Torque about another point differs by (r_old − r_new) × F.
    const Vec3<double> q(0.3, -0.2, 0.5);
    const auto w2 = penalty_wrench(v, t, {}, t, pb, 2.0, Vec3<double>::Zero(), q);
    CHECK((w2.on_b.torque - (w.on_b.torque + (pb.t - q).cross(w.on_b.force))).norm() < 1e-9 * (1 + w.on_b.torque.norm()));
    // No pairs, no force.
    const auto none = penalty_wrench(PenetrationVolumeResult{}, t, {}, t, pb, 2.0, Vec3<double>::Zero(), pb.t);
    CHECK(none.on_b.force.norm() == 0);
}

TEST_CASE("penalty force and torque are continuous along a continuous path", "[ist][force]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    // A jump would stay the same size when the step shrinks; a continuous (Lipschitz) wrench's changes shrink
    // with the step. The path enters contact, so pairs appear and vanish all along it.
    const int n = scaled(100, 40);
    const auto coarse = max_jumps(t, n);
    const auto fine = max_jumps(t, 4 * n);
    INFO("force jump " << coarse.first << " -> " << fine.first << ", torque jump " << coarse.second << " -> " << fine.second);
    REQUIRE(coarse.first > 0);
    CHECK(fine.first < 0.5 * coarse.first);
    CHECK(fine.second < 0.5 * coarse.second);
}

TEST_CASE("serialization: round trip gives the same tree and answers", "[ist][serialize]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    const std::string path = temp_file("roundtrip");
    save_inner_sphere_tree(t, path);
    const InnerSphereTree u = load_inner_sphere_tree(path);
    std::filesystem::remove(path);
    REQUIRE(u.spheres().size() == t.spheres().size());
    REQUIRE(u.nodes().size() == t.nodes().size());
    for (std::size_t i = 0; i < t.spheres().size(); ++i) {
        CHECK(u.spheres()[i].center == t.spheres()[i].center);
        CHECK(u.spheres()[i].radius == t.spheres()[i].radius);
        CHECK(u.cell_weights()[i] == t.cell_weights()[i]);
    }
    for (std::size_t i = 0; i < t.nodes().size(); ++i) {
        CHECK(u.nodes()[i].center == t.nodes()[i].center);
        CHECK(u.nodes()[i].first == t.nodes()[i].first);
        CHECK(u.nodes()[i].count == t.nodes()[i].count);
    }
    CHECK(u.mesh_volume() == t.mesh_volume());
    CHECK(u.out_degree() == t.out_degree());
    CHECK(u.stats().depth == t.stats().depth);
    const Transform<double> pb(Mat3<double>::Identity(), Vec3<double>(1.3, 0.1, 0));
    CHECK(penetration_volume(u, {}, u, pb).volume == penetration_volume(t, {}, t, pb).volume);
}

TEST_CASE("serialization: corrupt, truncated, foreign and missing files raise cdkit::Error naming the file",
          "[ist][serialize]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    const auto good = serialize_inner_sphere_tree(t);
    const std::string path = temp_file("corrupt");
    auto write = [&](const std::vector<std::uint8_t>& b) {
        std::ofstream f(path, std::ios::binary | std::ios::trunc);
        f.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
    };
    auto expect = [&](const std::string& what) {
        try {
            (void)load_inner_sphere_tree(path);
            FAIL("loaded a bad file: " << what);
        } catch (const Error& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find(path) != std::string::npos);
            CHECK(std::string(e.what()).find(what) != std::string::npos);
        }
    };
    auto flipped = good;
    flipped[good.size() / 2] ^= 0x10;
    write(flipped);
    expect("checksum");
    write(std::vector<std::uint8_t>(good.begin(), good.end() - 7));
    expect("truncated");
    auto magic = good;
    magic[0] = 'X';
    write(magic);
    expect("magic");
    auto version = good;
    version[8] = 99;
    write(version);
    expect("version");
    // Version 1 (weights calibrated for the former weight-product estimate) is refused, not misread.
    REQUIRE(good[8] == 2);
    version[8] = 1;
    write(version);
    expect("format version 1");
    write({});
    expect("too short");
    std::filesystem::remove(path);
    expect("cannot open");
    // A payload that passes the checksum but breaks the tree (a child index out of range) is caught too.
    CHECK_THROWS_AS(InnerSphereTree::from_parts(t.spheres(), t.cell_weights(),
                                                std::vector<IstNode>(t.nodes().begin(), t.nodes().begin() + 1),
                                                t.mesh_volume(), t.out_degree(), "<parts>"),
                    Error);
    CHECK_NOTHROW(deserialize_inner_sphere_tree(good));
}
