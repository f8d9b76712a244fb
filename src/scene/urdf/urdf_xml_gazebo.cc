// The URDF reader's sensors and drives (urdf_reader.h): Gazebo's <gazebo reference="…"><sensor>
// with its gazebo_ros plugin, and the model plugins of <gazebo><plugin> (doc/sensors.md). Read
// after every link and joint is known. A sensor on an unknown link or joint, a negative rate or
// noise, a number that does not parse and a drive naming a joint that is not a wheel are refused
// with the file, the line and the rule; a sensor type or plugin we do not simulate is warned
// about by name and skipped.
#include <cmath>
#include <cstring>
#include <sstream>

#include "cga_rigid_sim/format.h"
#include "scene/urdf/urdf_reader.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

using tinyxml2::XMLElement;

namespace {

std::string trimmed(const char* raw) {
  std::string text = raw ? raw : "";
  text.erase(0, text.find_first_not_of(" \t\n\r"));
  text.erase(text.find_last_not_of(" \t\n\r") + 1);
  return text;
}

std::string childText(const XMLElement* e, const char* name) {
  const XMLElement* c = e->FirstChildElement(name);
  return c ? trimmed(c->GetText()) : std::string();
}

// The plugin's base name without a directory: "/opt/…/libgazebo_ros_p3d.so" → the file name.
std::string pluginFile(const XMLElement* plugin) {
  std::string file = trimmed(plugin->Attribute("filename"));
  const std::size_t slash = file.find_last_of('/');
  return slash == std::string::npos ? file : file.substr(slash + 1);
}

// gazebo_ros joins robotNamespace and the topic with '/'; ROS cleans repeated slashes.
std::string joinTopic(const std::string& ns, const std::string& topic) {
  std::string joined = ns.empty() ? topic : ns + "/" + topic;
  std::string out;
  for (char c : joined)
    if (!(c == '/' && !out.empty() && out.back() == '/')) out += c;
  if (out.size() > 1 && out.back() == '/') out.pop_back();
  return out;
}

// The names gazebo_ros's plugins read as the world frame.
bool isWorldName(const std::string& frame) {
  return frame == "world" || frame == "/world" || frame == "map" || frame == "/map";
}

// The name Gazebo's URDF → SDF conversion gives the k-th <collision> of `link` (sdformat's
// parser_urdf: the collision's name, or the link's when it has none, + "_collision", + "_k" for
// k > 0; a name that does not start with the link's is prefixed "<link>_fixed_joint_lump__").
std::string sdfCollisionName(const std::string& link, const CollisionShape& shape, int k) {
  const bool named = shape.name != link + "#" + std::to_string(k);
  std::string name = (named ? shape.name : link) + "_collision";
  if (k > 0) name += "_" + std::to_string(k);
  if (name.compare(0, link.size(), link) != 0) name = link + "_fixed_joint_lump__" + name;
  return name;
}

constexpr const char* kImuSensorPlugin = "libgazebo_ros_imu_sensor.so";
constexpr const char* kImuModelPlugin = "libgazebo_ros_imu.so";
constexpr const char* kFtPlugin = "libgazebo_ros_ft_sensor.so";
constexpr const char* kBumperPlugin = "libgazebo_ros_bumper.so";
constexpr const char* kP3dPlugin = "libgazebo_ros_p3d.so";
constexpr const char* kDiffDrivePlugin = "libgazebo_ros_diff_drive.so";
constexpr const char* kSkidSteerPlugin = "libgazebo_ros_skid_steer_drive.so";
constexpr const char* kControlPlugin = "libgazebo_ros_control.so";

}  // namespace

std::string Reader::robotNamespace(const XMLElement* plugin) const {
  return plugin_namespace_.empty() ? childText(plugin, "robotNamespace") : plugin_namespace_;
}

// A number in an element's text: finite, and ≥ 0 when `non_negative`. Absent: `out` unchanged.
std::optional<Error> Reader::readGazeboNumber(const XMLElement* parent, const char* name,
                                              const std::string& owner, bool non_negative,
                                              double* out) const {
  const XMLElement* c = parent->FirstChildElement(name);
  if (!c) return std::nullopt;
  const std::string text = trimmed(c->GetText());
  double value = 0.0;
  if (!parseUrdfNumber(text.c_str(), &value))
    return fail(c->GetLineNum(),
                owner + ": <" + name + "> must be a finite number (got " + inQuotes(text) + ")");
  if (non_negative && value < 0)
    return fail(c->GetLineNum(),
                owner + ": <" + name + "> must be >= 0 (got " + inQuotes(text) + ")");
  *out = value;
  return std::nullopt;
}

