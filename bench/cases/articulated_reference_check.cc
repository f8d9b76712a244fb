// bench_articulated_reference: how good the articulated truth is (articulated_reference.h), and
// whether bench/cases/articulated_cases.h describes the URDFs it names.
//
//   bench_articulated_reference [--cases a,b] [--no-urdf]
//
// Per case: the reference at h = kReferenceStep against the same integration at 2 h (RK4: the
// error of the h run is ~1/15 of that difference) and at h/2; for the double pendulum also the
// hand-written Lagrange equations against the generic dynamics; the reference's own energy drift;
// each joint's range over [0, T] against its URDF limit. With urdfdom (CGA_HAVE_URDFDOM), the
// case's masses, CoMs, inertias, joint origins and axes against the URDF file.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "articulated_reference.h"

#ifdef CGA_HAVE_URDFDOM
#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <sstream>
#endif

#ifndef BENCH_REPO_ROOT
#define BENCH_REPO_ROOT "."
#endif

namespace {

using namespace bench::articulated;

double maxDiff(const std::vector<long double>& a, const std::vector<long double>& b, bool angle) {
  double e = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const long double d = a[i] - b[i];
    e = std::max(e, double(std::fabs(angle ? wrapAngle<long double>(d) : d)));
  }
  return e;
}

// Angle between two base orientations (rad); 0 for a fixed base.
double baseDiff(const ReferenceRun& a, const ReferenceRun& b) {
  const Eigen::Matrix3d d = (a.base.R.transpose() * b.base.R).cast<double>();
  const double c = std::max(-1.0, std::min(1.0, 0.5 * (d.trace() - 1)));
  // acos loses digits near 0: use the skew part as well.
  const Eigen::Vector3d s(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1));
  return std::atan2(0.5 * s.norm(), c);
}

