// The lecture's tunnelling example: a bullet (a sphere of 5 mm) crosses a sheet of paper (a box 1 mm thick) within
// one time step. A World tests the poses it is given, once per step: before and after the step the bullet is clear
// of the sheet, so without continuous collision nothing is reported and the bullet goes through. With the
// bullet's CCD flag set (World::set_ccd), step() tests its motion since the previous step and reports the contact
// with its time of impact.
// Usage: bullet_and_paper   (exits non-zero unless the first run tunnels and the second finds the contact)
#include <cdkit/world/world.hpp>

#include <cstdio>

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

namespace {

/// Fires the bullet from z = 0.5 to z = −0.5 in one step at a sheet in z = 0; returns the step's contacts.
std::vector<cdkit::WorldContact<double>> fire(bool ccd) {
    cdkit::World<double> world;
    const cdkit::ObjectId sheet = world.add(cdkit::Shape<double>::box(V(0.15, 0.1, 0.0005)), T());
    const cdkit::ObjectId bullet = world.add(cdkit::Shape<double>::sphere(0.005), T::translation(V(0.02, 0.01, 0.5)));
    world.set_ccd(bullet, ccd);
    (void)world.step();                                      // the step before: bullet far above
    world.set_pose(bullet, T::translation(V(0.02, 0.01, -0.5)));  // 1 m in one step (e.g. 1000 m/s at 1 ms)
    const auto result = world.step();
    std::printf("%s: %zu contact(s)", ccd ? "with CCD   " : "without CCD", result.contacts.size());
    for (const auto& c : result.contacts)
        std::printf(", objects %u–%u at t = %.6f of the step, normal (%.2f %.2f %.2f), sheet = %u", c.a, c.b, c.toi,
                    c.normal.x(), c.normal.y(), c.normal.z(), sheet);
    std::printf("\n");
    return result.contacts;
}

}  // namespace

int main() {
    const auto tunnelled = fire(false);
    const auto caught = fire(true);
    // The bullet's lowest point (z = 0.5 − 0.005) meets the sheet's top (z = 0.0005) after 0.4945 of the 1 m.
    const bool ok = tunnelled.empty() && caught.size() == 1 && caught[0].toi <= 0.4945 && caught[0].toi > 0.4944;
    std::printf("%s\n", ok ? "the bullet tunnels without CCD and is caught with it" : "unexpected result");
    return ok ? 0 : 1;
}