std::optional<Error> Reader::readGazeboTriple(const XMLElement* parent, const char* name,
                                              const std::string& owner,
                                              Eigen::Vector3d* out) const {
  const XMLElement* c = parent->FirstChildElement(name);
  if (!c) return std::nullopt;
  const std::string text = trimmed(c->GetText());
  if (!parseTriple(text.c_str(), out))
    return fail(c->GetLineNum(), owner + ": <" + name + "> must be three finite numbers (got " +
                                     inQuotes(text) + ")");
  return std::nullopt;
}

std::optional<Error> Reader::readGazeboBool(const XMLElement* parent, const char* name,
                                            const std::string& owner, bool* out) const {
  const XMLElement* c = parent->FirstChildElement(name);
  if (!c) return std::nullopt;
  const std::string text = trimmed(c->GetText());
  if (text == "true" || text == "1")
    *out = true;
  else if (text == "false" || text == "0")
    *out = false;
  else
    return fail(c->GetLineNum(),
                owner + ": <" + name + "> must be true or false (got " + inQuotes(text) + ")");
  return std::nullopt;
}

// SDF's <noise type="gaussian"> (or "gaussian_quantized"; "none" is no noise) with <mean>,
// <stddev>, <bias_mean>, <bias_stddev>; stddev and the bias's are ≥ 0.
std::optional<Error> Reader::readNoise(const XMLElement* holder, const std::string& owner,
                                       GaussianNoise* noise) {
  const XMLElement* n = holder->FirstChildElement("noise");
  if (!n) return std::nullopt;
  std::string type = trimmed(n->Attribute("type"));
  if (type.empty()) type = childText(n, "type");  // SDF 1.4 wrote <type> as an element
  if (type == "none") return std::nullopt;
  if (type != "gaussian" && type != "gaussian_quantized")
    return fail(n->GetLineNum(), owner + ": <noise type=" + inQuotes(type) +
                                     "> is not supported (gaussian, gaussian_quantized or none)");
  if (type == "gaussian_quantized")
    warn(n->GetLineNum(), owner +
                              ": <noise type='gaussian_quantized'>: the quantisation "
                              "(<precision>) is not modelled, the Gaussian part is");
  if (auto err = readGazeboNumber(n, "mean", owner + " <noise>", false, &noise->mean)) return err;
  for (auto [name, value] :
       {std::pair{"stddev", &noise->stddev}, std::pair{"bias_mean", &noise->bias_mean},
        std::pair{"bias_stddev", &noise->bias_stddev}})
    if (auto err = readGazeboNumber(n, name, owner + " <noise>", true, value)) return err;
  return std::nullopt;
}

// SDF <pose>x y z roll pitch yaw</pose>, relative to the link.
std::optional<Error> Reader::readSensorPose(const XMLElement* sensor, const std::string& owner,
                                            Eigen::Isometry3d* X_LS) const {
  X_LS->setIdentity();
  const XMLElement* p = sensor->FirstChildElement("pose");
  if (!p) return std::nullopt;
  std::istringstream in(trimmed(p->GetText()));
  double v[6];
  int n = 0;
  std::string piece;
  while (in >> piece) {
    if (n == 6 || !parseUrdfNumber(piece.c_str(), &v[n]))
      return fail(p->GetLineNum(), owner +
                                       ": <pose> must be six finite numbers, x y z roll pitch "
                                       "yaw (got " +
                                       inQuotes(trimmed(p->GetText())) + ")");
    ++n;
  }
  if (n != 6)
    return fail(p->GetLineNum(), owner +
                                     ": <pose> must be six finite numbers, x y z roll pitch "
                                     "yaw (got " +
                                     inQuotes(trimmed(p->GetText())) + ")");
  X_LS->linear() = rotationFromRpy({v[3], v[4], v[5]});
  X_LS->translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return std::nullopt;
}

