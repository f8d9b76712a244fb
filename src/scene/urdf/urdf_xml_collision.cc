// The collision part of the URDF reader (urdf_reader.h): <collision> geometry with its origin,
// the contact parameters of the extension <cga_rigid_sim:contact>, and Gazebo's <mu1>/<mu2>
// and <self_collide> (doc/urdf.md).
#include <algorithm>
#include <cmath>
#include <cstring>

#include "cga_rigid_sim/format.h"
#include "scene/urdf/urdf_reader.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

using tinyxml2::XMLAttribute;
using tinyxml2::XMLElement;

// The <geometry> of a <visual> or <collision>: its shape element and numbers, in urdfdom's
// syntax. `strict` (a collision): sizes > 0 and a mesh scale without zeros, as a collision shape
// (and a mass from geometry) needs; a <visual> is only read as urdfdom reads it.
std::optional<Error> Reader::readGeometry(const XMLElement* holder, const std::string& owner,
                                          bool strict, CollisionGeometry* g) const {
  using Kind = CollisionShape::Kind;
  CollisionShape& shape_out = g->shape;
  const std::string where = owner + ": <" + holder->Name() + ">";
  if (auto err = readOrigin(holder, owner, &g->X_LS)) return err;
  const XMLElement* geometry = holder->FirstChildElement("geometry");
  if (!geometry) return fail(holder->GetLineNum(), where + " has no <geometry>");
  const XMLElement* shape = geometry->FirstChildElement();
  if (!shape) return fail(geometry->GetLineNum(), where + ": <geometry> is empty");
  g->geometry_line = shape->GetLineNum();
  const std::string kind = shape->Name();
  const std::string shape_owner = owner + ": <" + holder->Name() + "><" + kind + ">";
  auto positive = [&](double value, const char* attr) -> std::optional<Error> {
    if (!strict || value > 0) return std::nullopt;
    return fail(shape->GetLineNum(),
                shape_owner + " " + attr + " must be > 0 (got " + formatNumber(value, 6) + ")");
  };
  if (kind == "box") {
    shape_out.kind = Kind::kBox;
    const char* text = shape->Attribute("size");
    if (!text || !parseTriple(text, &shape_out.size))
      return fail(shape->GetLineNum(), shape_owner + " size must be three finite numbers (got " +
                                           inQuotes(text ? text : "") + ")");
    for (int k = 0; k < 3; ++k)
      if (auto err = positive(shape_out.size[k], "size")) return err;
  } else if (kind == "cylinder") {
    shape_out.kind = Kind::kCylinder;
    if (auto err = readNumberAttr(shape, "radius", owner, true, &shape_out.radius)) return err;
    if (auto err = readNumberAttr(shape, "length", owner, true, &shape_out.length)) return err;
    if (auto err = positive(shape_out.radius, "radius")) return err;
    if (auto err = positive(shape_out.length, "length")) return err;
  } else if (kind == "sphere") {
    shape_out.kind = Kind::kSphere;
    if (auto err = readNumberAttr(shape, "radius", owner, true, &shape_out.radius)) return err;
    if (auto err = positive(shape_out.radius, "radius")) return err;
  } else if (kind == "mesh") {
    shape_out.kind = Kind::kMesh;
    const char* file = shape->Attribute("filename");
    if (!file || !*file) return fail(shape->GetLineNum(), shape_owner + " has no filename");
    g->filename = file;
    if (const char* text = shape->Attribute("scale")) {
      if (!parseTriple(text, &g->scale))
        return fail(shape->GetLineNum(), shape_owner + " scale must be three finite numbers (got " +
                                             inQuotes(text) + ")");
      if (strict && (g->scale.array() == 0).any())
        return fail(shape->GetLineNum(), shape_owner + " scale must not be zero");
    }
  } else {
    return fail(shape->GetLineNum(), where + ": unknown geometry <" + kind +
                                         "> (URDF geometry: box, cylinder, sphere, mesh)");
  }
  return std::nullopt;
}

