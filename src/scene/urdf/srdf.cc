// applySrdf: an SRDF's collision rules → Scene::self_collision (srdf.h).
#include "cga_rigid_sim/scene/urdf/srdf.h"

#include <tinyxml2.h>

#include <cstring>

#include "cga_rigid_sim/format.h"

namespace cga_rigid_sim {
namespace scene {
namespace {

using tinyxml2::XMLElement;

class SrdfReader {
 public:
  SrdfReader(const Scene& scene, const std::string& source) : scene_(scene), source_(source) {}

  std::optional<Error> read(const std::string& xml, SelfCollisionRules& out) {
    tinyxml2::XMLDocument doc;
    doc.Parse(xml.data(), xml.size());
    if (doc.ErrorID() == tinyxml2::XML_ERROR_EMPTY_DOCUMENT)
      return fail(0, "the SRDF is empty (no XML at all)");
    if (doc.Error()) {
      const char* detail = doc.ErrorStr();
      return fail(doc.ErrorLineNum(),
                  std::string("malformed XML: ") + (detail ? detail : "") + " (not well-formed)");
    }
    const XMLElement* robot = doc.FirstChildElement("robot");
    if (!robot) {
      const XMLElement* first = doc.FirstChildElement();
      return fail(first ? first->GetLineNum() : 1,
                  "no <robot> element at the top level (is this an SRDF file?)");
    }
    out.srdf_source = source_;
    for (const XMLElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const bool disable = std::strcmp(e->Name(), "disable_collisions") == 0;
      const bool enable = std::strcmp(e->Name(), "enable_collisions") == 0;
      if (disable || enable) {
        LinkPair p;
        if (auto err = readPair(e, p)) return err;
        (disable ? out.srdf_disabled : out.srdf_enabled).push_back(std::move(p));
      } else if (std::strcmp(e->Name(), "disable_default_collisions") == 0) {
        std::string link;
        if (auto err = readLink(e, "link", link)) return err;
        out.srdf_disabled_links.push_back(std::move(link));
      }
    }
    return std::nullopt;
  }

 private:
  Error fail(int line, const std::string& what) const {
    return Error{"srdf " + inQuotes(source_) + (line > 0 ? ":" + std::to_string(line) : "") + ": " +
                 what};
  }
  // The link named by attribute `attr` of e: present and a link of the scene.
  std::optional<Error> readLink(const XMLElement* e, const char* attr, std::string& out) const {
    const char* name = e->Attribute(attr);
    const std::string element = std::string("<") + e->Name() + ">";
    if (!name || !*name)
      return fail(e->GetLineNum(),
                  element + " has no " + attr + " attribute (it must name a link)");
    if (scene_.findLink(name) < 0)
      return fail(e->GetLineNum(), element + " " + attr + " " + inQuotes(name) +
                                       ": the URDF has no link of that name (an SRDF written "
                                       "for another robot, or a renamed link?)");
    out = name;
    return std::nullopt;
  }
  std::optional<Error> readPair(const XMLElement* e, LinkPair& p) const {
    if (auto err = readLink(e, "link1", p.link1)) return err;
    if (auto err = readLink(e, "link2", p.link2)) return err;
    if (p.link1 == p.link2)
      return fail(e->GetLineNum(), std::string("<") + e->Name() + "> names link " +
                                       inQuotes(p.link1) + " twice (a pair needs two links)");
    const char* reason = e->Attribute("reason");
    p.reason = reason ? reason : "";
    p.line = e->GetLineNum();
    return std::nullopt;
  }

  const Scene& scene_;
  const std::string& source_;
};

}  // namespace

std::optional<Error> applySrdf(Scene& scene, const std::string& xml, const std::string& source) {
  SelfCollisionRules rules = scene.self_collision;
  rules.srdf_disabled.clear();
  rules.srdf_disabled_links.clear();
  rules.srdf_enabled.clear();
  if (auto err = SrdfReader(scene, source).read(xml, rules)) return err;
  scene.self_collision = std::move(rules);
  return std::nullopt;
}

}  // namespace scene
}  // namespace cga_rigid_sim