void Reader::warn(int line, const std::string& what) {
  out_.warnings.push_back(source_ + ":" + std::to_string(line) + ": " + what);
}

bool Reader::isLink(const std::string& name) const { return out_.links.count(name) > 0; }

const Reader::JointEdge* Reader::findEdge(const std::string& joint) const {
  for (const JointEdge& e : edges_)
    if (e.name == joint) return &e;
  return nullptr;
}

// One <gazebo> element: with reference, the sensors of that link (or, for force_torque, joint);
// without, the model plugins.
std::optional<Error> Reader::readGazeboSensors(const XMLElement* gazebo) {
  const char* reference = gazebo->Attribute("reference");
  for (const XMLElement* c = gazebo->FirstChildElement(); c; c = c->NextSiblingElement()) {
    if (std::strcmp(c->Name(), "sensor") == 0) {
      if (!reference)
        return fail(c->GetLineNum(),
                    "<sensor> must be inside <gazebo reference=\"link\"> (the "
                    "link it is fixed to; a force_torque sensor's reference "
                    "is its joint)");
      if (auto err = readSensor(c, reference)) return err;
    } else if (std::strcmp(c->Name(), "plugin") == 0) {
      if (reference) {
        warn(c->GetLineNum(), "<gazebo reference=" + inQuotes(reference) +
                                  "><plugin filename=" + inQuotes(pluginFile(c)) +
                                  "> outside a <sensor>: ignored (model plugins go in <gazebo> "
                                  "without reference)");
        continue;
      }
      if (auto err = readModelPlugin(c)) return err;
    }
  }
  return std::nullopt;
}

