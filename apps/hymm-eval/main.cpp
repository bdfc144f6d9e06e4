// hymm-eval: scores a SLAM result (path in TUM format, landmark CSV) against ground
// truth with the metrics hymm-slam reports, so any program's output can be compared; or a
// path on an MRPT laser rawlog against the corrected CARMEN log of the same run, at the
// scans the two logs share (hymm/datasets/CarmenGroundTruth.h).
#include <hymm/datasets/CarmenGroundTruth.h>
#include <hymm/eval/run_metrics.h>
#include <hymm/io/ground_truth_io.h>
#include <hymm/core/command_line.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <hymm/core/error_message.h>

#include <iostream>

int main(int argc, char** argv)
{
    try
    {
        TCLAP::CmdLine cmd("hymm-eval: metrics of a SLAM result against ground truth", ' ', "0.1");
        TCLAP::SwitchArg verbose("", "verbose", "errors with MRPT's call-stack backtraces", cmd);
        TCLAP::ValueArg<std::string> path("p", "path", "estimated path (TUM)", false, "", "FILE", cmd);
        TCLAP::ValueArg<std::string> lms("l", "landmarks", "estimated landmarks id,x,y[,cxx,cxy,cyy]",
                                         false, "", "FILE", cmd);
        TCLAP::ValueArg<std::string> gtp("", "gt-path", "true path (TUM or simul-landmarks)", false,
                                         "", "FILE", cmd);
        TCLAP::ValueArg<std::string> gtl("", "gt-landmarks", "true landmarks (CSV or simul-landmarks)",
                                         false, "", "FILE", cmd);
        TCLAP::ValueArg<std::string> carmen("", "carmen",
                                            "corrected CARMEN log (.log or .log.gz) of the run of --rawlog: "
                                            "the path (one pose per scan) is scored at the scans both hold",
                                            false, "", "FILE", cmd);
        TCLAP::ValueArg<std::string> rawlog("", "rawlog", "the rawlog the path was estimated from (with --carmen)",
                                            false, "", "FILE", cmd);
        TCLAP::ValueArg<std::string> out("o", "out", "write the JSON here instead of stdout", false,
                                         "", "FILE", cmd);
        if (const auto code = hymm::core::parseCommandLine(cmd, argc, argv)) return *code;
        hymm::eval::MetricsJson j;
        if (!carmen.getValue().empty() || !rawlog.getValue().empty())
        {
            if (carmen.getValue().empty() || rawlog.getValue().empty() || path.getValue().empty())
                throw std::invalid_argument("--carmen and --rawlog go together and need --path");
            if (!lms.getValue().empty() || !gtp.getValue().empty() || !gtl.getValue().empty())
                throw std::invalid_argument(
                    "--carmen scores the path alone: --landmarks, --gt-path and --gt-landmarks do not apply");
            const auto pairing = hymm::datasets::pairScansByRanges(
                rawlog.getValue(), hymm::datasets::readCarmenLaserScans(carmen.getValue()));
            j = hymm::datasets::pairedScoreMetrics(
                pairing, hymm::datasets::scorePathAtPairs(hymm::io::readTum(path.getValue()), pairing));
        }
        else
            j = hymm::eval::evaluateResultFiles(path.getValue(), lms.getValue(),
                                                hymm::io::loadGroundTruth(gtp.getValue(), gtl.getValue()));
        if (out.getValue().empty())
        {
            std::cout << j.dump() << "\n" << std::flush;
            if (!std::cout) throw std::runtime_error("cannot write the metrics to stdout");
        }
        else
            j.save(out.getValue());
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-eval: error: " << hymm::core::errorMessage(e, hymm::core::hasFlag(argc, argv, "--verbose")) << "\n";
        return 1;
    }
}
