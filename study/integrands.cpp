#include "integrands.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace oas::study {

double kernel(Kernel k, double r)
{
    switch (k) {
    case Kernel::Gaussian:
        return std::exp(-r * r / (2 * kSigma * kSigma));
    case Kernel::LinearStep:
        return 1.0 - std::clamp((r - kRStart) / (kREnd - kRStart), 0.0, 1.0);
    case Kernel::BinaryStep:
        return r < kREnd ? 1.0 : 0.0;
    case Kernel::Constant:
        return 1.0;
    }
    return 0;
}

std::string kernelName(Kernel k)
{
    switch (k) {
    case Kernel::Gaussian:
        return "gaussian";
    case Kernel::LinearStep:
        return "linear-step";
    case Kernel::BinaryStep:
        return "binary-step";
    case Kernel::Constant:
        return "constant";
    }
    return "?";
}

std::string comboName(Combo c)
{
    switch (c) {
    case Combo::Additive1:
        return "1-additive";
    case Combo::Additive2:
        return "2-additive";
    case Combo::Multiplicative2:
        return "2-multiplicative";
    case Combo::Radial:
        return "radial";
    }
    return "?";
}

std::string Integrand::name() const
{
    return comboName(combo) + " " + kernelName(kernel) + " " + std::to_string(dims) + "D";
}

std::vector<Integrand> paperIntegrands(std::uint32_t dims)
{
    std::vector<Integrand> out;
    for (Combo c : {Combo::Additive1, Combo::Additive2, Combo::Multiplicative2, Combo::Radial})
        for (Kernel k : {Kernel::Gaussian, Kernel::LinearStep, Kernel::BinaryStep}) out.push_back({c, k, dims});
    return out;
}

namespace {
constexpr std::uint32_t kMaxEvalDims = 64;

// The kernel from r^2 (and, for the Gaussian, the product of per-coordinate factors, which is
// the same number as exp(-r^2 / 2 sigma^2) and saves the exp per pair).
inline double kernelR2(Kernel k, double r2, double gauss)
{
    switch (k) {
    case Kernel::Gaussian:
        return gauss;
    case Kernel::LinearStep:
        if (r2 <= kRStart * kRStart) return 1.0;
        if (r2 >= kREnd * kREnd) return 0.0;
        return 1.0 - (std::sqrt(r2) - kRStart) / (kREnd - kRStart);
    case Kernel::BinaryStep:
        return r2 < kREnd * kREnd ? 1.0 : 0.0;
    case Kernel::Constant:
        return 1.0;
    }
    return 0;
}
}  // namespace

void evaluateAll(const std::vector<Integrand>& fs, const float* x, std::uint32_t dims, double* out)
{
    if (dims > kMaxEvalDims) throw std::invalid_argument("evaluateAll: at most 64 dims");
    double sq[kMaxEvalDims], ex[kMaxEvalDims];
    double norm2 = 0, gaussAll = 1;
    for (std::uint32_t i = 0; i < dims; ++i) {
        const double v = x[i];
        sq[i] = v * v;
        ex[i] = std::exp(-sq[i] / (2 * kSigma * kSigma));
        norm2 += sq[i];
        gaussAll *= ex[i];
    }
    for (size_t f = 0; f < fs.size(); ++f) {
        const Kernel k = fs[f].kernel;
        double acc = 0;
        switch (fs[f].combo) {
        case Combo::Additive1:
            for (std::uint32_t i = 0; i < dims; ++i) acc += kernelR2(k, sq[i], ex[i]);
            break;
        case Combo::Additive2:
            for (std::uint32_t i = 0; i < dims; ++i)
                for (std::uint32_t j = i + 1; j < dims; ++j) acc += kernelR2(k, sq[i] + sq[j], ex[i] * ex[j]);
            break;
        case Combo::Multiplicative2:
            acc = 1;
            for (std::uint32_t i = 0; i < dims && acc != 0; ++i)
                for (std::uint32_t j = i + 1; j < dims; ++j) acc *= kernelR2(k, sq[i] + sq[j], ex[i] * ex[j]);
            break;
        case Combo::Radial:
            acc = kernelR2(k, norm2, gaussAll);
            break;
        }
        out[f] = acc;
    }
}

double evaluate(const Integrand& f, const float* x)
{
    double v = 0;
    evaluateAll({f}, x, f.dims, &v);
    return v;
}

void gaussLegendre(int n, std::vector<double>& nodes, std::vector<double>& weights)
{
    nodes.assign(n, 0);
    weights.assign(n, 0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1, p1 = z;  // Legendre recurrence
            for (int j = 2; j <= n; ++j) {
                const double p2 = ((2 * j - 1) * z * p1 - (j - 1) * p0) / j;
                p0 = p1;
                p1 = p2;
            }
            if (n == 1) p1 = z, p0 = 1;
            dp = n * (z * p1 - p0) / (z * z - 1);
            const double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-16) break;
        }
        nodes[i] = z;
        weights[i] = 2 / ((1 - z * z) * dp * dp);
    }
}

