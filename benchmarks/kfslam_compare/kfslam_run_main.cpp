// hymm-kfslam-run: runs MRPT's CRangeBearingKFSLAM2D (the filter behind the kf-slam app)
// on a rawlog exactly as kf-slam does (same ini sections, same action/observation pairs
// from CRawlog::readActionObservationPair) and writes what kf-slam only prints or keeps:
// the path (TUM), the final landmark map with MRPT's landmark IDs and marginal
// covariances (id,x,y,cxx,cxy,cyy) and the time of every processActionObservation call,
// so that both filters are scored by the same evaluation code (hymm-eval).
//
//   hymm-kfslam-run -c kf-slam.ini -r run.rawlog -o OUT_DIR
//
// Timing covers processActionObservation only (kf-slam's own per-step state copies,
// logging and map dumps are left out, which favours MRPT).
#include <hymm/core/command_line.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/slam/CRangeBearingKFSLAM2D.h>
#include <mrpt/system/filesystem.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <stdexcept>

namespace
{
void writeTumRow(std::ostream& f, size_t i, double x, double y, double phi)
{
    f << i << ' ' << x << ' ' << y << " 0 0 0 " << std::sin(phi / 2) << ' ' << std::cos(phi / 2) << '\n';
}
}  // namespace

int main(int argc, char** argv)
{
    try
    {
        TCLAP::CmdLine cmd("hymm-kfslam-run: MRPT CRangeBearingKFSLAM2D on a rawlog, path/map/timing out", ' ',
                           "0.1");
        TCLAP::ValueArg<std::string> ini("c", "config", "kf-slam ini file", true, "", "FILE", cmd);
        TCLAP::ValueArg<std::string> rawlog("r", "rawlog", "rawlog (action/observation format)", true, "",
                                            "FILE", cmd);
        TCLAP::ValueArg<std::string> out("o", "out", "output directory", true, "", "DIR", cmd);
        TCLAP::SwitchArg first("", "first-frame",
                               "also process a leading sensory frame (kf-slam skips it; hymm-slam does not)", cmd);
        if (const auto code = hymm::core::parseCommandLine(cmd, argc, argv)) return *code;

        if (!mrpt::system::fileExists(ini.getValue())) throw std::runtime_error("no such file: " + ini.getValue());
        if (!mrpt::system::fileExists(rawlog.getValue()))
            throw std::runtime_error("no such file: " + rawlog.getValue());
        const mrpt::config::CConfigFile cfg(ini.getValue());
        mrpt::slam::CRangeBearingKFSLAM2D slam;
        slam.loadOptions(cfg);
        slam.KF_options.verbosity_level = mrpt::system::LVL_ERROR;

        mrpt::io::CFileGZInputStream in(rawlog.getValue());
        auto arch = mrpt::serialization::archiveFrom(in);
        if (!mrpt::system::directoryExists(out.getValue()) && !mrpt::system::createDirectory(out.getValue()))
            throw std::runtime_error("cannot create '" + out.getValue() + "'");
        const std::string dir = out.getValue() + "/";
        std::ofstream path(dir + "path.tum"), timing(dir + "timing.csv");
        if (!path || !timing) throw std::runtime_error("cannot write into '" + dir + "'");
        path << std::setprecision(12);
        timing << "step,landmarks,observations,seconds\n" << std::setprecision(9);
        // kf-slam starts at the origin; readActionObservationPair skips a leading frame
        // (simul-landmarks writes the frame at the start pose first), so row 0 is that pose.
        // With --first-frame that frame is processed too, with an empty action (the filter
        // skips the prediction while its map is empty), as hymm-slam does.
        mrpt::obs::CActionCollection::Ptr action;
        mrpt::obs::CSensoryFrame::Ptr frame;
        mrpt::poses::CPosePDFGaussian pose;
        size_t entry = 0, step = 0;
        double total = 0;
        if (first.getValue())
        {
            mrpt::serialization::CSerializable::Ptr obj;
            arch >> obj;
            frame = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj);
            if (!frame) throw std::runtime_error("--first-frame: the rawlog does not start with a sensory frame");
            action = std::make_shared<mrpt::obs::CActionCollection>();
            slam.processActionObservation(action, frame);
        }
        slam.getCurrentRobotPose(pose);
        writeTumRow(path, 0, pose.mean.x(), pose.mean.y(), pose.mean.phi());

        while (mrpt::obs::CRawlog::readActionObservationPair(arch, action, frame, entry))
        {
            const auto t0 = std::chrono::steady_clock::now();
            slam.processActionObservation(action, frame);
            const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            total += dt;
            ++step;
            slam.getCurrentRobotPose(pose);
            writeTumRow(path, step, pose.mean.x(), pose.mean.y(), pose.mean.phi());
            size_t nobs = 0;
            if (auto br = frame->getObservationByClass<mrpt::obs::CObservationBearingRange>())
                nobs = br->sensedData.size();
            timing << step << ',' << slam.getNumberOfLandmarksInTheMap() << ',' << nobs << ',' << dt << '\n';
        }
        if (step == 0) throw std::runtime_error("no action/observation pair in '" + rawlog.getValue() + "'");

        std::vector<mrpt::math::TPoint2D> lms;
        std::map<unsigned int, mrpt::maps::CLandmark::TLandmarkID> ids;
        mrpt::math::CVectorDouble x;
        mrpt::math::CMatrixDouble P;
        slam.getCurrentState(pose, lms, ids, x, P);
        std::ofstream lf(dir + "landmarks.csv");
        lf << std::setprecision(12);
        for (size_t i = 0; i < lms.size(); ++i)
        {
            const size_t k = 3 + 2 * i;
            lf << ids.at(static_cast<unsigned int>(i)) << ',' << lms[i].x << ',' << lms[i].y << ',' << P(k, k) << ','
               << P(k, k + 1) << ',' << P(k + 1, k + 1) << '\n';
        }
        if (!lf || !path || !timing) throw std::runtime_error("error writing into '" + dir + "'");
        std::cout << "steps " << step << " landmarks " << lms.size() << " seconds " << total << "\n";
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-kfslam-run: error: " << mrpt::exception_to_str(e) << "\n";
        return 1;
    }
}
