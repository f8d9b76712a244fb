// Counter-based sensor noise (noise.h, doc/sensors.md#noise).
#include "cga_rigid_sim/sensor/noise.h"

#include <cmath>

#include "cga_rigid_sim/math/constants.h"

namespace cga_rigid_sim {
namespace sensor {
namespace {

constexpr double kTwoPow53 = 9007199254740992.0;

// Two independent 64-bit words of (seed, stream, n): a hash chain, so neighbouring counters and
// neighbouring streams give unrelated words.
std::uint64_t word(std::uint64_t seed, std::uint64_t stream, std::uint64_t n, std::uint64_t k) {
  return mix64(mix64(mix64(seed) ^ stream) ^ mix64(n * 4 + k));
}

// The bias counter: far from the samples' counters (a run would need 2⁶² samples to reach it).
constexpr std::uint64_t kBiasCounter = std::uint64_t{1} << 62;

}  // namespace

double uniform01(std::uint64_t seed, std::uint64_t stream, std::uint64_t n) {
  return static_cast<double>(word(seed, stream, n, 2) >> 11) / kTwoPow53;
}

double standardNormal(std::uint64_t seed, std::uint64_t stream, std::uint64_t n) {
  // u1 in (0, 1] so that log(u1) is finite; u2 in [0, 1).
  const double u1 = static_cast<double>((word(seed, stream, n, 0) >> 11) + 1) / kTwoPow53;
  const double u2 = static_cast<double>(word(seed, stream, n, 1) >> 11) / kTwoPow53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * math::kPi * u2);
}

NoisyChannel::NoisyChannel(const scene::GaussianNoise& noise, std::uint64_t seed,
                           std::uint64_t stream)
    : noise_(noise), seed_(seed), stream_(stream) {
  if (noise.bias_mean == 0.0 && noise.bias_stddev == 0.0) return;
  bias_ = noise.bias_mean + noise.bias_stddev * standardNormal(seed, stream, kBiasCounter);
  if (uniform01(seed, stream, kBiasCounter) < 0.5) bias_ = -bias_;
}

double NoisyChannel::apply(double value, std::uint64_t n) const {
  if (noise_.stddev == 0.0 && noise_.mean == 0.0) return value + bias_;
  return value + bias_ + noise_.mean + noise_.stddev * standardNormal(seed_, stream_, n);
}

}  // namespace sensor
}  // namespace cga_rigid_sim
