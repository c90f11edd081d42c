#include "spectral/spectral_light.h"

#include "spectral/uplift.h"

namespace farm {

SpectralLight SpectralLight::Hero(const Rgb& rgb, double u) {
  const SmitsSpectrum spectrum(rgb);
  SpectralLight light;
  light.count_ = kWavelengthsPerPath;
  for (int i = 0; i < kWavelengthsPerPath; ++i) {
    double ui = u + double(i) / kWavelengthsPerPath;
    if (ui >= 1) ui -= 1;
    light.at_[i] = MonochromePath::Sample(ui);
    light.value_[i] = spectrum.At(light.at_[i].lambda_nm);
  }
  return light;
}

SpectralLight SpectralLight::One(const Rgb& rgb, const MonochromePath& at) {
  SpectralLight light;
  light.count_ = 1;
  light.at_[0] = at;
  light.value_[0] = at.ValueOf(rgb);
  return light;
}

SpectralLight SpectralLight::HeroOnly() const {
  SpectralLight light = *this;
  light.count_ = 1;
  return light;
}

SpectralLight SpectralLight::Times(const Rgb& weight, double over) const {
  const SmitsSpectrum spectrum(weight);
  SpectralLight light = *this;
  for (int i = 0; i < count_; ++i) light.value_[i] = value_[i] * spectrum.At(at_[i].lambda_nm) / over;
  return light;
}

SpectralLight SpectralLight::Over(double k) const {
  SpectralLight light = *this;
  for (int i = 0; i < count_; ++i) light.value_[i] = value_[i] / k;
  return light;
}

Rgb SpectralLight::ToRgb() const {
  Rgb sum;
  for (int i = 0; i < count_; ++i) sum += at_[i].ToRgb(value_[i]);
  return count_ > 0 ? sum / float(count_) : sum;
}

}  // namespace farm
