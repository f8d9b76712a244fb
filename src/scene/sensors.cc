// Names of the sensor kinds (sensors.h), for summaries and messages.
#include "cga_rigid_sim/scene/sensors.h"

namespace cga_rigid_sim {
namespace scene {

const char* toString(SensorKind k) {
  switch (k) {
    case SensorKind::kImu:
      return "imu";
    case SensorKind::kForceTorque:
      return "force_torque";
    case SensorKind::kContact:
      return "contact";
    case SensorKind::kGroundTruth:
      return "ground_truth";
  }
  return "?";
}

}  // namespace scene
}  // namespace cga_rigid_sim
