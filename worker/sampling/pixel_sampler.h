#pragma once

// The sampler of camera paths: a padded, Owen-scrambled 2D Sobol sampler.
//
// Every value it returns is a pure function of (scene seed, pixel index y*width+x, sample
// index, dimension), never of the order pixels are visited or of the tile they belong to.
// Dimensions are consumed in pairs (Get2D) or singly (Get1D); each call gets its own
// scramble seed and its own shuffle of the sample indices, both hashed from (seed, pixel,
// dimension). Within one pixel the samples of one dimension pair therefore form a
// stratified (0,2)-net when samples_per_pixel is a power of two, while different pairs are
// decorrelated. Cheap to copy: one per thread, restarted for each pixel sample. The tile
// renderer takes a sample's position on the film from film_sampler.h instead, which
// stratifies it across pixels too, and the rest of the camera path from here.

#include <cstdint>
#include <string>

#include "math/vec3.h"
#include "sampling/hash.h"
#include "sampling/sobol.h"

namespace farm {

class PixelSampler {
 public:
  PixelSampler(uint32_t samples_per_pixel, uint64_t seed)
      : samples_per_pixel_(samples_per_pixel), seed_(seed) {}

  void StartPixelSample(uint64_t pixel_index, uint32_t sample_index) {
    pixel_ = pixel_index;
    sample_index_ = sample_index;
    dimension_ = 0;
  }

  float Get1D() {
    const uint64_t hash = Hash(seed_, pixel_, dimension_);
    ++dimension_;
    const uint32_t index = PermutationElement(sample_index_, samples_per_pixel_, uint32_t(hash));
    return SobolSample(index, 0, uint32_t(hash >> 32));
  }

  Vec2 Get2D() {
    const uint64_t hash = Hash(seed_, pixel_, dimension_);
    dimension_ += 2;
    const uint32_t index = PermutationElement(sample_index_, samples_per_pixel_, uint32_t(hash));
    // The two coordinates take independent halves of the hash as scramble seeds; the
    // permutation seed is reused with the low half, which is harmless because the
    // permutation and the scramble act on different things (index vs. value).
    const uint64_t seeds = MixBits(hash);
    return {SobolSample(index, 0, uint32_t(seeds)), SobolSample(index, 1, uint32_t(seeds >> 32))};
  }

  uint32_t samples_per_pixel() const { return samples_per_pixel_; }
  int dimension() const { return dimension_; }

  std::string ToString() const {
    return "PixelSampler{spp=" + std::to_string(samples_per_pixel_) +
           ", seed=" + std::to_string(seed_) + ", pixel=" + std::to_string(pixel_) +
           ", sample=" + std::to_string(sample_index_) + ", dim=" + std::to_string(dimension_) +
           "}";
  }

 private:
  uint32_t samples_per_pixel_;
  uint64_t seed_;
  uint64_t pixel_ = 0;
  uint32_t sample_index_ = 0;
  int dimension_ = 0;
};

}  // namespace farm
