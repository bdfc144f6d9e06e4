#include "hymm/eval/nees.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hymm::eval
{
namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kMaxSeriesTerms = 100000;
constexpr double kEps = 1e-16;
constexpr int kBisectionSteps = 400;

// Regularised lower incomplete gamma P(a, x) by its power series (converges for x < a+1).
double gammaPSeries(double a, double x)
{
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < kMaxSeriesTerms; ++n)
    {
        term *= x / (a + n);
        sum += term;
        if (std::abs(term) < std::abs(sum) * kEps) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Regularised upper incomplete gamma Q(a, x) by its continued fraction (modified Lentz),
// which converges quickly for x >= a+1.
double gammaQContinuedFraction(double a, double x)
{
    constexpr double kTiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
    for (int i = 1; i < kMaxSeriesTerms; ++i)
    {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < kTiny) d = kTiny;
        c = b + an / c;
        if (std::abs(c) < kTiny) c = kTiny;
        d = 1.0 / d;
        const double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < kEps) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

double regularisedGammaP(double a, double x)
{
    if (x <= 0) return 0.0;
    if (x < a + 1.0) return gammaPSeries(a, x);
    return 1.0 - gammaQContinuedFraction(a, x);
}

void checkProbability(double p, const char* what)
{
    if (!(p > 0 && p < 1))
        throw std::invalid_argument(std::string(what) + ": probability " + std::to_string(p) +
                                    " must be in (0, 1)");
}
}  // namespace

NeesValue nees(const Eigen::VectorXd& error, const Eigen::MatrixXd& cov, double min_rcond)
{
    const auto n = error.size();
    if (n == 0 || cov.rows() != n || cov.cols() != n)
        throw std::invalid_argument("nees: error of size " + std::to_string(n) +
                                    " and covariance " + std::to_string(cov.rows()) + "x" +
                                    std::to_string(cov.cols()) + " do not match");
    NeesValue out;
    out.value = kNaN;
    if (!error.allFinite() || !cov.allFinite())
    {
        out.status = NeesStatus::NotFinite;
        return out;
    }
    const Eigen::MatrixXd S = 0.5 * (cov + cov.transpose());
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
    const Eigen::VectorXd& lambda = eig.eigenvalues();  // ascending
    if (eig.info() != Eigen::Success || !(lambda[n - 1] > 0) ||
        !(lambda[0] > min_rcond * lambda[n - 1]))
    {
        out.status = NeesStatus::Singular;
        return out;
    }
    const Eigen::VectorXd proj = eig.eigenvectors().transpose() * error;
    out.value = (proj.array().square() / lambda.array()).sum();
    out.status = NeesStatus::Ok;
    return out;
}

double chi2Cdf(double x, double dof)
{
    if (!(dof > 0)) throw std::invalid_argument("chi2Cdf: dof must be > 0");
    return regularisedGammaP(0.5 * dof, 0.5 * x);
}

double chi2Quantile(double p, double dof)
{
    checkProbability(p, "chi2Quantile");
    if (!(dof > 0)) throw std::invalid_argument("chi2Quantile: dof must be > 0");
    // Bracket, then bisect: the CDF is monotone, so this cannot fail, and ~60 halvings
    // already reach double precision.
    double lo = 0, hi = std::max(1.0, dof);
    while (chi2Cdf(hi, dof) < p) lo = hi, hi *= 2.0;
    for (int i = 0; i < kBisectionSteps && hi - lo > 1e-15 * hi; ++i)
    {
        const double mid = 0.5 * (lo + hi);
        (chi2Cdf(mid, dof) < p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double normalQuantile(double p)
{
    checkProbability(p, "normalQuantile");
    // Bisection on the CDF 0.5 erfc(-z / sqrt 2): slow but exact to double precision.
    double lo = -40, hi = 40;
    for (int i = 0; i < 200 && hi - lo > 1e-15; ++i)
    {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double chi2QuantileWilsonHilferty(double p, double dof)
{
    if (!(dof > 0)) throw std::invalid_argument("chi2QuantileWilsonHilferty: dof must be > 0");
    const double z = normalQuantile(p);
    const double v = 2.0 / (9.0 * dof);
    const double c = 1.0 - v + z * std::sqrt(v);
    return dof * c * c * c;
}

NeesBounds averageNeesBounds(int dim, int runs, double confidence)
{
    if (dim < 1 || runs < 1)
        throw std::invalid_argument("averageNeesBounds: dim=" + std::to_string(dim) +
                                    " and runs=" + std::to_string(runs) + " must be >= 1");
    checkProbability(confidence, "averageNeesBounds confidence");
    const double dof = static_cast<double>(dim) * runs;
    return NeesBounds{chi2Quantile(0.5 * (1.0 - confidence), dof) / runs,
                      chi2Quantile(0.5 * (1.0 + confidence), dof) / runs};
}

double fractionInsideBounds(const std::vector<double>& series, const NeesBounds& bounds)
{
    size_t finite = 0, inside = 0;
    for (double v : series)
    {
        if (!std::isfinite(v)) continue;
        ++finite;
        if (bounds.contains(v)) ++inside;
    }
    return finite == 0 ? kNaN : static_cast<double>(inside) / static_cast<double>(finite);
}

}  // namespace hymm::eval
