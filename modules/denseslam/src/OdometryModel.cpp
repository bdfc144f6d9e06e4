#include "hymm/denseslam/OdometryModel.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionRobotMovement2D.h>

#include <Eigen/Core>

#include <cmath>

namespace hymm::denseslam
{
// MRPT's TOptions_ThrunModel defaults, in double: MRPT stores them as float, whose
// rounding (0.01f = 0.0099999998) would show in the options tables (a test checks that
// these equal MRPT's to float precision).
ThrunOdometryParams::ThrunOdometryParams()
    : alpha1_rot_rot(0.05),
      alpha2_rot_trans(4.0 * M_PI / 180.0),
      alpha3_trans_trans(0.01),
      alpha4_trans_rot(0.0001 * 180.0 / M_PI),
      additional_std_xy(0.001),
      additional_std_phi(0.05 * M_PI / 180.0)
{
}

mrpt::poses::CPosePDFGaussian odometryIncrementPdf(const mrpt::poses::CPose2D& inc,
                                                   OdometryModel model,
                                                   const ThrunOdometryParams& p)
{
    mrpt::poses::CPosePDFGaussian out;
    out.mean = inc;
    out.cov.setZero();
    if (model == OdometryModel::Gaussian)
    {
        // MRPT's own closed form, with MRPT's defaults.
        mrpt::obs::CActionRobotMovement2D act;
        mrpt::obs::CActionRobotMovement2D::TMotionModelOptions o;
        o.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
        act.computeFromOdometry(inc, o);
        out.copyFrom(*act.poseChange);
        out.mean = inc;
    }
    else if (model == OdometryModel::Thrun)
    {
        // rot1, trans, rot2 as CActionRobotMovement2D::computeFromOdometry_modelThrun.
        const double rot1 = (inc.x() != 0 || inc.y() != 0) ? std::atan2(inc.y(), inc.x()) : 0.0;
        const double trans = inc.norm();
        const double rot2 = mrpt::math::wrapToPi(inc.phi() - rot1);
        const double s_rot1 = p.alpha1_rot_rot * std::abs(rot1) + p.alpha2_rot_trans * trans;
        const double s_trans =
            p.alpha3_trans_trans * trans + p.alpha4_trans_rot * (std::abs(rot1) + std::abs(rot2));
        const double s_rot2 = p.alpha1_rot_rot * std::abs(rot2) + p.alpha2_rot_trans * trans;
        // Exact second moments of MRPT's samples (rot1, trans, rot2 independent normals,
        // x = trans cos rot1, y = trans sin rot1, phi = rot1 + rot2, plus the additive
        // noise), not a first-order linearisation: at MRPT's defaults (s_rot1 = 0.07 rad
        // per metre) the cosine's curvature adds 11 % to the along-track variance that a
        // Jacobian misses. E[cos r] = cos(m) e^{-s^2/2}, E[cos^2 r] = (1 + cos(2m) e^{-2 s^2}) / 2,
        // and by Stein's lemma Cov(cos r, r) = -s^2 E[sin r].
        const double v1 = s_rot1 * s_rot1, vt = s_trans * s_trans, v2 = s_rot2 * s_rot2;
        const double a = std::exp(-v1 / 2), b = std::exp(-2 * v1);
        const double c = std::cos(rot1), s = std::sin(rot1);
        const double c2 = std::cos(2 * rot1), s2 = std::sin(2 * rot1);
        const double m2 = trans * trans + vt;  // E[trans^2]
        Eigen::Matrix3d C;
        C(0, 0) = m2 * (1 + c2 * b) / 2 - trans * trans * a * a * c * c;
        C(1, 1) = m2 * (1 - c2 * b) / 2 - trans * trans * a * a * s * s;
        C(0, 1) = C(1, 0) = m2 * s2 * b / 2 - trans * trans * a * a * s * c;
        C(0, 2) = C(2, 0) = -trans * v1 * s * a;
        C(1, 2) = C(2, 1) = trans * v1 * c * a;
        C(2, 2) = v1 + v2;
        C(0, 0) += p.additional_std_xy * p.additional_std_xy;
        C(1, 1) += p.additional_std_xy * p.additional_std_xy;
        C(2, 2) += p.additional_std_phi * p.additional_std_phi;
        out.cov = mrpt::math::CMatrixDouble33(0.5 * (C + C.transpose()));
    }
    return out;
}
}  // namespace hymm::denseslam