// The k-th <collision> of a link (k from 0): its shape, name and contact parameters. Every error
// ends with "[collision '<name>']".
std::optional<Error> Reader::readCollision(const XMLElement* e, const std::string& link, int k,
                                           CollisionGeometry* g) const {
  const char* name = e->Attribute("name");
  g->shape.name = name && *name ? std::string(name) : link + "#" + std::to_string(k);
  g->shape.line = e->GetLineNum();
  const std::string owner = "link " + inQuotes(link);
  const std::string tag = " [collision " + inQuotes(g->shape.name) + "]";
  auto tagged = [&](std::optional<Error> err) {
    if (err) err->rule += tag;
    return err;
  };
  if (auto err = readGeometry(e, owner, true, g)) return tagged(err);
  const XMLElement* contact = e->FirstChildElement(kContactElement);
  if (!contact) return std::nullopt;
  if (const XMLElement* second = contact->NextSiblingElement(kContactElement))
    return tagged(fail(second->GetLineNum(),
                       owner + ": <collision> has more than one <" + kContactElement + ">"));
  return tagged(readContact(contact, owner, &g->shape.surface));
}

// <cga_rigid_sim:contact mu="…" restitution="…"/>: either attribute optional, nothing else.
std::optional<Error> Reader::readContact(const XMLElement* e, const std::string& owner,
                                         SurfaceParameters* surface) const {
  const int line = e->GetLineNum();
  const std::string where = owner + ": <" + kContactElement + ">";
  for (const XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
    const std::string name = a->Name();
    double value = 0.0;
    if (name == "mu") {
      if (auto err = readNumberAttr(e, "mu", owner, true, &value)) return err;
      if (!(value >= 0))
        return fail(line, where + " mu must be >= 0 (got " + formatNumber(value, 6) +
                              "): a Coulomb friction coefficient cannot be negative");
      surface->mu = value;
    } else if (name == "restitution") {
      if (auto err = readNumberAttr(e, "restitution", owner, true, &value)) return err;
      if (!(value >= 0 && value <= 1))
        return fail(line, where + " restitution must be in [0, 1] (got " + formatNumber(value, 6) +
                              "): 0 is a perfectly plastic impact, 1 a perfectly elastic one");
      surface->restitution = value;
    } else if (name.compare(0, 6, "xmlns:") != 0) {
      return fail(line, where + ": unknown attribute " + inQuotes(name) +
                            " (allowed: mu, the Coulomb friction coefficient >= 0; "
                            "restitution, in [0, 1])");
    }
  }
  return std::nullopt;
}

// <gazebo reference="…"> with <mu1>/<mu2> (Gazebo's URDF extension: friction of every collision
// of the link). Kept as written; checked once all links are known (applyGazeboFriction).
void Reader::readGazebo(const XMLElement* e) {
  const char* reference = e->Attribute("reference");
  if (!reference) return;  // about the whole model: nothing we read
  GazeboFriction f;
  f.reference = reference;
  f.line = e->GetLineNum();
  for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const bool is_mu1 = std::strcmp(c->Name(), "mu1") == 0;
    if (!is_mu1 && std::strcmp(c->Name(), "mu2") != 0) continue;
    const char* text = c->GetText();
    (is_mu1 ? f.mu1 : f.mu2) = GazeboNumber{text ? text : "", c->GetLineNum()};  // last wins
  }
  if (f.mu1 || f.mu2) gazebo_.push_back(std::move(f));
}