double kernelIntegral1D(Kernel k)
{
    switch (k) {
    case Kernel::Gaussian:
        return kSigma * std::sqrt(kPi / 2) * std::erf(1 / (kSigma * std::sqrt(2.0)));
    case Kernel::LinearStep:
        return kRStart + 0.5 * (kREnd - kRStart);  // r_end < 1
    case Kernel::BinaryStep:
        return kREnd;
    case Kernel::Constant:
        return 1.0;
    }
    return 0;
}

namespace {
// Integral of g(r) r^(d-1) over [0, r_end] for the step kernels (support inside the unit cube).
double radialMoment(Kernel k, std::uint32_t d)
{
    const double D = d, rs = kRStart, re = kREnd;
    if (k == Kernel::BinaryStep) return std::pow(re, D) / D;
    // linear step: 1 on [0, rs], (re - r)/(re - rs) on [rs, re]
    return std::pow(rs, D) / D +
           (re * (std::pow(re, D) - std::pow(rs, D)) / D - (std::pow(re, D + 1) - std::pow(rs, D + 1)) / (D + 1)) / (re - rs);
}

double quadrature2DOrder(Kernel k, int n)
{
    // theta in [0, pi/2] split at pi/4; r from 0 to R(theta) = 1/max(cos, sin), split at rs, re.
    auto inner = [&](double th) {
        const double R = 1.0 / std::max(std::cos(th), std::sin(th));
        return integrateGL([&](double r) { return kernel(k, r) * r; }, 0.0, R, {kRStart, kREnd}, n);
    };
    return integrateGL(inner, 0.0, kPi / 2, {kPi / 4}, n);
}
}  // namespace

Reference quadrature2D(Kernel k)
{
    const double hi = quadrature2DOrder(k, 40), lo = quadrature2DOrder(k, 24);
    Reference ref;
    ref.value = hi;
    ref.error = std::abs(hi - lo) + 1e-15 * std::abs(hi);
    ref.method = "Gauss-Legendre 40x40 in polar coordinates (error: |Q40 - Q24|)";
    ref.exact = true;
    return ref;
}

Reference closedFormReference(const Integrand& f)
{
    const double D = f.dims;
    const double pairs = D * (D - 1) / 2;
    const double rs = kRStart, re = kREnd;
    Reference ref;
    ref.exact = true;
    ref.method = "closed form";
    double v = std::numeric_limits<double>::quiet_NaN();
    const double I1 = kernelIntegral1D(f.kernel);
    switch (f.combo) {
    case Combo::Additive1:
        v = D * I1;
        ref.method = "closed form: D * integral_0^1 g";
        break;
    case Combo::Additive2: {
        double I2 = 1;
        if (f.kernel == Kernel::Gaussian)
            I2 = I1 * I1;
        else if (f.kernel == Kernel::BinaryStep)
            I2 = kPi * re * re / 4;
        else if (f.kernel == Kernel::LinearStep)
            I2 = kPi / 2 * (rs * rs / 2 + (re * (re * re - rs * rs) / 2 - (re * re * re - rs * rs * rs) / 3) / (re - rs));
        v = pairs * I2;
        ref.method = "closed form: C(D,2) * I2 (checked against 2D Gauss-Legendre)";
        break;
    }
    case Combo::Multiplicative2:
        if (f.kernel == Kernel::Constant || f.dims < 2)
            v = 1;
        else if (f.kernel == Kernel::Gaussian) {
            // prod_{i<j} exp(-(x_i^2 + x_j^2) / 2 s^2) = prod_i exp(-(D-1) x_i^2 / 2 s^2)
            const double s = kSigma / std::sqrt(D - 1);
            v = std::pow(s * std::sqrt(kPi / 2) * std::erf(1 / (s * std::sqrt(2.0))), D);
            ref.method = "closed form (separable Gaussian)";
        } else if (f.kernel == Kernel::BinaryStep) {
            // all pairs inside the disc <=> the two largest coordinates are: with a the maximum,
            // the others lie below min(a, sqrt(re^2 - a^2)); a = re cos(theta) for the second part.
            const double sinInt = integrateGL([&](double t) { return std::pow(std::sin(t), D); }, 0.0, kPi / 4, {}, 40);
            v = std::pow(re / std::sqrt(2.0), D) + D * std::pow(re, D) * sinInt;
            ref.method = "closed form + 1D Gauss-Legendre (order statistics of the two largest coordinates)";
        } else {
            ref.exact = false;
            ref.method = "none (RQMC)";
        }
        break;
    case Combo::Radial: {
        const double surface = 2 * std::pow(kPi, D / 2) / std::tgamma(D / 2);  // S_{D-1}
        if (f.kernel == Kernel::Constant)
            v = 1;
        else if (f.kernel == Kernel::Gaussian) {
            v = std::pow(I1, D);
            ref.method = "closed form (separable Gaussian)";
        } else {
            // r_end < 1: the orthant part of the ball lies inside the unit cube.
            v = surface / std::pow(2.0, D) * radialMoment(f.kernel, f.dims);
            ref.method = "closed form (ball in the positive orthant)";
        }
        break;
    }
    }
    ref.value = v;
    ref.error = ref.exact ? 1e-14 * std::abs(v) : std::numeric_limits<double>::quiet_NaN();
    return ref;
}

}  // namespace oas::study
