// An exact solution of the mini-app's equation for accuracy studies: a Gaussian
// translated by a uniform velocity on the periodic unit domain. The scheme's
// unknowns are cell averages, so the reference is the exact cell average.
#pragma once

#include <array>

namespace miniamr
{

class TranslatedGaussian
{
public:
  /// exp(-|x - center - velocity t|^2 / (2 sigma^2)), summed over the periodic images.
  TranslatedGaussian(int dimension, std::array<double, 3> center, double sigma,
                     std::array<double, 3> velocity);

  /// The exact average over the box [low, low + size] at time t.
  double cellAverage(const std::array<double, 3>& low, const std::array<double, 3>& size,
                     double time) const;

  /// Its integral over the unit domain, (2 pi sigma^2)^(d/2): conserved.
  double integral() const;

  /// The mini-app's profile: sigma 0.15, wide enough that 32 cells per axis already
  /// converge at close to first order; centered off the domain's symmetry axes.
  static TranslatedGaussian standard(int dimension, std::array<double, 3> velocity);

private:
  double axisAverage(int axis, double low, double size, double time) const;

  int Dimension;
  std::array<double, 3> Center;
  double Sigma;
  std::array<double, 3> Velocity;
  int Images; ///< periodic images on each side that contribute above round-off
};

} // namespace miniamr
