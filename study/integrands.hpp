#pragma once
// Analytic test integrands of the OA-sampling paper (Jarosz et al. 2019, after Subr et al. 2016)
// and their reference values. See docs/STUDY.md for the definitions and the reference errors.
//
// Points x lie in the unit cube [0,1)^D and every radius is measured from the origin (no
// centring), as in the paper: 1D kernel g(r) of r with r_end = 3/pi, r_start = r_end - 0.2,
// sigma = 1/3, combined as
//   1-additive        sum_i g(x_i)
//   2-additive        sum_{i<j} g(||(x_i, x_j)||)
//   2-multiplicative  prod_{i<j} g(||(x_i, x_j)||)
//   radial            g(||x||)
#include <cstdint>
#include <string>
#include <vector>

namespace oas::study {

enum class Kernel { Gaussian, LinearStep, BinaryStep, Constant };
enum class Combo { Additive1, Additive2, Multiplicative2, Radial };

constexpr double kPi = 3.14159265358979323846;
constexpr double kREnd = 3.0 / kPi;
constexpr double kRStart = kREnd - 0.2;
constexpr double kSigma = 1.0 / 3.0;

/// The 1D kernel g(r).
double kernel(Kernel k, double r);
std::string kernelName(Kernel k);  ///< "gaussian", "linear-step", "binary-step", "constant"
std::string comboName(Combo c);    ///< "1-additive", "2-additive", "2-multiplicative", "radial"

struct Integrand {
    Combo combo;
    Kernel kernel;
    std::uint32_t dims;
    std::string name() const;  ///< "2-additive binary-step 4D"
};

/// f(x) for one point x[0..dims).
double evaluate(const Integrand& f, const float* x);
/// All integrands (same dims) at once for one point; shares the pair distances. out[i] = fs[i](x).
void evaluateAll(const std::vector<Integrand>& fs, const float* x, std::uint32_t dims, double* out);

/// The 12 paper integrands (4 combinations x 3 kernels) in `dims` dimensions.
std::vector<Integrand> paperIntegrands(std::uint32_t dims);

/// A reference value with an honest absolute error (a bound for closed forms: a few ulps;
/// quadrature: the difference between two orders; RQMC: the standard error).
struct Reference {
    double value = 0;
    double error = 0;
    std::string method;
    bool exact = false;  ///< closed form (or quadrature accurate to machine precision)
};

/// Closed-form (or 1D Gauss-Legendre) reference; exact == false when no closed form exists
/// (2-multiplicative linear step), in which case value is NaN and the caller uses RQMC.
Reference closedFormReference(const Integrand& f);

/// Integral of g over [0,1] (closed form).
double kernelIntegral1D(Kernel k);
/// Integral of g(||(x,y)||) over [0,1]^2 by Gauss-Legendre in polar coordinates (each piece is
/// smooth, so it converges exponentially); error = |Q(n) - Q(m)| for two orders n > m.
Reference quadrature2D(Kernel k);

/// n-point Gauss-Legendre nodes and weights on [-1, 1].
void gaussLegendre(int n, std::vector<double>& nodes, std::vector<double>& weights);
/// Integral of f over [a, b] split at `breaks` (sorted, inside (a,b)), each piece by n-point GL.
template <class F>
double integrateGL(F f, double a, double b, std::vector<double> breaks, int n);

}  // namespace oas::study

#include <algorithm>
namespace oas::study {
template <class F>
double integrateGL(F f, double a, double b, std::vector<double> breaks, int n)
{
    std::vector<double> x, w;
    gaussLegendre(n, x, w);
    std::vector<double> pts{a};
    std::sort(breaks.begin(), breaks.end());
    for (double c : breaks)
        if (c > a && c < b) pts.push_back(c);
    pts.push_back(b);
    double sum = 0;
    for (size_t p = 0; p + 1 < pts.size(); ++p) {
        const double lo = pts[p], hi = pts[p + 1], h = 0.5 * (hi - lo), m = 0.5 * (hi + lo);
        double s = 0;
        for (int i = 0; i < n; ++i) s += w[i] * f(m + h * x[i]);
        sum += h * s;
    }
    return sum;
}
}  // namespace oas::study
