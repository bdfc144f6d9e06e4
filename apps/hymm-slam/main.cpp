// hymm-slam: EKF feature SLAM with dense layers on an MRPT rawlog.
// All behaviour lives in hymm::app::SlamApp; this only parses and reports.
#include <hymm/app/SlamApp.h>
#include <mrpt/core/exceptions.h>

#include <iostream>

int main(int argc, char** argv)
{
    try
    {
        hymm::app::SlamApp::Args args;
        if (!hymm::app::parseSlamArgs(argc, argv, args, std::cout)) return 0;
        hymm::app::SlamApp app(args);
        app.run(std::cerr);
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-slam: error: " << mrpt::exception_to_str(e) << "\n";
        return 1;
    }
}
