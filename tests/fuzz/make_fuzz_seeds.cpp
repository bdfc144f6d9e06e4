/**
 * @file make_fuzz_seeds.cpp
 * @brief Writes the seed corpora of the fuzz targets: short uncompressed rawlogs cut from
 *        the bundled samples, every .ini under configs/ and rawlogs/, and one small valid
 *        input of each importer format (packed as import_fuzz.cpp unpacks them).
 *
 * Usage: make_fuzz_seeds <source dir> <output dir>  (writes rawlog/, rawlog_sensors/, ini/,
 *        import/ there)
 */
#include <hymm/datasets/MatFile.h>
#include <hymm/io/RawlogReader.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRGBD360.h>
#include <mrpt/obs/CObservationRange.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CObservationStereoImagesFeatures.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/obs/gnss_messages_topcon.h>
#include <mrpt/serialization/CArchive.h>

#include <Eigen/Core>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_util.h"

namespace fs = std::filesystem;

namespace
{
// The first `n` entries of `rawlog`, uncompressed: a mutation of a gzip stream mostly
// tests zlib's checksum, and short inputs keep each execution fast.
void cutRawlog(const fs::path& rawlog, size_t n, const fs::path& out)
{
    hymm::io::RawlogReader reader(rawlog.string());
    mrpt::io::CFileOutputStream f(out.string());
    auto arch = mrpt::serialization::archiveFrom(f);
    hymm::io::RawlogEntry e;
    for (size_t i = 0; i < n && reader.next(e); ++i)
    {
        if (e.actions) arch << *e.actions;
        if (e.frame) arch << *e.frame;
        if (e.observation) arch << *e.observation;
    }
}

mrpt::img::CImage patternImage(int w, int h, mrpt::img::TImageChannels ch)
{
    mrpt::img::CImage img(w, h, ch);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < static_cast<int>(ch); ++c) *img(x, y, c) = static_cast<uint8_t>(17 * x + 5 * y + c);
    return img;
}

mrpt::obs::CObservationImage::Ptr imageObservation(int w, int h, mrpt::img::TImageChannels ch)
{
    auto obs = mrpt::obs::CObservationImage::Create();
    obs->sensorLabel = "camera";
    obs->image = patternImage(w, h, ch);
    return obs;
}