std::optional<Error> Reader::readSensor(const XMLElement* e, const std::string& reference) {
  const std::string type = trimmed(e->Attribute("type"));
  const std::string name = trimmed(e->Attribute("name"));
  const std::string owner = "<gazebo reference=" + inQuotes(reference) +
                            "><sensor name=" + inQuotes(name) + " type=" + inQuotes(type) + ">";
  const int line = e->GetLineNum();
  SensorModel s;
  s.name = name;
  s.line = line;
  if (type == "imu") {
    s.kind = SensorKind::kImu;
  } else if (type == "force_torque") {
    s.kind = SensorKind::kForceTorque;
  } else if (type == "contact") {
    s.kind = SensorKind::kContact;
  } else {
    warn(line, owner + ": sensor type " + inQuotes(type) +
                   " is not simulated (imu, force_torque and contact are): ignored");
    return std::nullopt;
  }
  // The reference: a link, or for force_torque a joint (whose child link carries it).
  if (s.kind == SensorKind::kForceTorque) {
    const JointEdge* joint = findEdge(reference);
    if (!joint)
      return fail(line, owner + ": " + inQuotes(reference) +
                            " is not a joint of this URDF (a force_torque sensor measures the "
                            "joint its <gazebo reference> names)");
    s.joint = joint->name;
    s.link = joint->child;
  } else {
    if (!isLink(reference))
      return fail(line, owner + ": " + inQuotes(reference) +
                            " is not a link of this URDF (a sensor is fixed to the link its "
                            "<gazebo reference> names)");
    s.link = reference;
  }
  if (auto err = readGazeboNumber(e, "update_rate", owner, true, &s.update_rate)) return err;
  if (auto err = readSensorPose(e, owner, &s.X_LS)) return err;
  s.frame_id = s.link;

  if (const XMLElement* imu = e->FirstChildElement("imu")) {
    const char* axes[3] = {"x", "y", "z"};
    for (auto [group, noises] : {std::pair{"angular_velocity", &s.angular_velocity_noise},
                                 std::pair{"linear_acceleration", &s.linear_acceleration_noise}})
      if (const XMLElement* g = imu->FirstChildElement(group))
        for (int k = 0; k < 3; ++k)
          if (const XMLElement* axis = g->FirstChildElement(axes[k]))
            if (auto err = readNoise(axis, owner + " <imu><" + group + "><" + axes[k] + ">",
                                     &(*noises)[k]))
              return err;
    // SDF 1.4: <imu><noise type="gaussian"><rate>…</rate><accel>…</accel></noise>.
    if (const XMLElement* n = imu->FirstChildElement("noise")) {
      for (auto [group, noises] : {std::pair{"rate", &s.angular_velocity_noise},
                                   std::pair{"accel", &s.linear_acceleration_noise}})
        if (const XMLElement* g = n->FirstChildElement(group)) {
          GaussianNoise noise;
          for (auto [field, value] :
               {std::pair{"mean", &noise.mean}, std::pair{"stddev", &noise.stddev},
                std::pair{"bias_mean", &noise.bias_mean},
                std::pair{"bias_stddev", &noise.bias_stddev}})
            if (auto err = readGazeboNumber(g, field, owner + " <imu><noise><" + group + ">",
                                            std::strcmp(field, "mean") != 0, value))
              return err;
          noises->fill(noise);
        }
    }
  }
  if (const XMLElement* ft = e->FirstChildElement("force_torque")) {
    const std::string frame = childText(ft, "frame");
    if (frame == "child" || frame.empty())
      s.wrench_frame = WrenchFrame::kChild;
    else if (frame == "parent")
      s.wrench_frame = WrenchFrame::kParent, s.frame_id = findEdge(s.joint)->parent;
    else if (frame == "sensor")
      s.wrench_frame = WrenchFrame::kSensor;
    else
      return fail(ft->GetLineNum(), owner +
                                        ": <force_torque><frame> must be child, parent or "
                                        "sensor (got " +
                                        inQuotes(frame) + ")");
    const std::string direction = childText(ft, "measure_direction");
    if (direction == "child_to_parent" || direction.empty())
      s.measure_direction = MeasureDirection::kChildToParent;
    else if (direction == "parent_to_child")
      s.measure_direction = MeasureDirection::kParentToChild;
    else
      return fail(ft->GetLineNum(), owner +
                                        ": <force_torque><measure_direction> must be "
                                        "child_to_parent or parent_to_child (got " +
                                        inQuotes(direction) + ")");
  }

  // The ROS plugin that publishes it; without one Gazebo publishes nothing on ROS.
  const XMLElement* plugin = nullptr;
  for (const XMLElement* p = e->FirstChildElement("plugin"); p;
       p = p->NextSiblingElement("plugin")) {
    const std::string file = pluginFile(p);
    const bool fits = (s.kind == SensorKind::kImu && file == kImuSensorPlugin) ||
                      (s.kind == SensorKind::kForceTorque && file == kFtPlugin) ||
                      (s.kind == SensorKind::kContact && file == kBumperPlugin);
    if (fits && !plugin)
      plugin = p;
    else
      warn(p->GetLineNum(), owner + ": plugin " + inQuotes(file) +
                                " is not one this sensor type runs here (imu: " + kImuSensorPlugin +
                                ", force_torque: " + kFtPlugin + ", contact: " + kBumperPlugin +
                                "): ignored");
  }
  if (!plugin) {
    warn(line, owner + " has no gazebo_ros plugin, so nothing publishes it: ignored");
    return std::nullopt;
  }
  s.plugin = pluginFile(plugin);
  const std::string powner = owner + "<plugin filename=" + inQuotes(s.plugin) + ">";
  std::string ns = robotNamespace(plugin);
  if (s.kind == SensorKind::kImu) {
    // gazebo_ros_imu_sensor: robotNamespace defaults to the model's name, topicName to
    // imu_data; updateRateHZ (default 1) gates the sensor's own update_rate.
    if (plugin_namespace_.empty() && !plugin->FirstChildElement("robotNamespace"))
      ns = "/" + out_.robot_name;
    const std::string topic = childText(plugin, "topicName");
    s.topic = joinTopic(ns, topic.empty() ? "imu_data" : topic);
    double rate = 1.0;
    if (auto err = readGazeboNumber(plugin, "updateRateHZ", powner, true, &rate)) return err;
    if (rate > 0 && (s.update_rate == 0 || rate < s.update_rate)) s.update_rate = rate;
    if (auto err = readGazeboNumber(plugin, "gaussianNoise", powner, true, &s.gaussian_noise))
      return err;
    Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
    if (auto err = readGazeboTriple(plugin, "rpyOffset", powner, &rpy)) return err;
    s.X_LS.linear() = s.X_LS.linear() * rotationFromRpy(rpy);
    if (auto err = readGazeboBool(plugin, "initialOrientationAsReference", powner,
                                  &s.initial_orientation_as_reference))
      return err;
    std::string frame = childText(plugin, "frameName");
    if (frame.empty()) frame = childText(plugin, "bodyName");
    if (!frame.empty()) s.frame_id = frame;
  } else if (s.kind == SensorKind::kForceTorque) {
    const std::string topic = childText(plugin, "topicName");
    s.topic = joinTopic(ns, topic.empty() ? "ft_sensor" : topic);
    double rate = 0.0;
    if (auto err = readGazeboNumber(plugin, "updateRate", powner, true, &rate)) return err;
    if (rate > 0 && (s.update_rate == 0 || rate < s.update_rate)) s.update_rate = rate;
    if (auto err = readGazeboNumber(plugin, "gaussianNoise", powner, true, &s.gaussian_noise))
      return err;
  } else {
    // gazebo_ros_bumper: bumperTopicName (default bumper_states), frameName (default world:
    // the contacts in world coordinates; a link: in that link's frame).
    const std::string topic = childText(plugin, "bumperTopicName");
    s.topic = joinTopic(ns, topic.empty() ? "bumper_states" : topic);
    const std::string frame = childText(plugin, "frameName");
    s.frame_id = frame.empty() ? "world" : frame;
    s.reference_link = isWorldName(s.frame_id) ? "world" : s.frame_id;
    if (s.reference_link != "world" && !isLink(s.reference_link))
      return fail(plugin->GetLineNum(), powner + ": <frameName> " + inQuotes(frame) +
                                            " is neither world nor a link of this URDF (the "
                                            "bumper's contacts are expressed in it)");
    readBumperCollision(e, owner, &s);
  }
  out_.sensors.sensors.push_back(std::move(s));
  return std::nullopt;
}

