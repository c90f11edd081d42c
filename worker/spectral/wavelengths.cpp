#include "spectral/wavelengths.h"

namespace farm {

SampledWavelengths SampleWavelengths(double u) {
  constexpr double range = kLambdaMax - kLambdaMin;
  SampledWavelengths w;
  w.pdf = 1 / range;
  for (int i = 0; i < kWavelengthsPerPath; ++i) {
    double offset = u * range + i * range / kWavelengthsPerPath;
    if (offset >= range) offset -= range;
    w.lambda[i] = kLambdaMin + offset;
  }
  return w;
}

}  // namespace farm