// Frames of the observation classes the pipeline does not read but MRPT builds (comment,
// range finder, IMU, GPS, grey, raw colour, JPEG and external images; in a second file,
// under 4 KB each, Velodyne, RGB-D, point-cloud and rotating scans; in a third, stereo
// images and features, an RGB-D 360 scan and Topcon GPS messages), so that the rawlog target
// mutates the sizes GuardedRawlogStream checks in them. Images are serialised when the
// frame is written, hence the JPEG switch around that write.
void sensorSeeds(const fs::path& dir)
{
    using namespace mrpt::obs;
    mrpt::io::CFileOutputStream f((dir / "sensors.rawlog").string());
    auto arch = mrpt::serialization::archiveFrom(f);
    CSensoryFrame first;
    auto comment = CObservationComment::Create();
    comment->text = "sensor seed";
    first.insert(comment);
    auto range = CObservationRange::Create();
    range->sensorLabel = "sonar";
    range->sensedData.resize(2);
    range->sensedData[1].sensedDistance = 1.5f;
    first.insert(range);
    auto imu = CObservationIMU::Create();
    imu->sensorLabel = "imu";
    imu->set(IMU_WZ, 0.1);
    first.insert(imu);
    auto gps = CObservationGPS::Create();
    gps->sensorLabel = "gps";
    gnss::Message_NMEA_GGA gga;
    gga.fields.fix_quality = 1;
    gps->setMsg(gga);
    first.insert(gps);
    arch << first;
    const bool raw = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();
    for (const bool jpeg : {false, true})
    {
        mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(!jpeg);
        CSensoryFrame images;
        images.insert(imageObservation(jpeg ? 16 : 8, jpeg ? 12 : 6, mrpt::img::CH_RGB));
        if (!jpeg)
        {
            images.insert(imageObservation(8, 6, mrpt::img::CH_GRAY));
            auto external = CObservationImage::Create();
            external->image.setExternalStorage("left_000001.png");
            images.insert(external);
        }
        arch << images;
    }
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(raw);
    mrpt::io::CFileOutputStream f2((dir / "sensor_clouds.rawlog").string());
    auto arch2 = mrpt::serialization::archiveFrom(f2);
    CSensoryFrame clouds;
    auto velodyne = CObservationVelodyneScan::Create();
    velodyne->point_cloud.x = {1.0f, 2.0f};
    velodyne->point_cloud.y = {0.5f, 0.5f};
    velodyne->point_cloud.z = {0.1f, 0.2f};
    velodyne->point_cloud.intensity = {10, 20};
    clouds.insert(velodyne);
    auto rgbd = CObservation3DRangeScan::Create();
    rgbd->hasPoints3D = true;
    rgbd->resizePoints3DVectors(3);
    rgbd->hasRangeImage = true;
    rgbd->rangeImage_setSize(3, 4);
    rgbd->rangeImage.setZero();
    rgbd->cameraParams.ncols = 4;  // the range image's size, as MRPT expects
    rgbd->cameraParams.nrows = 3;
    clouds.insert(rgbd);
    auto cloud = CObservationPointCloud::Create();
    auto points = mrpt::maps::CSimplePointsMap::Create();
    points->insertPoint(1, 2, 3);
    cloud->pointcloud = points;
    clouds.insert(cloud);
    auto rotating = CObservationRotatingScan::Create();
    rotating->rowCount = 3;
    rotating->columnCount = 4;
    rotating->rangeImage.setZero(3, 4);
    rotating->intensityImage.setZero(3, 4);
    clouds.insert(rotating);
    arch2 << clouds;

    mrpt::io::CFileOutputStream f3((dir / "sensor_stereo.rawlog").string());
    auto arch3 = mrpt::serialization::archiveFrom(f3);
    CSensoryFrame stereo;
    auto pair = CObservationStereoImages::Create();
    pair->sensorLabel = "stereo";
    pair->imageLeft = patternImage(8, 6, mrpt::img::CH_GRAY);
    pair->imageRight = pair->imageLeft;
    stereo.insert(pair);
    auto features = CObservationStereoImagesFeatures::Create();
    features->sensorLabel = "stereo_features";
    features->theFeatures.resize(2);
    stereo.insert(features);
    auto rgbd360 = CObservationRGBD360::Create();
    rgbd360->hasRangeImage = true;
    rgbd360->rangeImages[0].setZero(2, 3);
    rgbd360->rangeImages[1].setZero(2, 3);
    stereo.insert(rgbd360);
    auto topcon = CObservationGPS::Create();
    topcon->sensorLabel = "topcon";
    topcon->setMsg(gnss::Message_TOPCON_PZS());
    gnss::Message_TOPCON_SATS sats;
    sats.USIs = {3, 7};
    sats.ELs = {40, 60};
    sats.AZs = {90, 180};
    topcon->setMsg(sats);
    stereo.insert(topcon);
    arch3 << stereo;
}

