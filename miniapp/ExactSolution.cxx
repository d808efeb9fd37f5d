#include "ExactSolution.h"

#include <cmath>

namespace miniamr
{

TranslatedGaussian::TranslatedGaussian(int dimension, std::array<double, 3> center, double sigma,
                                       std::array<double, 3> velocity)
    : Dimension(dimension), Center(center), Sigma(sigma), Velocity(velocity),
      // A point and the (wrapped) center are less than 1 apart; beyond 9 sigma
      // more, an image adds less than exp(-40) ~ 4e-18.
      Images(1 + static_cast<int>(std::ceil(9 * sigma)))
{
}

TranslatedGaussian TranslatedGaussian::standard(int dimension, std::array<double, 3> velocity)
{
  return TranslatedGaussian(dimension, {{0.3, 0.4, 0.45}}, 0.15, velocity);
}

double TranslatedGaussian::axisAverage(int axis, double low, double size, double time) const
{
  double center = std::fmod(Center[axis] + Velocity[axis] * time, 1.0);
  if (center < 0)
    center += 1.0;
  // The integral of exp(-s^2 / (2 sigma^2)) over [a, b] is
  // sigma sqrt(pi / 2) (erf(b') - erf(a')), with s' = s / (sigma sqrt 2); on the
  // right tail erfc avoids subtracting two numbers close to 1.
  const double scale = 1.0 / (Sigma * std::sqrt(2.0));
  double sum = 0;
  for (int k = -Images; k <= Images; ++k)
  {
    const double a = (low - center + k) * scale;
    const double b = (low + size - center + k) * scale;
    sum += a >= 0   ? std::erfc(a) - std::erfc(b)
           : b <= 0 ? std::erfc(-b) - std::erfc(-a)
                    : std::erf(b) - std::erf(a);
  }
  return sum * Sigma * std::sqrt(std::acos(-1.0) / 2.0) / size;
}

double TranslatedGaussian::cellAverage(const std::array<double, 3>& low,
                                       const std::array<double, 3>& size, double time) const
{
  // Separable: the box average is the product of the axes' averages.
  double average = 1.0;
  for (int a = 0; a < Dimension; ++a)
    average *= axisAverage(a, low[a], size[a], time);
  return average;
}

double TranslatedGaussian::integral() const
{
  return std::pow(2 * std::acos(-1.0) * Sigma * Sigma, 0.5 * Dimension);
}

} // namespace miniamr