// Gazebo's <self_collide> (true/false, 1/0), of the model (<gazebo> without reference) or of one
// link; the last one written wins, as in Gazebo. Links are checked once all are known.
std::optional<Error> Reader::readSelfCollide(const XMLElement* e) {
  const XMLElement* c = e->FirstChildElement("self_collide");
  if (!c) return std::nullopt;
  const char* raw = c->GetText();
  std::string text = raw ? raw : "";
  text.erase(0, text.find_first_not_of(" \t\n\r"));
  text.erase(text.find_last_not_of(" \t\n\r") + 1);
  bool value = false;
  if (text == "true" || text == "1")
    value = true;
  else if (text != "false" && text != "0")
    return fail(c->GetLineNum(),
                "<self_collide> must be true or false (got " + inQuotes(text) + ")");
  const char* reference = e->Attribute("reference");
  if (!reference) {
    out_.self_collide_model = value;
  } else {
    out_.self_collide_links[reference] = value;
    self_collide_lines_.emplace_back(reference, c->GetLineNum());
  }
  return std::nullopt;
}

// Gazebo's μ for each link's collisions that do not set their own with <cga_rigid_sim:contact>.
// Gazebo has two coefficients (mu1 along fdir1, mu2 across); our friction cone is isotropic:
// with both given we take the smaller (the cone inside Gazebo's friction pyramid, so no contact
// can hold more than Gazebo would let it) and warn when they differ; with one given, that one.
// Several <gazebo> for one link: the last value of each in document order wins.
std::optional<Error> Reader::applyGazeboFriction() {
  std::unordered_map<std::string, GazeboFriction> by_link;
  for (const GazeboFriction& f : gazebo_) {
    if (!out_.links.count(f.reference)) {
      out_.warnings.push_back(source_ + ":" + std::to_string(f.line) +
                              ": <gazebo reference=" + inQuotes(f.reference) +
                              "> gives <mu1>/<mu2>, but " + inQuotes(f.reference) +
                              " is not a link: ignored (friction belongs to a link's "
                              "collisions)");
      continue;
    }
    GazeboFriction& merged = by_link[f.reference];
    merged.reference = f.reference;
    merged.line = f.line;
    for (const auto& [from, to] : {std::pair{&f.mu1, &merged.mu1}, std::pair{&f.mu2, &merged.mu2}})
      if (*from) *to = *from;
  }
  for (const std::string& link : link_names_) {
    const auto it = by_link.find(link);
    if (it == by_link.end()) continue;
    const GazeboFriction& f = it->second;
    std::optional<double> mu[2];
    for (int k = 0; k < 2; ++k) {
      const std::optional<GazeboNumber>& given = k == 0 ? f.mu1 : f.mu2;
      if (!given) continue;
      const std::string where = "link " + inQuotes(link) + ": <gazebo reference=\"" + link +
                                "\"><mu" + std::to_string(k + 1) + ">";
      std::string text = given->text;
      text.erase(text.find_last_not_of(" \t\r\n") + 1);
      double value = 0.0;
      if (!parseUrdfNumber(text.c_str(), &value))
        return fail(given->line,
                    where + " must be a finite number (got " + inQuotes(given->text) + ")");
      if (!(value >= 0))
        return fail(given->line, where + " must be >= 0 (got " + formatNumber(value, 6) +
                                     "): a Coulomb friction coefficient cannot be negative");
      mu[k] = value;
    }
    const double chosen = mu[0] && mu[1] ? std::min(*mu[0], *mu[1]) : mu[0] ? *mu[0] : *mu[1];
    if (mu[0] && mu[1] && *mu[0] != *mu[1])
      out_.warnings.push_back(source_ + ":" + std::to_string(f.line) + ": link " + inQuotes(link) +
                              ": <gazebo> mu1 = " + formatNumber(*mu[0], 6) +
                              " and mu2 = " + formatNumber(*mu[1], 6) +
                              " differ; the friction cone is isotropic: using the smaller, mu = " +
                              formatNumber(chosen, 6));
    for (CollisionGeometry& g : out_.links.at(link).collisions)
      if (!g.shape.surface.mu) g.shape.surface.mu = chosen;
  }
  return std::nullopt;
}

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