#ifdef CGA_HAVE_URDFDOM
// Largest deviation between the case and the URDF file; prints what differs.
double compareWithUrdf(const ArticulatedCase& c) {
  const std::string path = std::string(BENCH_REPO_ROOT) + "/" + c.urdf;
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(ss.str());
  if (!model) {
    std::printf("  urdf: cannot parse %s\n", path.c_str());
    return INFINITY;
  }
  double worst = 0;
  auto check = [&](const std::string& what, double a, double b) {
    const double d = std::fabs(a - b);
    if (d > 1e-15) std::printf("  urdf: %s differs: case %.17g, urdf %.17g\n", what.c_str(), a, b);
    worst = std::max(worst, d);
  };
  if (c.base.floating) {
    urdf::LinkConstSharedPtr ub = model->getLink(c.base.link);
    if (!ub || !ub->inertial || model->getRoot() != ub) {
      std::printf("  urdf: base link %s missing or not the root\n", c.base.link.c_str());
      return INFINITY;
    }
    check("base mass", c.base.mass, ub->inertial->mass);
    check("base com.x", c.base.com[0], ub->inertial->origin.position.x);
    check("base com.y", c.base.com[1], ub->inertial->origin.position.y);
    check("base com.z", c.base.com[2], ub->inertial->origin.position.z);
    check("base ixx", c.base.inertia_diag[0], ub->inertial->ixx);
    check("base iyy", c.base.inertia_diag[1], ub->inertial->iyy);
    check("base izz", c.base.inertia_diag[2], ub->inertial->izz);
  }
  for (int i = 0; i < c.n(); ++i) {
    const JointSpec& j = c.joints[i];
    urdf::JointConstSharedPtr uj = model->getJoint(j.joint);
    urdf::LinkConstSharedPtr ul = model->getLink(j.link);
    if (!uj || !ul || !ul->inertial) {
      std::printf("  urdf: joint %s or link %s missing\n", j.joint.c_str(), j.link.c_str());
      return INFINITY;
    }
    check(j.link + " mass", j.mass, ul->inertial->mass);
    const auto& o = ul->inertial->origin.position;
    check(j.link + " com.x", j.com[0], o.x);
    check(j.link + " com.y", j.com[1], o.y);
    check(j.link + " com.z", j.com[2], o.z);
    check(j.link + " ixx", j.inertia_diag[0], ul->inertial->ixx);
    check(j.link + " iyy", j.inertia_diag[1], ul->inertial->iyy);
    check(j.link + " izz", j.inertia_diag[2], ul->inertial->izz);
    check(
        j.link + " ixy+ixz+iyz", 0,
        std::fabs(ul->inertial->ixy) + std::fabs(ul->inertial->ixz) + std::fabs(ul->inertial->iyz));
    check(j.joint + " axis.x", j.axis[0], uj->axis.x);
    check(j.joint + " axis.y", j.axis[1], uj->axis.y);
    check(j.joint + " axis.z", j.axis[2], uj->axis.z);
    check(j.joint + " limit", j.limit,
          uj->type == urdf::Joint::CONTINUOUS ? 0.0 : (uj->limits ? uj->limits->upper : 0.0));
    // The joint origin in the world for a root joint (composed with fixed joints above it).
    urdf::Pose pose = uj->parent_to_joint_origin_transform;
    std::string parent = uj->parent_link_name;
    if (j.parent >= 0) {
      if (parent != c.joints[j.parent].link)
        std::printf("  urdf: %s parent differs\n", j.joint.c_str());
    } else {
      for (urdf::LinkConstSharedPtr l = model->getLink(parent); l && l->parent_joint;
           l = model->getLink(l->parent_joint->parent_link_name)) {
        const urdf::Pose& up = l->parent_joint->parent_to_joint_origin_transform;
        urdf::Pose composed;
        composed.rotation = up.rotation * pose.rotation;
        const urdf::Vector3 r = up.rotation * pose.position;
        composed.position =
            urdf::Vector3(up.position.x + r.x, up.position.y + r.y, up.position.z + r.z);
        pose = composed;
      }
    }
    check(j.joint + " origin.x", j.origin_xyz[0], pose.position.x);
    check(j.joint + " origin.y", j.origin_xyz[1], pose.position.y);
    check(j.joint + " origin.z", j.origin_xyz[2], pose.position.z);
    for (int col = 0; col < 3; ++col) {
      urdf::Vector3 e(col == 0, col == 1, col == 2);
      const urdf::Vector3 r = pose.rotation * e;
      const double rv[3] = {r.x, r.y, r.z};
      for (int row = 0; row < 3; ++row)
        check(j.joint + " origin.R", j.origin_R[3 * row + col], rv[row]);
    }
  }
  return worst;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> only;
  bool urdf = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--cases" && i + 1 < argc) {
      std::string s = argv[++i], t;
      for (char ch : s + ",")
        if (ch == ',') {
          if (!t.empty()) only.push_back(t);
          t.clear();
        } else {
          t += ch;
        }
    } else if (a == "--no-urdf")
      urdf = false;
    else {
      std::printf("usage: %s [--cases a,b] [--no-urdf]\n", argv[0]);
      return a == "--help" ? 0 : 2;
    }
  }
  for (const ArticulatedCase& c : allArticulatedCases()) {
    if (!only.empty() && std::find(only.begin(), only.end(), c.name) == only.end()) continue;
    const double h = kReferenceStep;
    std::printf("%s: T = %g s, E0 = %.12g J, reference RK4 long double h = %g\n", c.name.c_str(),
                c.T, energy(c, c.q0, c.qd0), h);
    const ReferenceRun r1 = integrateReference(c, h);
    const ReferenceRun r2 = integrateReference(c, 2 * h);
    const ReferenceRun rh = integrateReference(c, h / 2);
    std::printf("  |q(h) - q(2h)|max   = %.3e rad   |qd(h) - qd(2h)|max   = %.3e rad/s\n",
                maxDiff(r1.q, r2.q, true), maxDiff(r1.qd, r2.qd, false));
    std::printf("  |q(h) - q(h/2)|max  = %.3e rad   |qd(h) - qd(h/2)|max  = %.3e rad/s\n",
                maxDiff(r1.q, rh.q, true), maxDiff(r1.qd, rh.qd, false));
    if (c.base.floating)
      std::printf(
          "  base orientation: h vs 2h %.3e rad, h vs h/2 %.3e rad; |w_b(h) - w_b(h/2)| = %.3e "
          "rad/s\n",
          baseDiff(r1, r2), baseDiff(r1, rh), double((r1.base.w - rh.base.w).norm()));
    if (c.name == "double_pendulum") {
      const ReferenceRun rl = integrateReference(c, h, Rhs::kLagrangeDoublePendulum);
      std::printf("  |q(generic) - q(Lagrange)|max = %.3e rad   qd: %.3e rad/s (same h)\n",
                  maxDiff(r1.q, rl.q, true), maxDiff(r1.qd, rl.qd, false));
    }
    std::printf("  energy drift of the reference: %.3e (relative to E0)\n",
                double(r1.max_energy_drift_rel));
    std::printf("  q(T) =");
    for (long double v : r1.q) std::printf(" %.15Lg", v);
    std::printf("\n  range over [0, T] (rad) and URDF limit:\n");
    for (int i = 0; i < c.n(); ++i) {
      const JointSpec& j = c.joints[i];
      const bool inside = j.limit == 0 || (r1.q_min[i] > -j.limit && r1.q_max[i] < j.limit);
      std::printf("    %-9s [%+8.4f, %+8.4f]  limit %s%s\n", j.joint.c_str(), r1.q_min[i],
                  r1.q_max[i], j.limit == 0 ? "none" : ("+-" + std::to_string(j.limit)).c_str(),
                  inside ? "" : "  OUTSIDE");
    }
#ifdef CGA_HAVE_URDFDOM
    if (urdf)
      std::printf("  case vs %s: largest difference %.3e\n", c.urdf.c_str(), compareWithUrdf(c));
#else
    (void)urdf;
#endif
  }
  return 0;
}
