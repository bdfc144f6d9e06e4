// hymm-slam: EKF feature SLAM with dense layers on an MRPT rawlog.
// All behaviour lives in hymm::app::SlamApp; this only parses and reports.
#include <hymm/app/SlamApp.h>
#include <hymm/core/error_message.h>

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
        std::cerr << "hymm-slam: error: "
                  << hymm::core::errorMessage(e, hymm::core::hasFlag(argc, argv, "--verbose")) << "\n";
        return 1;
    }
}