std::string readAll(const fs::path& p)
{
    std::ifstream f(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

void writePacked(const fs::path& out, char format, const std::vector<std::string>& files)
{
    std::ofstream f(out, std::ios::binary);
    f << format;
    for (size_t i = 0; i < files.size(); ++i)
        f << (i ? hymm::fuzz::fileSeparator() : "") << files[i];
}

std::string matBytes(const fs::path& tmp,
                     const std::vector<std::pair<std::string, Eigen::MatrixXd>>& vars)
{
    hymm::datasets::writeMatFile(tmp.string(), vars);
    return readAll(tmp);
}

void importSeeds(const fs::path& dir)
{
    // MRCLAM: 2 s of odometry at 50 Hz, a few measurements of one landmark.
    std::ostringstream odo, gt;
    for (int i = 0; i < 100; ++i)
    {
        odo << 1000.0 + 0.02 * i << " 0.1 0.05\n";
        gt << 1000.0 + 0.01 * i << " " << 0.001 * i << " 0 0\n";
    }
    writePacked(dir / "mrclam.seed", 0,
                {odo.str(), "1000.5 27 1.5 0.1\n1001.0 27 1.45 0.12\n1001.5 5 2.0 0.3\n",
                 "1 5\n2 14\n6 27\n", "6 2.0 0.3 0.001 0.001\n", gt.str()});

    const fs::path tmp = dir / "tmp.mat";
    Eigen::VectorXd t(40), v(40), s(40);
    for (int i = 0; i < 40; ++i) t(i) = 20000 + 25 * i, v(i) = 2.0, s(i) = 0.01;
    Eigen::VectorXd tg(3), x(3), y(3);
    tg << 20000, 20400, 20800;
    x << 0, 0.8, 1.6;
    y << 0, 0, 0;
    writePacked(dir / "victoria.seed", 1,
                {matBytes(tmp, {{"time", t}, {"speed", v}, {"steering", s}}),
                 "     0.200   10.0    1.5707963    0.30\n     0.500   20.0    0.0   0.20\n",
                 matBytes(tmp, {{"timeGps", tg}, {"Lo_m", x}, {"La_m", y}})});

    Eigen::VectorXd tv(20), vel(20), steer(20);
    for (int i = 0; i < 20; ++i) tv(i) = 45.0 + 0.025 * i, vel(i) = 2.0, steer(i) = 0.1;
    Eigen::MatrixXd tl(2, 1), laser(2, 361), inten(2, 361);
    tl << 45.1, 45.3;
    laser.setConstant(5.0);
    inten.setZero();
    Eigen::MatrixXd tgp(2, 1), gx(2, 1), gy(2, 1), beac(2, 2);
    tgp << 45.0, 45.4;
    gx << 0, 0.8;
    gy << 0, 0;
    beac << 2.9, -4.0, 9.9, 6.9;
    writePacked(dir / "carpark.seed", 2,
                {matBytes(tmp, {{"Time_VS", tv}, {"Velocity", vel}, {"Steering", steer},
                                {"TimeLaser", tl}, {"Laser", laser}, {"Intensity", inten},
                                {"TimeGPS", tgp}, {"GPSLon", gx}, {"GPSLat", gy}}),
                 matBytes(tmp, {{"estbeac", beac}})});
    fs::remove(tmp);
}
}  // namespace

int main(int argc, char** argv)
{
    if (argc != 3)
    {
        std::cerr << "usage: make_fuzz_seeds <source dir> <output dir>\n";
        return 2;
    }
    try
    {
        const fs::path src = argv[1], out = argv[2];
        for (const char* d : {"rawlog", "ini", "import"}) fs::create_directories(out / d);
        for (const auto& e : fs::directory_iterator(src / "rawlogs"))
        {
            if (e.path().extension() == ".ini")
                fs::copy_file(e.path(), out / "ini" / e.path().filename(),
                              fs::copy_options::overwrite_existing);
            if (e.path().extension() != ".rawlog") continue;
            for (size_t n : {3, 12, 40})
                cutRawlog(e.path(), n,
                          out / "rawlog" /
                              (e.path().stem().string() + "_" + std::to_string(n) + ".rawlog"));
        }
        for (const fs::path& d : {src / "configs", src / "configs" / "sim"})
            for (const auto& e : fs::directory_iterator(d))
                if (e.path().extension() == ".ini")
                    fs::copy_file(e.path(),
                                  out / "ini" / (d.filename().string() + "_" + e.path().filename().string()),
                                  fs::copy_options::overwrite_existing);
        fs::create_directories(out / "rawlog_sensors");
        sensorSeeds(out / "rawlog_sensors");
        importSeeds(out / "import");
    }
    catch (const std::exception& e)
    {
        std::cerr << "make_fuzz_seeds: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