// A contact sensor's <contact><collision>: which of its link's collisions it reports, by the SDF
// name Gazebo gives them (also as lumped into a parent: "<parent>_fixed_joint_lump__<name>").
// A name that is none of them is warned about; the sensor then reports every collision of the
// link.
void Reader::readBumperCollision(const XMLElement* sensor, const std::string& owner,
                                 SensorModel* s) {
  const XMLElement* contact = sensor->FirstChildElement("contact");
  if (!contact || !contact->FirstChildElement("collision")) return;
  const std::string wanted = childText(contact, "collision");
  const auto link = out_.links.find(s->link);
  std::vector<std::string> names;
  if (link != out_.links.end())
    for (std::size_t k = 0; k < link->second.collisions.size(); ++k) {
      const std::string name =
          sdfCollisionName(s->link, link->second.collisions[k].shape, static_cast<int>(k));
      const std::string lumped = "_fixed_joint_lump__" + name;
      const bool lumped_match =
          wanted.size() > lumped.size() &&
          wanted.compare(wanted.size() - lumped.size(), lumped.size(), lumped) == 0;
      if (wanted == name || lumped_match) {
        s->collision = static_cast<int>(k);
        return;
      }
      names.push_back(inQuotes(name));
    }
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  warn(contact->GetLineNum(),
       owner + ": <contact><collision> " + inQuotes(wanted) + " is not a collision of link " +
           inQuotes(s->link) + " (" +
           (names.empty() ? std::string("it has none") : "its SDF names: " + list) +
           "): the bumper reports every contact of the link");
}

