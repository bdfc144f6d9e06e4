// A program outside the HYMM tree that links the installed package.
#include <hymm/core/UteVehicleModel.h>

#include <cmath>
#include <iostream>

int main()
{
    const hymm::core::UteParams p;
    const auto x = hymm::core::uteStep(Eigen::Vector3d::Zero(), Eigen::Vector2d(1.0, 0.0), 1.0, p);
    if (std::abs(x[0] - 1.0) > 1e-12) return 1;
    std::cout << "consumer ok\n";
    return 0;
}
