// hymm-slam: EKF feature SLAM with dense layers on an MRPT rawlog.
// All behaviour lives in hymm::denseslam::SlamApp; this only parses and reports.
#include <hymm/denseslam/SlamApp.h>
#include <mrpt/core/exceptions.h>

#include <iostream>

int main(int argc, char** argv)
{
    try
    {
        hymm::denseslam::SlamApp::Args args;
        if (!hymm::denseslam::parseSlamArgs(argc, argv, args, std::cout)) return 0;
        hymm::denseslam::SlamApp app(args);
        app.run(std::cerr);
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-slam: error: " << mrpt::exception_to_str(e) << "\n";
        return 1;
    }
}
