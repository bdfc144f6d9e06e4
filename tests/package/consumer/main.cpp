// A program outside the HYMM tree that links the installed package (hymm::sim) and
// checks a laser ray against a landmark of a simulated world.
#include <hymm/sim/World.h>

#include <cmath>
#include <iostream>

int main()
{
    hymm::sim::Landmark pole;
    pole.id = 0;
    pole.position = hymm::sim::Vec2(10.0, 0.0);
    pole.radius = 0.5;
    const hymm::sim::World world({pole}, {});
    const auto snap = world.snapshot(0.0, hymm::sim::Vec2::Zero(), 50.0);
    const auto hit = snap.castRay(hymm::sim::Vec2::Zero(), 0.0, 50.0);
    if (!hit || std::abs(hit->range - 9.5) > 1e-9) return 1;
    std::cout << "consumer ok\n";
    return 0;
}
