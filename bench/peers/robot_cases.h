// Real robot descriptions in the contact benchmark (doc/benchmarks-contacts.md, "Real robots"):
// published URDFs with mesh collision shapes that nobody here wrote, read from Debian's dart-doc
// package at run time (never copied into the repository), run in every engine from the same
// file. No truth: these cases measure the cost of a step on a real robot, phase by phase, and
// report what the state looks like at each phase's end (the root's height, kinetic energy,
// contacts).
//
// Header-only so that our runner (bench/contacts.cc) and the peers (contacts_<engine>.cc) share
// it without a link dependency.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "../../test/common/real_like_robots.h"

namespace bench {
namespace robots {

// Debian's dart-doc data directory.
inline std::string dartData() { return "/usr/share/doc/dart/data"; }

struct RobotCase {
  std::string name;
  std::string urdf;  // absolute path; empty when `generate` writes it
  // A URDF written at run time: the text, given a directory for its meshes.
  std::function<std::string(const std::string& dir)> generate;
  // package:// names the URDF uses -> directories (resolved through ROS_PACKAGE_PATH: a
  // temporary directory of symlinks named after the packages).
  std::map<std::string, std::string> packages;
  bool floating = false;  // the root link is a free body (the humanoid); else fixed to the world
  std::string root_link;  // the floating root (observed: its height)
  // Contacts: collision meshes against each other (the engine's self-collision rule) and a
  // ground plane at ground_z. false: no contact at all (the arms), shapes dropped.
  bool contacts = false;
  double ground_z = 0;
  double h = 1e-3;
  // The phases timed separately: [0, phase_ends[0]), [phase_ends[0], phase_ends[1]), ...; the
  // last end is the case's duration.
  std::vector<double> phase_ends;
  std::vector<std::string> phase_names;
};

// Atlas v3 without head: 28 moving bodies (pelvis + 27 revolute joints; the six camera links
// are fixed to utorso), 29 STL collision meshes (the .dae are visuals), 146.6 kg, a floating
// pelvis at the origin. Its lowest point at the URDF's zero pose (the sole of the feet, the
// lowest vertex of the meshes at the identity pelvis pose) is z = -0.927351 m (MuJoCo's
// compiled geoms and our loader agree); the plane is 1 cm below it. It falls 1 cm, lands on
// its soles with straight legs and topples; a 5 s run shows the fall (first second) and the
// lying (last four).
inline RobotCase atlasFall() {
  RobotCase c;
  c.name = "atlas_fall";
  c.urdf = dartData() + "/sdf/atlas/atlas_v3_no_head.urdf";
  c.floating = true;
  c.root_link = "pelvis";
  c.contacts = true;
  c.ground_z = -0.927351 - 0.01;
  c.phase_ends = {1.0, 5.0};
  c.phase_names = {"fall", "lying"};
  return c;
}

// KUKA KR5 sixx R650: 6 revolute joints, fixed to the world; from the URDF's zero pose under
// gravity, no efforts, no contacts (its collision meshes dropped), 5 s.
inline RobotCase kr5Swing() {
  RobotCase c;
  c.name = "kr5_swing";
  c.urdf = dartData() + "/urdf/KR5/KR5 sixx R650.urdf";
  c.phase_ends = {5.0};
  c.phase_names = {"swing"};
  return c;
}

// Barrett WAM: 7 revolute joints, fixed to the world, meshes through
// package://herb_description; same protocol as kr5_swing.
inline RobotCase wamSwing() {
  RobotCase c;
  c.name = "wam_swing";
  c.urdf = dartData() + "/urdf/wam/wam.urdf";
  c.packages = {{"herb_description", dartData() + "/urdf/wam"}};
  c.phase_ends = {5.0};
  c.phase_names = {"swing"};
  return c;
}

// The tests' floating humanoid-like tree (test/common/real_like_robots.h: ten chamfered-box
// mesh links, 9 revolute joints with limits of ±2.5 rad, ~35 kg), written at run time: a
// dependency-free stand-in for Atlas. Its lowest point (the shins' soles) is z = -0.69 with the
// pelvis at the origin; the plane is 1 cm below.
inline RobotCase humanoidFall() {
  RobotCase c;
  c.name = "humanoid_fall";
  c.generate = [](const std::string& dir) { return cga_rigid_sim::test::humanoidUrdf(dir); };
  c.floating = true;
  c.root_link = "pelvis";
  c.contacts = true;
  c.ground_z = -0.69 - 0.01;
  c.phase_ends = {1.0, 5.0};
  c.phase_names = {"fall", "lying"};
  return c;
}

inline std::vector<RobotCase> allRobotCases() {
  return {atlasFall(), humanoidFall(), kr5Swing(), wamSwing()};
}

}  // namespace robots
}  // namespace bench