// A <plugin> of <gazebo> without reference: p3d, imu (the model plugin), ft_sensor, the drives.
std::optional<Error> Reader::readModelPlugin(const XMLElement* p) {
  const std::string file = pluginFile(p);
  const std::string name = trimmed(p->Attribute("name"));
  const std::string owner =
      "<gazebo><plugin name=" + inQuotes(name) + " filename=" + inQuotes(file) + ">";
  const int line = p->GetLineNum();
  const std::string ns = robotNamespace(p);
  // A link a plugin names in `element` (required).
  auto needLink = [&](const char* element, std::string* link) -> std::optional<Error> {
    *link = childText(p, element);
    if (link->empty()) return fail(line, owner + " has no <" + element + "> (the link it reads)");
    if (!isLink(*link))
      return fail(line,
                  owner + ": <" + element + "> " + inQuotes(*link) + " is not a link of this URDF");
    return std::nullopt;
  };

  if (file == kP3dPlugin || file == kImuModelPlugin) {
    SensorModel s;
    s.kind = file == kP3dPlugin ? SensorKind::kGroundTruth : SensorKind::kImu;
    s.name = name;
    s.plugin = file;
    s.line = line;
    if (auto err = needLink("bodyName", &s.link)) return err;
    std::string topic = childText(p, "topicName");
    if (topic.empty()) {
      if (s.kind == SensorKind::kGroundTruth)
        return fail(line, owner + " has no <topicName> (gazebo_ros_p3d requires one)");
      topic = "/default_imu";  // gazebo_ros_imu's default
    }
    s.topic = joinTopic(ns, topic);
    if (auto err = readGazeboNumber(p, "updateRate", owner, true, &s.update_rate)) return err;
    if (auto err = readGazeboNumber(p, "gaussianNoise", owner, true, &s.gaussian_noise)) return err;
    if (s.kind == SensorKind::kGroundTruth) {
      // gazebo_ros_p3d: frameName (default world) is the reference; offsets in it.
      s.reference_link = childText(p, "frameName");
      if (s.reference_link.empty()) s.reference_link = "world";
      if (!isWorldName(s.reference_link) && !isLink(s.reference_link))
        return fail(line, owner + ": <frameName> " + inQuotes(s.reference_link) +
                              " is neither world nor a link of this URDF");
      if (isWorldName(s.reference_link)) s.reference_link = "world";
      s.frame_id = childText(p, "frameName").empty() ? "world" : childText(p, "frameName");
      if (auto err = readGazeboTriple(p, "xyzOffsets", owner, &s.xyz_offset)) return err;
      if (auto err = readGazeboTriple(p, "rpyOffsets", owner, &s.rpy_offset)) return err;
    } else {
      std::string frame = childText(p, "frameName");
      s.frame_id = frame.empty() ? s.link : frame;
      Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
      if (auto err = readGazeboTriple(p, "xyzOffset", owner, &xyz)) return err;
      if (auto err = readGazeboTriple(p, "rpyOffset", owner, &rpy)) return err;
      s.X_LS.linear() = rotationFromRpy(rpy);
      s.X_LS.translation() = xyz;
    }
    out_.sensors.sensors.push_back(std::move(s));
    return std::nullopt;
  }
  if (file == kFtPlugin) {
    SensorModel s;
    s.kind = SensorKind::kForceTorque;
    s.name = name;
    s.plugin = file;
    s.line = line;
    s.joint = childText(p, "jointName");
    if (s.joint.empty()) return fail(line, owner + " has no <jointName> (the joint it measures)");
    const JointEdge* joint = findEdge(s.joint);
    if (!joint)
      return fail(line,
                  owner + ": <jointName> " + inQuotes(s.joint) + " is not a joint of this URDF");
    s.link = joint->child;
    s.frame_id = s.link;
    const std::string topic = childText(p, "topicName");
    if (topic.empty()) return fail(line, owner + " has no <topicName>");
    s.topic = joinTopic(ns, topic);
    if (auto err = readGazeboNumber(p, "updateRate", owner, true, &s.update_rate)) return err;
    if (auto err = readGazeboNumber(p, "gaussianNoise", owner, true, &s.gaussian_noise)) return err;
    // gazebo_ros_ft_sensor reports the wrench on the child, in the child link's frame.
    s.measure_direction = MeasureDirection::kParentToChild;
    out_.sensors.sensors.push_back(std::move(s));
    return std::nullopt;
  }
  if (file == kDiffDrivePlugin || file == kSkidSteerPlugin) return readDrive(p, file, name);
  if (file == kControlPlugin) {
    warn(line, owner +
                   ": ignored; the node's controllers come from ~controllers in the "
                   "ros_control YAML vocabulary (doc/control.md)");
    return std::nullopt;
  }
  warn(line, owner + ": plugin " + inQuotes(file) + " is not simulated (model plugins read: " +
                 kP3dPlugin + ", " + kImuModelPlugin + ", " + kFtPlugin + ", " + kDiffDrivePlugin +
                 ", " + kSkidSteerPlugin + "): ignored");
  return std::nullopt;
}

