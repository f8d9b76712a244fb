// Sensor noise from a counter-based generator (doc/sensors.md#noise): the n-th sample of a
// stream is a pure function of (seed, stream, n), so a reading never depends on which samples
// were taken before it — whether a topic had subscribers, how often it was read, or a bag
// replayed into a fresh node — and runs with the same seed are bit-identical.
//
// Uniforms: SplitMix64 (Steele, Lea, Flood 2014) hashes of the counter, 53 bits each. Normals:
// Box–Muller on two uniforms (the generator gazebo_ros's plugins use too).
#pragma once

#include <cstdint>

#include "cga_rigid_sim/scene/sensors.h"

namespace cga_rigid_sim {
namespace sensor {

/// SplitMix64's finaliser: a bijection of 64-bit words whose output bits each depend on every
/// input bit.
constexpr std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

/// A standard normal N(0, 1) sample, the n-th of `stream` under `seed`.
double standardNormal(std::uint64_t seed, std::uint64_t stream, std::uint64_t n);

/// A uniform sample in [0, 1), the n-th of `stream` under `seed` (independent of the normals of
/// the same stream and n).
double uniform01(std::uint64_t seed, std::uint64_t stream, std::uint64_t n);

/// SDF Gaussian noise on one channel: value + bias + N(mean, stddev²). The bias is drawn once
/// (sample index ~0 of the stream's own bias counter) as N(bias_mean, bias_stddev²) with a
/// random sign, as Gazebo draws it.
class NoisyChannel {
 public:
  NoisyChannel() = default;
  NoisyChannel(const scene::GaussianNoise& noise, std::uint64_t seed, std::uint64_t stream);
  /// The value of sample n with its noise; exactly `value` when the noise is zero.
  double apply(double value, std::uint64_t n) const;
  double bias() const { return bias_; }

 private:
  scene::GaussianNoise noise_;
  std::uint64_t seed_ = 0, stream_ = 0;
  double bias_ = 0.0;
};

}  // namespace sensor
}  // namespace cga_rigid_sim
