/**
 * @file relative_pose_error.h
 * @brief Relative pose error (RPE) between consecutive samples of two paired paths: the
 *        error of the motion from one sample to the next, which a global rotation or an
 *        early heading error does not inflate as it does the absolute trajectory error.
 */
#pragma once

#include <hymm/io/trajectory_io.h>

#include <cstddef>
#include <vector>

namespace hymm::eval
{
struct RelativePoseError
{
    size_t pairs = 0;             //!< consecutive sample pairs scored
    double translation_mean = 0;  //!< [m] |t_est - t_true| of the relative poses
    double translation_median = 0;
    double translation_max = 0;
    double rotation_mean = 0;  //!< [rad] |phi_est - phi_true| of the relative poses, wrapped
    double rotation_median = 0;
    double rotation_max = 0;
};

/** estimate[i] and truth[i] are the same instant (timestamps are ignored). For each i the
 *  relative pose est_i^-1 (+) est_{i+1} is compared with truth_i^-1 (+) truth_{i+1}: the
 *  translation error in the frame of sample i, and the wrapped heading error. Throws
 *  std::invalid_argument when the sizes differ or a pose is not finite; fewer than two
 *  samples give pairs = 0 and NaN errors. */
RelativePoseError relativePoseError(const std::vector<io::StampedPose2D>& estimate,
                                    const std::vector<io::StampedPose2D>& truth);

}  // namespace hymm::eval