std::optional<Error> Reader::readDrive(const XMLElement* p, const std::string& file,
                                       const std::string& name) {
  const std::string owner =
      "<gazebo><plugin name=" + inQuotes(name) + " filename=" + inQuotes(file) + ">";
  const int line = p->GetLineNum();
  DriveModel d;
  d.name = name;
  d.plugin = file;
  d.line = line;
  const bool diff = file == kDiffDrivePlugin;
  d.kind = diff ? DriveKind::kDifferential : DriveKind::kSkidSteer;
  // The wheel joints, by the plugin's element names and defaults.
  using Wheel = std::pair<const char*, const char*>;  // element, default joint name
  const std::vector<Wheel> left = diff ? std::vector<Wheel>{{"leftJoint", "left_joint"}}
                                       : std::vector<Wheel>{{"leftFrontJoint", "left_front_joint"},
                                                            {"leftRearJoint", "left_rear_joint"}};
  const std::vector<Wheel> right =
      diff ? std::vector<Wheel>{{"rightJoint", "right_joint"}}
           : std::vector<Wheel>{{"rightFrontJoint", "right_front_joint"},
                                {"rightRearJoint", "right_rear_joint"}};
  for (auto [wheels, out] : {std::pair{&left, &d.left_joints}, std::pair{&right, &d.right_joints}})
    for (const auto& [element, fallback] : *wheels) {
      std::string joint = childText(p, element);
      if (joint.empty()) joint = fallback;
      const auto it = out_.joints.find(joint);
      if (it == out_.joints.end())
        return fail(line, owner + ": <" + element + "> names joint " + inQuotes(joint) +
                              ", which is not a joint of this URDF (a drive turns its wheels' "
                              "continuous or revolute joints)");
      if (!it->second.type || *it->second.type == JointType::kPrismatic)
        return fail(line, owner + ": <" + element + "> names joint " + inQuotes(joint) +
                              ", which is not continuous or revolute (a wheel turns)");
      out->push_back(joint);
    }
  if (!diff) {
    d.wheel_separation = 0.4;  // gazebo_ros_skid_steer_drive's defaults
    d.wheel_torque = 4.0;
    d.publish_odom_tf = false;
  }
  if (auto err = readGazeboNumber(p, "wheelSeparation", owner, true, &d.wheel_separation))
    return err;
  if (auto err = readGazeboNumber(p, "wheelDiameter", owner, true, &d.wheel_diameter)) return err;
  if (auto err = readGazeboNumber(p, diff ? "wheelTorque" : "torque", owner, true, &d.wheel_torque))
    return err;
  if (auto err = readGazeboNumber(p, "wheelAcceleration", owner, true, &d.wheel_acceleration))
    return err;
  if (auto err = readGazeboNumber(p, "updateRate", owner, true, &d.update_rate)) return err;
  if (auto err = readGazeboNumber(p, "commandTimeout", owner, true, &d.command_timeout)) return err;
  if (!(d.wheel_separation > 0) || !(d.wheel_diameter > 0))
    return fail(line, owner + ": wheelSeparation and wheelDiameter must be > 0");
  const std::string ns = robotNamespace(p);
  for (auto [element, out] :
       {std::pair{"commandTopic", &d.command_topic}, std::pair{"odometryTopic", &d.odometry_topic},
        std::pair{"odometryFrame", &d.odometry_frame},
        std::pair{"robotBaseFrame", &d.robot_base_frame}}) {
    const std::string text = childText(p, element);
    if (!text.empty()) *out = text;
  }
  d.command_topic = joinTopic(ns, d.command_topic);
  d.odometry_topic = joinTopic(ns, d.odometry_topic);
  if (auto err =
          readGazeboBool(p, diff ? "publishOdomTF" : "broadcastTF", owner, &d.publish_odom_tf))
    return err;
  if (auto err = readGazeboBool(p, "publishWheelTF", owner, &d.publish_wheel_tf)) return err;
  if (auto err = readGazeboBool(p, "publishWheelJointState", owner, &d.publish_wheel_joint_state))
    return err;
  const std::string source = childText(p, "odometrySource");
  if (diff && (source == "encoder" || source == "0"))
    d.odometry_from_world = false;
  else if (source == "world" || source == "1" || source.empty())
    d.odometry_from_world = true;
  else
    return fail(
        line, owner + ": <odometrySource> must be encoder or world (got " + inQuotes(source) + ")");
  out_.sensors.drives.push_back(std::move(d));
  return std::nullopt;
}

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
