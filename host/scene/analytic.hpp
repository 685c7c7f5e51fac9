#pragma once
// Closed-form answers for the test scenes (scenes/README.md, "Scenes with known answers").
#include <cmath>

namespace oas::scene {

/// Configuration (view) factor from a differential area at the origin, facing +y, to the
/// rectangle [x1, x2] x [z1, z2] in the plane y = h > 0, facing down (Howell's catalogue,
/// factor B-3, "plane element to a parallel rectangle, normal through a corner", combined by
/// superposition over the four corners):
///   f(X, Z) = 1/(2 pi) [ X/sqrt(1+X^2) atan(Z/sqrt(1+X^2)) + Z/sqrt(1+Z^2) atan(X/sqrt(1+Z^2)) ]
///   F = f(x2/h, z2/h) - f(x1/h, z2/h) - f(x2/h, z1/h) + f(x1/h, z1/h)
/// f is odd in each argument, so the sum is right for any position of the rectangle.
/// A uniform emitter of radiance L gives irradiance E = pi * L * F; a Lambertian surface of
/// albedo rho then reflects radiance rho * L * F.
inline double parallelRectangleFactor(double x1, double x2, double z1, double z2, double h)
{
    constexpr double kPi = 3.14159265358979323846;
    auto f = [](double X, double Z) {
        const double a = std::sqrt(1 + X * X), b = std::sqrt(1 + Z * Z);
        return (X / a * std::atan(Z / a) + Z / b * std::atan(X / b)) / (2 * kPi);
    };
    return f(x2 / h, z2 / h) - f(x1 / h, z2 / h) - f(x2 / h, z1 / h) + f(x1 / h, z1 / h);
}

}  // namespace oas::scene
