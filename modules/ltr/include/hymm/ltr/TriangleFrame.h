/**
 * @file TriangleFrame.h
 * @brief Local frame of a Local Triangular Region (thesis Sec. 3.4.1, App. C).
 *
 * Three vertices L1, L2, L3 define the axes a = L2 - L1, b = L3 - L1 (Eq. 3.6) and
 * any point is written x = L1 + alpha a + beta b (Eq. 3.7). With D = [a b] (a 2x2
 * matrix with the axes as columns) the local coordinates are l = [alpha, beta]^T =
 * D^{-1} (x - L1), which is Eq. 3.9 / C.3 written in matrix form.
 *
 * Jacobians (App. C, derived here in matrix form because the transcribed C.14 has
 * its components swapped: the correct d alpha / d d13 is [dy, -dx] / Delta with
 * d = x - L1, not [dx, -dy] / Delta):
 *   dl/dx  = D^{-1}                                   (C.5)
 *   dl/dL1 = -(1 - alpha - beta) D^{-1}               (C.7, all chain terms summed)
 *   dl/dL2 = -alpha D^{-1}                            (C.8)
 *   dl/dL3 = -beta  D^{-1}                            (C.9)
 * These follow from d(D^{-1}) = -D^{-1} dD D^{-1}: moving L2 by dL2 changes the first
 * column of D, so dl = -D^{-1} dL2 alpha. The inverse map x = L1 + D l has
 *   dx/dl = D,  dx/dL1 = (1 - alpha - beta) I,  dx/dL2 = alpha I,  dx/dL3 = beta I.
 * Every one of these is checked against finite differences in TriangleFrame_test.
 */
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>  // determinant(), inverse() of the 2x2 axes

#include <array>
#include <optional>
#include <string>

namespace hymm::ltr
{
/** Numerical limits below which a triangle is refused as a frame. */
struct FrameLimits
{
    double min_area = 1e-6;              //!< [m^2] smaller triangles are degenerate
    double max_condition_number = 1e6;   //!< sigma_max / sigma_min of D = [a b]
};

class TriangleFrame
{
public:
    using Vertices = std::array<Eigen::Vector2d, 3>;

    /** Builds the frame; throws std::invalid_argument naming the failed limit (area or
     *  condition number) when the triangle is degenerate. Never yields NaN. */
    TriangleFrame(
        const Eigen::Vector2d& l1, const Eigen::Vector2d& l2, const Eigen::Vector2d& l3,
        const FrameLimits& limits = FrameLimits());
    explicit TriangleFrame(const Vertices& v, const FrameLimits& limits = FrameLimits())
        : TriangleFrame(v[0], v[1], v[2], limits)
    {
    }

    /** Non-throwing variant: returns std::nullopt for a degenerate triangle and, if
     *  `why` is given, a message saying which limit failed. */
    static std::optional<TriangleFrame> tryCreate(
        const Vertices& v, const FrameLimits& limits = FrameLimits(), std::string* why = nullptr);

    /** Empty string when `v` is a valid frame under `limits`, else the reason. */
    static std::string degeneracyReason(const Vertices& v, const FrameLimits& limits);

    const Vertices& vertices() const { return v_; }
    const Eigen::Vector2d& vertex(int k) const { return v_[static_cast<size_t>(k)]; }
    /** D = [L2 - L1, L3 - L1]. */
    const Eigen::Matrix2d& axes() const { return d_; }
    const Eigen::Matrix2d& axesInverse() const { return d_inv_; }
    /** Signed area (> 0 when L1, L2, L3 are counter-clockwise). */
    double signedArea() const { return 0.5 * d_.determinant(); }
    double area() const;

    /** Local coordinates [alpha, beta] of a global point (Eq. 3.9). */
    Eigen::Vector2d toLocal(const Eigen::Vector2d& x) const;
    /** Global point of local coordinates (Eq. 3.7). */
    Eigen::Vector2d toGlobal(const Eigen::Vector2d& local) const;
    /** Barycentric weights (1 - alpha - beta, alpha, beta) of L1, L2, L3. */
    static Eigen::Vector3d weights(const Eigen::Vector2d& local);
    /** True if the local coordinates lie in the closed triangle, up to `tol`. */
    static bool insideLocal(const Eigen::Vector2d& local, double tol = 1e-12);
    bool contains(const Eigen::Vector2d& x, double tol = 1e-12) const
    {
        return insideLocal(toLocal(x), tol);
    }

    // --- Jacobians of the local coordinates (App. C) -------------------------------
    /** d(alpha, beta) / dx  (C.5). */
    Eigen::Matrix2d jacLocalWrtPoint() const { return d_inv_; }
    /** d(alpha, beta) / dL_k for vertex k in {0, 1, 2}, at global point x (C.7-C.9). */
    Eigen::Matrix2d jacLocalWrtVertex(const Eigen::Vector2d& x, int k) const;
    /** [dl/dL1 dl/dL2 dl/dL3] as one 2x6 block. */
    Eigen::Matrix<double, 2, 6> jacLocalWrtVertices(const Eigen::Vector2d& x) const;

    // --- Jacobians of the global position ---------------------------------------
    /** dx / d(alpha, beta) = D. */
    Eigen::Matrix2d jacGlobalWrtLocal() const { return d_; }
    /** dx / dL_k = w_k I with the barycentric weight w_k of `local`. */
    static Eigen::Matrix2d jacGlobalWrtVertex(const Eigen::Vector2d& local, int k);
    /** [dx/dL1 dx/dL2 dx/dL3] as one 2x6 block. */
    static Eigen::Matrix<double, 2, 6> jacGlobalWrtVertices(const Eigen::Vector2d& local);

private:
    struct Unchecked
    {
    };
    TriangleFrame(const Vertices& v, Unchecked);

    Vertices v_;
    Eigen::Matrix2d d_;
    Eigen::Matrix2d d_inv_;
};

}  // namespace hymm::ltr
